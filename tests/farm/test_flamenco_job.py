"""The Flamenco job type, compiled by Node against a stand-in for Flamenco's `author` API: its
shards come from the add-on's plan (many_worlds.farm.plan), computed in the submitting Blender;
its tasks are then run here in dependency order, and their merged result compared with one run."""
import json
import os
import subprocess
from types import SimpleNamespace

from conftest import QUICKSTART_BLEND, ROOT

JOB_TYPE = os.path.join(ROOT, "addon", "many_worlds", "farm", "flamenco", "many_worlds_sample.js")
STUB = os.path.join(os.path.dirname(os.path.abspath(__file__)), "flamenco_author_stub.js")


def compile_job(settings):
    return subprocess.run(["node", STUB, JOB_TYPE, json.dumps(settings)], capture_output=True, text=True)


def job_type():
    result = subprocess.run(["node", STUB, JOB_TYPE, "--job-type"], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout)


def settings_for(out_dir, first_world=0, world_count=10, chunk_size=4, **overrides):
    """The job's settings as the submitting Blender sends them, shards computed by the plan."""
    from many_worlds.farm import plan
    settings = {"world_count": world_count, "first_world": first_world, "chunk_size": chunk_size,
                "shards": plan.flamenco_shards(first_world, world_count, chunk_size), "output_dir": str(out_dir),
                "cli_script": plan.CLI_SCRIPT, "blendfile": QUICKSTART_BLEND}
    settings.update(overrides)
    return settings


def after_dashes(args):
    """The command line's own arguments, after Blender's."""
    return args[args.index("--") + 1:]


def worker_command(command):
    """What a Flamenco Worker runs for a command, with the Manager's default variables."""
    variables = {"{blender}": "blender", "{blenderArgs}": "-b -y"}
    p = command["parameters"]
    if command["type"] == "blender-render":
        return [variables[p["exe"]], *variables[p["exeArgs"]].split(), *p["argsBefore"], p["blendfile"], *p["args"]]
    assert command["type"] == "exec"
    return [variables.get(p["exe"], p["exe"]), *p["args"]]


def test_the_submitting_blender_computes_the_shards_with_the_add_ons_plan():
    from many_worlds.farm import plan
    (setting,) = [s for s in job_type()["settings"] if s["key"] == "shards"]
    assert setting["visible"] == "hidden" and setting["required"]
    # As Flamenco's Blender add-on evaluates a setting: the expression, given the job's settings
    # (the add-on is loaded there, as it is here).
    settings = SimpleNamespace(first_world=3, world_count=10, chunk_size=4)
    value = eval(setting["eval"], {}, {"settings": settings, "bpy": None, "C": None})
    assert value == plan.flamenco_shards(3, 10, 4)
    assert json.loads(value) == [{"worlds": "3:7", "file": "shard_00000003_00000007.mwb"},
                                 {"worlds": "7:11", "file": "shard_00000007_00000011.mwb"},
                                 {"worlds": "11:13", "file": "shard_00000011_00000013.mwb"}]


def test_job_samples_each_shard_of_the_plan_and_merges_after_every_one(tmp_path):
    from many_worlds.farm import plan
    for first, count, chunk in [(0, 10, 4), (5, 1, 100), (0, 7, 7), (1000, 2500, 300)]:
        result = compile_job(settings_for(tmp_path, first, count, chunk))
        assert result.returncode == 0, result.stderr
        tasks = json.loads(result.stdout)
        samples = [t for t in tasks if t["name"].startswith("sample")]
        # Each task runs the command a Slurm array task runs for its chunk.
        ranges = plan.chunks(first, count, chunk)
        assert [after_dashes(t["commands"][0]["parameters"]["args"]) for t in samples] == [
            after_dashes(plan.sample_command(None, a, b, str(tmp_path))) for a, b in ranges]
        merge = tasks[-1]
        assert merge["name"] == "merge" and sorted(merge["dependencies"]) == sorted(t["name"] for t in samples)
        assert merge["commands"][0]["parameters"]["args"][-len(ranges):] == [
            os.path.join(str(tmp_path), plan.shard_name(a, b)) for a, b in ranges]


def test_paths_are_joined_with_the_separator_of_the_workers_folder(tmp_path):
    tasks = json.loads(compile_job(settings_for("S:\\farm\\run1", chunk_size=5)).stdout)
    assert tasks[0]["commands"][0]["parameters"]["args"][-1] == "S:\\farm\\run1\\shard_00000000_00000005.mwb"
    assert "S:\\farm\\run1\\merged.mwb" in tasks[-1]["commands"][0]["parameters"]["args"]
    tasks = json.loads(compile_job(settings_for("/shared/run1/", chunk_size=5)).stdout)
    assert tasks[0]["commands"][0]["parameters"]["args"][-1] == "/shared/run1/shard_00000000_00000005.mwb"


def test_a_job_without_shards_stops_the_compiler(tmp_path):
    result = compile_job(settings_for(tmp_path, shards=""))
    assert result.returncode != 0 and "shards is empty" in result.stderr


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
