"""Shared fixtures for tests of the native module, run with Debian's python3 (Blender's)."""
import os
import shutil
import subprocess
import sys

import pytest

# Test helpers shared by the Python and the in-Blender suites.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "shared"))

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENES = os.path.join(ROOT, "tests", "scenes")


@pytest.fixture(scope="session")
def native():
    from many_worlds import _native
    return _native


@pytest.fixture(scope="session")
def engine():
    """Path of the mwb-engine executable built next to the module."""
    path = os.environ.get("MWB_ENGINE") or shutil.which("mwb-engine") or os.path.join(ROOT, "build", "native", "mwb-engine")
    assert os.path.exists(path), f"mwb-engine not built at {path}"
    return path


@pytest.fixture
def scene_text():
    def load(name):
        with open(os.path.join(SCENES, name)) as f:
            return f.read()
    return load


def run_engine(engine_path, *args, **kwargs):
    return subprocess.run([engine_path, *args], capture_output=True, text=True, **kwargs)
