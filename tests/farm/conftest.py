"""Farm tests run the add-on's real command line in headless Blender on a bundled example."""
import os
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
QUICKSTART_BLEND = os.path.join(ROOT, "blend_examples", "quickstart", "quickstart.blend")


def run_cli(args, blend_file=None):
    from many_worlds.farm import plan
    command = plan.cli_prefix("blender", blend_file) + list(args)
    result = subprocess.run(command, capture_output=True, text=True)
    assert result.returncode == 0, f"{' '.join(command)}\n{result.stdout[-2000:]}\n{result.stderr[-2000:]}"
    return result


@pytest.fixture(scope="session")
def single_machine_library(tmp_path_factory):
    """Worlds 0..9 of the quick-start example sampled in one run, records sorted by world."""
    folder = tmp_path_factory.mktemp("single")
    run_cli(["sample", "--worlds", "0:10", "--out", str(folder / "all.mwb")], QUICKSTART_BLEND)
    run_cli(["merge", str(folder / "sorted.mwb"), str(folder / "all.mwb")])
    return (folder / "sorted.mwb").read_bytes()
