"""Sampling, refinement and goal search on a scene as an animator builds it (every active body at
Blender's default Convex Hull shape, with float coordinates: cubes, UV spheres, a cylinder, lathed
bottles and a Cell Fracture wall, over a passive MESH plane), in the default supervised worker
processes: every world is stored, none is rejected, nothing ODE prints reaches a record, and the
library is the same file byte for byte as one made in a single process."""
import json
import os
import shutil
import subprocess

import pytest

from conftest import SCENES, run_engine

DEFAULTS = os.path.join(SCENES, "blender_defaults.json")
ODE_TEXT = ("WARNING", "counterclockwise", "does not contain the origin")


def body_index(name):
    with open(DEFAULTS) as f:
        return [b["name"] for b in json.load(f)["bodies"]].index(name)


def sample(engine, out, *extra, env=None):
    result = subprocess.run([engine, "sample", "--scene", DEFAULTS, "--out", str(out), "--seed", "2", *extra],
                            capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stderr
    return result


def test_a_sample_is_the_same_file_on_one_or_two_threads_whichever_worker_finishes_first(engine, tmp_path):
    """World 1 finishes half a second late and worlds 4 and 9 print as ODE does, in the middle of
    the run, on standard output and standard error: nothing is rejected, and two supervised runs
    write the file a single-threaded run in one process writes."""
    env = dict(os.environ, MWB_ENGINE_TEST_FAULTS="1:slow,4:print,9:print")
    files = []
    for k, extra in enumerate((["--threads", "2"], ["--threads", "2"], ["--threads", "1", "--in-process"],
                               ["--threads", "2", "--in-process"])):
        out = tmp_path / f"run{k}.mwb"
        result = sample(engine, out, "--worlds", "0:12", *extra, env=env)
        assert "rejected 0" in result.stdout, result.stdout
        files.append(out.read_bytes())
    assert files[0] == files[2], "supervised on 2 threads, in one process on 1"
    assert files[1] == files[0], "a re-run"
    assert files[3] == files[0], "in one process on 2 threads"


def sample_with_faults(engine, out, worlds, faults):
    """Sample worlds 0..worlds-1 in 2 workers with the test-only faults given, with --events.
    Returns (the events, what the engine printed on standard error)."""
    env = dict(os.environ, MWB_ENGINE_TEST_FAULTS=faults)
    result = subprocess.run([engine, "sample", "--scene", DEFAULTS, "--out", str(out), "--worlds", f"0:{worlds}",
                             "--threads", "2", "--events"], capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stderr
    return [json.loads(line) for line in result.stdout.splitlines()], result.stderr


def test_text_a_worker_prints_goes_to_the_log_and_every_world_is_stored(native, engine, tmp_path):
    out = tmp_path / "printed.mwb"
    events, log = sample_with_faults(engine, out, 6, "2:print,3:print")
    assert sum(e["event"] == "world" and e["stored"] for e in events) == 6
    assert "counterclockwise" in log and "standard error" in log
    assert sorted(native.Library(str(out)).world_indices) == list(range(6))


@pytest.fixture(scope="module")
def sampled(engine, tmp_path_factory):
    out = tmp_path_factory.mktemp("defaults") / "sampled.mwb"
    sample(engine, out, "--worlds", "0:8", "--threads", "2")
    return out


def copy_of(library, tmp_path, name):
    path = tmp_path / name
    shutil.copyfile(library, path)
    return path


def test_refining_hull_bodies_in_workers_stores_every_child_as_one_process_does(engine, sampled, tmp_path):
    """The UV sphere and a lathed bottle, refined at 0.8 s: their ghosts are grown hulls that ODE
    used to refuse with prints into the workers' records, which stalled each child until its time
    limit. Every child is stored, none rejected, with no ODE text anywhere."""
    bodies = f"{body_index('Sphere')},{body_index('Bottle.000')}"
    refine = ["--world", "3", "--bodies", bodies, "--time", "0.8", "--count", "8", "--threads", "2"]
    supervised, alone = copy_of(sampled, tmp_path, "supervised.mwb"), copy_of(sampled, tmp_path, "alone.mwb")
    result = run_engine(engine, "refine", "--library", str(supervised), *refine, "--world-time-limit", "20")
    assert result.returncode == 0, result.stderr
    assert "8 stored, 0 rejected" in result.stdout, result.stdout
    assert not any(text in result.stdout + result.stderr for text in ODE_TEXT), result.stderr
    reference = run_engine(engine, "refine", "--library", str(alone), *refine, "--in-process")
    assert reference.returncode == 0, reference.stderr
    assert not any(text in reference.stdout + reference.stderr for text in ODE_TEXT), reference.stderr
    assert supervised.read_bytes() == alone.read_bytes()


def test_a_pose_seek_on_hull_bodies_makes_the_same_worlds_in_workers_in_process_and_on_one_thread(native, engine, sampled, tmp_path):
    goal = tmp_path / "standing.goal.json"
    goal.write_text(json.dumps({"boxes": [], "orientations": [
        {"objects": ["Bottle.000", "Bottle.002"], "within_deg": 10, "time_window": [2.0, 3.0]}]}))
    seek = ["--goal", str(goal), "--budget-worlds", "48", "--seed", "1", "--threads", "2", "--json"]
    supervised, alone = copy_of(sampled, tmp_path, "supervised.mwb"), copy_of(sampled, tmp_path, "alone.mwb")
    result = run_engine(engine, "seek", "--library", str(supervised), *seek, "--world-time-limit", "20")
    assert result.returncode == 0, result.stderr
    assert not any(text in result.stdout + result.stderr for text in ODE_TEXT), result.stderr
    reference = run_engine(engine, "seek", "--library", str(alone), *seek, "--in-process")
    assert reference.returncode == 0, reference.stderr
    library = native.Library(str(supervised))
    assert library.rejections == []
    assert len(library.world_indices) >= 8 + 40, "the search made its worlds"
    assert supervised.read_bytes() == alone.read_bytes()
    # A pose goal's search is the same on one thread.
    one = copy_of(sampled, tmp_path, "one.mwb")
    single = [*seek[:seek.index("--threads")], "--threads", "1", "--json"]
    assert run_engine(engine, "seek", "--library", str(one), *single).returncode == 0
    assert one.read_bytes() == alone.read_bytes()


def run_without_proc(command):
    """`command` in a mount namespace whose /proc is empty, as in a chroot without /proc."""
    if shutil.which("unshare") is None or os.geteuid() != 0:
        pytest.skip("needs root and unshare to hide /proc")
    probe = subprocess.run(["unshare", "--mount", "--fork", "bash", "-c", "mount -t tmpfs none /proc"],
                           capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"this machine cannot hide /proc: {probe.stderr.strip()}")
    return subprocess.run(["unshare", "--mount", "--fork", "bash", "-c", "mount -t tmpfs none /proc && " + command],
                          capture_output=True, text=True)


def test_without_proc_the_engine_finds_itself_on_path_or_by_its_path(native, engine, tmp_path):
    by_path, by_name = tmp_path / "by_path.mwb", tmp_path / "by_name.mwb"
    directory = os.path.dirname(os.path.abspath(engine))
    common = f"sample --scene {DEFAULTS} --worlds 0:4 --threads 2"
    result = run_without_proc(f"{os.path.abspath(engine)} {common} --out {by_path} && "
                              f"PATH={directory}:$PATH {os.path.basename(engine)} {common} --out {by_name}")
    assert result.returncode == 0, result.stderr
    assert "in this process" not in result.stderr, "workers were started"
    assert by_path.read_bytes() == by_name.read_bytes()
    assert sorted(native.Library(str(by_path)).world_indices) == list(range(4))


def test_an_engine_that_cannot_find_itself_samples_in_process_with_one_warning(native, engine, tmp_path):
    out = tmp_path / "alone.mwb"
    result = run_without_proc(f"exec -a nowhere-engine {os.path.abspath(engine)} sample --scene {DEFAULTS} "
                              f"--worlds 0:4 --threads 2 --out {out} --events")
    if "exec: -a" in result.stderr or "illegal option" in result.stderr:
        pytest.skip("this shell cannot set argv[0]")
    assert result.returncode == 0, result.stderr
    warnings = [json.loads(line) for line in result.stdout.splitlines() if '"warning"' in line]
    assert [w["code"] for w in warnings] == ["in_process"]
    assert "nowhere-engine" in warnings[0]["message"]
    assert sorted(native.Library(str(out)).world_indices) == list(range(4))


def test_a_message_from_ode_in_a_worker_becomes_one_warning_naming_the_worlds(native, engine, tmp_path):
    """Worlds 3 and 7 get quickstep's "LCP internal error" through ODE's own message function (a
    test-only switch): the run warns once, with the count of worlds and the first, and stores
    every world."""
    out = tmp_path / "messages.mwb"
    events, _ = sample_with_faults(engine, out, 10, "3:odemessage,7:odemessage")
    warnings = [e for e in events if e["event"] == "warning"]
    assert [w["code"] for w in warnings] == ["ode_message"], warnings
    assert warnings[0]["message"].startswith('ODE said "LCP internal error, s <= 0 (s=-1.5000e-05)" in 2 worlds '
                                             '(first world 3 at 0.5 s)'), warnings[0]["message"]
    assert sorted(native.Library(str(out)).world_indices) == list(range(10))
