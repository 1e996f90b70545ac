"""The Flamenco job type, compiled by Node against a stand-in for Flamenco's `author` API; its
tasks are then run here in dependency order, and their merged result compared with one run."""
import json
import os
import subprocess

import pytest

from conftest import QUICKSTART_BLEND, ROOT

JOB_TYPE = os.path.join(ROOT, "addon", "many_worlds", "farm", "flamenco", "many_worlds_sample.js")
STUB = os.path.join(os.path.dirname(os.path.abspath(__file__)), "flamenco_author_stub.js")


def compile_job(settings):
    return subprocess.run(["node", STUB, JOB_TYPE, json.dumps(settings)], capture_output=True, text=True)


def settings_for(out_dir, **overrides):
    from many_worlds.farm import plan
    settings = {"world_count": 10, "chunk_size": 4, "output_dir": str(out_dir), "cli_script": plan.CLI_SCRIPT,
                "blendfile": QUICKSTART_BLEND}
    settings.update(overrides)
    return settings


def worker_command(command):
    """What a Flamenco Worker runs for a command, with the Manager's default variables."""
    variables = {"{blender}": "blender", "{blenderArgs}": "-b -y"}
    p = command["parameters"]
    if command["type"] == "blender-render":
        return [variables[p["exe"]], *variables[p["exeArgs"]].split(), *p["argsBefore"], p["blendfile"], *p["args"]]
    assert command["type"] == "exec"
    return [variables.get(p["exe"], p["exe"]), *p["args"]]


def test_job_splits_the_range_and_merges_after_every_chunk(tmp_path):
    result = compile_job(settings_for(tmp_path))
    assert result.returncode == 0, result.stderr
    tasks = json.loads(result.stdout)
    samples = [t for t in tasks if t["name"].startswith("sample")]
    assert [t["commands"][0]["parameters"]["args"][-3] for t in samples] == ["0:4", "4:8", "8:10"]
    merge = tasks[-1]
    assert merge["name"] == "merge" and sorted(merge["dependencies"]) == sorted(t["name"] for t in samples)


def test_bad_settings_stop_the_compiler(tmp_path):
    result = compile_job(settings_for(tmp_path, chunk_size=0))
    assert result.returncode != 0 and "chunk_size" in result.stderr


def test_compiled_tasks_run_locally_reproduce_a_single_machine_run(tmp_path, single_machine_library):
    tasks = json.loads(compile_job(settings_for(tmp_path)).stdout)
    done = set()
    while len(done) < len(tasks):
        ready = [t for t in tasks if t["name"] not in done and set(t["dependencies"]) <= done]
        assert ready, "the task graph has a cycle"
        for task in ready:
            for command in task["commands"]:
                run = subprocess.run(worker_command(command), capture_output=True, text=True)
                assert run.returncode == 0, run.stderr[-2000:]
            done.add(task["name"])
    assert (tmp_path / "merged.mwb").read_bytes() == single_machine_library
