"""Library files written by the engine process: reading, crash safety under kill -9, following,
merging, and the engine's command-line errors."""
import json
import os
import random
import signal
import subprocess
import time
import zlib

import numpy as np
import pytest

from camera_math import look_at, perspective, screen_of
from conftest import SCENES, run_engine

QUICKSTART = os.path.join(SCENES, "quickstart.json")


def lineage_tuples(info):
    """A WorldInfo's lineage as (branch time s, world, bodies, added, removed) tuples."""
    return [(s.branch_time_s, s.world, list(s.bodies), list(s.added), list(s.removed)) for s in info.lineage]


def sample(engine, out, *extra):
    result = run_engine(engine, "sample", "--scene", QUICKSTART, "--out", str(out), "--seed", "4", *extra)
    assert result.returncode == 0, result.stderr
    return result


def test_engine_writes_a_library_the_module_reads(native, engine, tmp_path):
    out = tmp_path / "q.mwb"
    sample(engine, out, "--worlds", "0:6", "--threads", "2")
    lib = native.Library(str(out))
    assert sorted(lib.world_indices) == list(range(6))
    assert lib.warnings == []
    scene = native.Scene.from_json(lib.header.scene_json)
    w = lib.world_indices[0]
    positions = lib.positions(w)
    assert positions.shape == (len(scene.body_names), lib.frame_count(w), 3)
    location, rotation = lib.pose(w, 2, lib.frame_count(w) - 1)
    np.testing.assert_array_equal(location, positions[2, -1])
    # The decoded motion is the sampled motion within the codec bound.
    direct = native.sample(scene, lib.header.parameters, 4, w, 1, threads=1)[0]
    error = np.linalg.norm(positions - direct.positions, axis=2).max()
    assert 0 < error <= lib.header.position_error_max_m


def test_engine_run_can_be_extended_later_without_recomputing(native, engine, tmp_path):
    out = tmp_path / "grow.mwb"
    sample(engine, out, "--worlds", "0:3")
    result = sample(engine, out, "--worlds", "0:5")
    assert "skipped 3 already stored" in result.stdout
    assert sorted(native.Library(str(out)).world_indices) == list(range(5))


def test_kill_9_at_random_moments_never_loses_finished_worlds(native, engine, tmp_path):
    rng = random.Random(20261122)
    out = tmp_path / "killed.mwb"
    whole = tmp_path / "whole.mwb"
    sample(engine, whole, "--worlds", "0:120", "--threads", "2")
    reference = native.Library(str(whole))
    seen = 0
    interrupted = 0
    for attempt in range(12):
        proc = subprocess.Popen([engine, "sample", "--scene", QUICKSTART, "--out", str(out), "--seed", "4",
                                 "--worlds", "0:120", "--threads", "2"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        # Kill once the file has grown by a random amount (about one to four worlds), so every kill
        # lands mid-run however fast or loaded the machine is.
        before = out.stat().st_size if out.exists() else 0
        grow = rng.randint(1, 12000)
        while proc.poll() is None and (not out.exists() or out.stat().st_size < before + grow):
            time.sleep(0.001)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        if not out.exists():
            continue
        lib = native.Library(str(out))
        # Every stored world is intact and equal to the uninterrupted run's.
        assert len(lib.world_indices) >= seen
        seen = len(lib.world_indices)
        for w in lib.world_indices:
            np.testing.assert_array_equal(lib.positions(w), reference.positions(w))
        assert all("incomplete" in message for message in lib.warnings)
        interrupted += len(lib.world_indices) < 120
    assert interrupted >= 10, "the kills land mid-run"
    # Finishing the interrupted run gives the same worlds as the uninterrupted one.
    sample(engine, out, "--worlds", "0:120")
    final = native.Library(str(out))
    assert sorted(final.world_indices) == list(range(120))
    assert final.warnings == []


def test_ctrl_c_keeps_finished_worlds(native, engine, tmp_path):
    out = tmp_path / "interrupted.mwb"
    proc = subprocess.Popen([engine, "sample", "--scene", QUICKSTART, "--out", str(out), "--worlds", "0:400",
                             "--threads", "2", "--events"], stdout=subprocess.PIPE, text=True)
    for line in proc.stdout:
        event = json.loads(line)
        if event["event"] == "progress" and event["done"] == 3:
            proc.send_signal(signal.SIGINT)
            break
    proc.communicate()
    assert proc.returncode == 130
    lib = native.Library(str(out))
    assert 3 <= len(lib.world_indices) < 400
    assert lib.warnings == []


def test_a_follower_sees_worlds_while_the_engine_writes(native, engine, tmp_path):
    out = tmp_path / "live.mwb"
    proc = subprocess.Popen([engine, "sample", "--scene", QUICKSTART, "--out", str(out), "--worlds", "0:200",
                             "--threads", "1"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    while not out.exists() or out.stat().st_size == 0:
        time.sleep(0.01)
    time.sleep(0.05)
    lib = native.Library(str(out))
    counts = [len(lib.world_indices)]
    while proc.poll() is None:
        lib.poll()
        counts.append(len(lib.world_indices))
        time.sleep(0.02)
    lib.poll()
    counts.append(len(lib.world_indices))
    assert counts[-1] == 200
    # Whatever the timing: the follower ends with every world, and saw them arrive in order.
    assert counts == sorted(counts)
    assert len(set(counts)) >= 2, "the follower saw worlds arrive while the engine wrote"
    assert counts == sorted(counts)
    assert lib.warnings == []


def test_merged_shards_equal_one_run(native, engine, tmp_path):
    sample(engine, tmp_path / "a.mwb", "--worlds", "0:4", "--threads", "2")
    sample(engine, tmp_path / "b.mwb", "--worlds", "4:8", "--threads", "1")
    sample(engine, tmp_path / "whole.mwb", "--worlds", "0:8")
    merged = run_engine(engine, "merge", str(tmp_path / "m.mwb"), str(tmp_path / "b.mwb"), str(tmp_path / "a.mwb"))
    assert merged.returncode == 0, merged.stderr
    native.merge_libraries([str(tmp_path / "whole.mwb")], str(tmp_path / "w.mwb"))
    assert (tmp_path / "m.mwb").read_bytes() == (tmp_path / "w.mwb").read_bytes()
    # A re-run shard is byte-identical.
    sample(engine, tmp_path / "a2.mwb", "--worlds", "0:4", "--threads", "1")
    native.merge_libraries([str(tmp_path / "a.mwb")], str(tmp_path / "a_sorted.mwb"))
    native.merge_libraries([str(tmp_path / "a2.mwb")], str(tmp_path / "a2_sorted.mwb"))
    assert (tmp_path / "a_sorted.mwb").read_bytes() == (tmp_path / "a2_sorted.mwb").read_bytes()


def test_info_reports_worlds_rejections_and_sizes(engine, tmp_path):
    import json
    out = tmp_path / "i.mwb"
    sample(engine, out, "--worlds", "0:3")
    result = run_engine(engine, "info", str(out), "--json")
    assert result.returncode == 0
    info = json.loads(result.stdout)
    assert info["worlds"] == 3 and info["rejected"] == 0 and info["bodies"] == 6
    assert 0 < info["motion_bytes_per_body_frame"] < 28
    assert len(info["scene_hash"]) == 16


@pytest.mark.parametrize("args,phrase", [
    ([], "no command"),
    (["explode"], "unknown command"),
    (["sample", "--scene", QUICKSTART], "needs --scene and --out"),
    (["sample", "--scene", QUICKSTART, "--out", "x.mwb", "--worlds", "5:2"], "empty range"),
    (["sample", "--scene", QUICKSTART, "--out", "x.mwb", "--threads", "two"], "not a non-negative integer"),
    (["sample", "--scene", "/nonexistent/scene.json", "--out", "x.mwb"], "/nonexistent/scene.json"),
    (["info", "/nonexistent.mwb"], "/nonexistent.mwb"),
    (["info", QUICKSTART], "not a Many-Worlds library"),
    (["merge", "out.mwb"], "at least one input"),
])
def test_engine_user_mistakes_are_one_clear_line(engine, tmp_path, args, phrase):
    result = run_engine(engine, *args, cwd=tmp_path)
    assert result.returncode != 0
    assert phrase in result.stderr.splitlines()[0] or phrase in result.stderr
    assert "Traceback" not in result.stderr and "terminate" not in result.stderr


def test_refined_worlds_store_only_what_changed_and_read_back_whole(native, engine, tmp_path):
    out = tmp_path / "refine.mwb"
    sample(engine, out, "--worlds", "0:3")
    scene = native.Scene.from_json(native.Library(str(out)).header.scene_json)
    die = scene.body_names.index("Die")
    result = run_engine(engine, "refine", "--library", str(out), "--world", "1", "--bodies", str(die),
                        "--time", "1.0", "--count", "4", "--threads", "2")
    assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    assert sorted(lib.world_indices) == [0, 1, 2, 3, 4, 5, 6]
    parent_positions = lib.positions(1)
    for child in (3, 4, 5, 6):
        info = lib.world_info(child)
        assert info.parent_world == 1 and info.root_world == 1
        assert info.branch_time_s == 1.0 and lineage_tuples(info) == [(1.0, child, [die], [], [])]
        changed = info.changed_bodies
        assert changed[die]
        positions = lib.positions(child)
        assert positions.shape[0] == len(scene.body_names)
        bound = lib.header.position_error_max_m
        # Before the branch every body is where the parent was (both decoded within the bound).
        branch = 120
        assert np.abs(positions[:, :branch + 1] - parent_positions[:, :branch + 1]).max() <= 2 * bound
        # Untouched bodies are the parent's own stored track.
        for body, moved in enumerate(changed):
            if not moved:
                frames = min(positions.shape[1], parent_positions.shape[1])
                np.testing.assert_array_equal(positions[body, :frames], parent_positions[body, :frames])
    # A grandchild: refining a refined world works through the stored lineage.
    result = run_engine(engine, "refine", "--library", str(out), "--world", "4", "--bodies", str(die),
                        "--time", "2.0", "--count", "1")
    assert result.returncode == 0, result.stderr
    grandchild = native.Library(str(out)).world_info(7)
    assert grandchild.parent_world == 4 and [step.world for step in grandchild.lineage] == [4, 7]


def test_refine_mistakes_are_clear_errors(engine, tmp_path):
    out = tmp_path / "r.mwb"
    sample(engine, out, "--worlds", "0:1")
    for args, phrase in ((["--world", "9", "--bodies", "2", "--time", "1"], "no world 9"),
                         (["--world", "0", "--bodies", "0", "--time", "1"], "not a simulated body"),
                         (["--world", "0", "--bodies", "2", "--time", "99"], "not a frame of the parent")):
        result = run_engine(engine, "refine", "--library", str(out), *args)
        assert result.returncode == 2 and phrase in result.stderr, result.stderr


def scene_with_pebble(tmp_path):
    """quickstart.json exported again after a 10 cm ball was added far from everything."""
    with open(QUICKSTART) as f:
        scene = json.load(f)
    scene["bodies"].append({"name": "Pebble", "type": "ACTIVE", "shape": {"type": "SPHERE", "radius_m": 0.1},
                            "initial": {"location": [4.0, 4.0, 1.0]}})
    path = tmp_path / "with_pebble.json"
    path.write_text(json.dumps(scene))
    return str(path)


def test_bodies_added_to_and_removed_from_worlds(native, engine, tmp_path):
    out = tmp_path / "changes.mwb"
    sample(engine, out, "--worlds", "0:2")
    sampled = native.Library(str(out))
    names = native.Scene.from_json(sampled.header.scene_json).body_names
    chute, die = names.index("Chute"), names.index("Die")
    result = run_engine(engine, "refine", "--library", str(out), "--world", "0", "--add", "Pebble",
                        "--scene", scene_with_pebble(tmp_path), "--count", "2", "--threads", "2")
    assert result.returncode == 0, result.stderr
    result = run_engine(engine, "refine", "--library", str(out), "--world", "1", "--remove", "Chute", "--count", "1")
    assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    assert lib.warnings == []
    assert lib.header.scene_json == sampled.header.scene_json, "the sampled scene stays as it was"
    pebble = len(names)
    assert lib.body_count == pebble + 1
    assert [b["name"] for b in json.loads(lib.scene_json)["bodies"]] == names + ["Pebble"]
    # Worlds sampled before the pebble do not have it: NaN rows, no metrics, never in a box.
    assert lib.present(0) == [True] * pebble + [False]
    assert np.isnan(lib.positions(0)[pebble]).all() and np.isnan(lib.polyline(0)[pebble]).all()
    assert lib.metrics(0)["collision_count"][pebble] == 0
    parent = lib.positions(0)
    bound = lib.header.position_error_max_m
    for child in (2, 3):
        assert lib.present(child) == [True] * (pebble + 1)
        assert lineage_tuples(lib.world_info(child)) == [(0.0, child, [], [pebble], [])]
        positions = lib.positions(child)
        # The pebble falls from where it was added onto the ground; nothing else is touched.
        assert np.abs(positions[pebble, 0] - [4.0, 4.0, 1.0]).max() < 0.1
        assert abs(positions[pebble, -1, 2] - 0.1) < 0.01
        assert lib.world_info(child).changed_bodies == [False] * pebble + [True]
        frames = min(parent.shape[1], positions.shape[1])
        np.testing.assert_array_equal(positions[:pebble, :frames], parent[:pebble, :frames])
    # Without the chute the die drops where it was instead of sliding down the chute.
    removed = 4
    assert not lib.present(removed)[chute] and lib.present(removed)[die]
    assert np.isnan(lib.positions(removed)[chute]).all()
    assert lib.positions(1)[die, -1, 0] > 1.5
    assert lib.positions(removed)[die, -1, 0] < 0.5 and abs(lib.positions(removed)[die, -1, 2] - 0.1) < 2 * bound + 0.01
    # A query box around the chute's place finds the chute's path in world 1, never in world 4.
    index = native.PathIndex(native.body_bounding_radii(native.Scene.from_json(lib.scene_json)))
    assert index.add_library(lib) == 5
    view, projection, size = look_at([0, -8, 3], [0, 0, 0]), perspective(0.9, 1.6, 0.1, 100), (1600, 1000)
    x, y = screen_of(view, projection, size, [0, 0, 0])
    box = native.QueryBox(view, projection, size, (x - 10, y - 10, x + 10, y + 10), bodies=[chute])
    assert sorted(int(w) for w in index.query([box]).matching) == [0, 1, 2, 3]
    far = native.QueryBox(view, projection, size, (x - 10, y - 10, x + 10, y + 10), bodies=[pebble])
    assert list(index.query([far]).matching) == [], "no world has the pebble there"
    # Adding the pebble again to another world reuses its index; a changed pebble is refused.
    result = run_engine(engine, "refine", "--library", str(out), "--world", "1", "--add", "Pebble",
                        "--scene", scene_with_pebble(tmp_path), "--count", "1")
    assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    assert lib.body_count == pebble + 1 and lib.present(5)[pebble]


def test_adding_and_removing_mistakes_are_clear_errors(engine, tmp_path):
    out = tmp_path / "m.mwb"
    sample(engine, out, "--worlds", "0:1")
    pebble_scene = scene_with_pebble(tmp_path)
    run_engine(engine, "refine", "--library", str(out), "--world", "0", "--add", "Pebble", "--scene", pebble_scene,
               "--count", "1")
    for args, phrase in ((["--world", "0", "--add", "Pebble"], "need --scene"),
                         (["--world", "0", "--add", "Nothing", "--scene", pebble_scene], "'Nothing': not in the exported scene"),
                         (["--world", "0", "--add", "Die", "--scene", pebble_scene], "'Die' is already in the world"),
                         (["--world", "0", "--remove", "Nothing"], "'Nothing' is not in the world"),
                         (["--world", "0", "--remove", "Pebble"], "'Pebble' is not in the world"),
                         (["--world", "0", "--remove", "Die", "--time", "1"], "act from t = 0"),
                         (["--world", "1", "--update", "Pebble", "--scene", pebble_scene], "'Pebble' is unchanged"),
                         (["--world", "0", "--update", "Pebble", "--scene", pebble_scene], "add it instead")):
        result = run_engine(engine, "refine", "--library", str(out), *args)
        assert result.returncode == 2 and phrase in result.stderr, (args, result.stderr)


def test_an_object_moved_after_sampling_is_updated_in_new_worlds(native, engine, tmp_path):
    out = tmp_path / "update.mwb"
    sample(engine, out, "--worlds", "0:2")
    with open(QUICKSTART) as f:
        scene = json.load(f)
    can = [b["name"] for b in scene["bodies"]].index("Can")
    scene["bodies"][can]["initial"]["location"] = [4.0, -4.0, 0.5]
    moved = tmp_path / "moved.json"
    moved.write_text(json.dumps(scene))
    result = run_engine(engine, "refine", "--library", str(out), "--world", "1", "--update", "Can",
                        "--scene", str(moved), "--count", "2")
    assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    bodies = json.loads(lib.scene_json)["bodies"]
    assert [(b["name"], b.get("object")) for b in bodies[len(scene["bodies"]):]] == [("Can#2", "Can")]
    new_can = len(scene["bodies"])
    for child in (2, 3):
        present = lib.present(child)
        assert not present[can] and present[new_can]
        assert np.abs(lib.positions(child)[new_can, 0] - [4.0, -4.0, 0.5]).max() < 0.05, "the can starts where it was moved"
    assert lib.present(1)[can] and not lib.present(1)[new_can], "the parent keeps its can"
    # Updating the updated can in a child to the same place again is refused; moving it back reuses the old body.
    result = run_engine(engine, "refine", "--library", str(out), "--world", "2", "--update", "Can",
                        "--scene", str(moved), "--count", "1")
    assert result.returncode == 2 and "'Can' is unchanged" in result.stderr, result.stderr
    result = run_engine(engine, "refine", "--library", str(out), "--world", "2", "--update", "Can",
                        "--scene", QUICKSTART, "--count", "1")
    assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    assert lib.body_count == new_can + 1 and lib.present(4)[can] and not lib.present(4)[new_can]


def test_refinement_in_this_process_equals_the_engines(native, engine, tmp_path):
    """The module and the engine refine through the same core function: the same request on two
    copies of a library appends the same bytes, and the next world index comes from the library."""
    by_engine, in_process = tmp_path / "engine.mwb", tmp_path / "module.mwb"
    # One thread: worlds are stored as they finish, so only then is the file order fixed too.
    sample(engine, by_engine, "--worlds", "0:3", "--threads", "1")
    sample(engine, in_process, "--worlds", "0:3", "--threads", "1")
    die = native.Scene.from_json(native.Library(str(by_engine)).header.scene_json).body_names.index("Die")
    assert native.Library(str(in_process)).next_world_index == 3
    result = run_engine(engine, "refine", "--library", str(by_engine), "--world", "1", "--bodies", str(die),
                        "--time", "1.0", "--count", "3", "--threads", "1")
    assert result.returncode == 0, result.stderr
    refined = native.refine_stored_world(str(in_process), 1, [die], 1.0, 3, threads=1)
    children, stored, rejected = refined.children, refined.stored, refined.rejected
    assert children == [3, 4, 5] and (stored, rejected) == (3, 0)
    assert by_engine.read_bytes() == in_process.read_bytes()
    assert native.Library(str(in_process)).next_world_index == 6
    with pytest.raises(native.RefineError, match="no world 42"):
        native.refine_stored_world(str(in_process), 42, [die], 1.0, 1)
    assert by_engine.read_bytes() == in_process.read_bytes(), "a refused request writes nothing"


def test_worlds_that_crash_or_hang_are_rejected_and_the_run_goes_on(native, engine, tmp_path):
    """Chosen worlds abort, segfault or hang inside the simulation (a test-only switch of the
    engine's workers): each is stored as a rejection naming its fault, and every other world is
    stored exactly as a run without faults stores it."""
    clean, faulty = tmp_path / "clean.mwb", tmp_path / "faulty.mwb"
    sample(engine, clean, "--worlds", "0:24", "--in-process")
    env = dict(os.environ, MWB_ENGINE_TEST_FAULTS="3:abort,9:segv,14:hang")
    result = subprocess.run([engine, "sample", "--scene", QUICKSTART, "--out", str(faulty), "--seed", "4",
                             "--worlds", "0:24", "--world-time-limit", "3"], capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stderr
    lib, reference = native.Library(str(faulty)), native.Library(str(clean))
    reasons = {world: reason for world, _, reason in lib.rejections}
    assert sorted(reasons) == [3, 9, 14]
    assert "Aborted" in reasons[3] and "Segmentation fault" in reasons[9] and "did not finish within 3 s" in reasons[14]
    assert sorted(lib.world_indices) == sorted(set(range(24)) - {3, 9, 14})
    for w in lib.world_indices:
        np.testing.assert_array_equal(lib.positions(w), reference.positions(w))
        np.testing.assert_array_equal(lib.orientations(w), reference.orientations(w))
    # Sampling the range again with the faults gone fills nothing in: a rejected world is a result.
    rerun = run_engine(engine, "sample", "--scene", QUICKSTART, "--out", str(faulty), "--seed", "4", "--worlds", "0:24")
    assert "skipped 24 already stored" in rerun.stdout


FAULT_WORDS = {"abort": "Aborted", "segv": "Segmentation fault", "hang": "did not finish within 3 s"}


def assert_stored_alike(library, reference, worlds):
    """Each of `worlds` has the same motion and lineage in both libraries."""
    for w in worlds:
        np.testing.assert_array_equal(library.positions(w), reference.positions(w))
        np.testing.assert_array_equal(library.orientations(w), reference.orientations(w))
        assert lineage_tuples(library.world_info(w)) == lineage_tuples(reference.world_info(w)), w


def test_refined_children_that_crash_or_hang_are_rejected_and_their_siblings_stored_as_without(native, engine,
                                                                                              tmp_path):
    """A refinement runs its children in the supervisor's worker processes: children that abort,
    segfault or hang are stored as rejections naming the fault, and every other child is stored
    exactly as a refinement in one process stores it."""
    clean, faulty = tmp_path / "clean.mwb", tmp_path / "faulty.mwb"
    for out in (clean, faulty):
        sample(engine, out, "--worlds", "0:4")
    die = native.Scene.from_json(native.Library(str(clean)).header.scene_json).body_names.index("Die")
    refine = ["refine", "--world", "2", "--bodies", str(die), "--time", "0.8", "--count", "8", "--threads", "2"]
    result = run_engine(engine, *refine[:1], "--library", str(clean), *refine[1:], "--in-process")
    assert result.returncode == 0, result.stderr
    faults = {5: "abort", 7: "segv", 10: "hang"}
    env = dict(os.environ, MWB_ENGINE_TEST_FAULTS=",".join(f"{w}:{f}" for w, f in faults.items()))
    result = subprocess.run([engine, *refine[:1], "--library", str(faulty), *refine[1:], "--world-time-limit", "3"],
                            capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stderr
    assert "5 stored, 3 rejected" in result.stdout, result.stdout
    library, reference = native.Library(str(faulty)), native.Library(str(clean))
    reasons = {world: reason for world, _, reason in library.rejections}
    assert sorted(reasons) == sorted(faults)
    for world, fault in faults.items():
        assert FAULT_WORDS[fault] in reasons[world], reasons[world]
    assert sorted(library.world_indices) == sorted(set(range(12)) - set(faults))
    assert_stored_alike(library, reference, library.world_indices)


def test_a_seek_whose_children_crash_or_hang_goes_on_and_stores_every_other_world_as_without(native, engine,
                                                                                            tmp_path):
    """A goal search runs every world it makes in the supervisor's workers. Refined children that
    abort, segfault or hang (ones the search would not have refined again) are stored as
    rejections naming the fault; the search goes on and every other world it makes is the world
    a search in one process makes, with the same lineage."""
    base = tmp_path / "base.mwb"
    sample(engine, base, "--worlds", "0:8")
    goal = tmp_path / "upright.goal.json"
    upright = {"within_deg": 8, "time_window": [3.0, 4.0]}
    goal.write_text(json.dumps({"boxes": [], "orientations": [dict(upright, objects=["Die"]),
                                                             dict(upright, objects=["Can"])]}))
    seek = ["--goal", str(goal), "--budget-worlds", "120", "--seed", "3", "--json"]
    clean, faulty = tmp_path / "clean.mwb", tmp_path / "faulty.mwb"
    for out in (clean, faulty):
        out.write_bytes(base.read_bytes())
    result = run_engine(engine, "seek", "--library", str(clean), *seek, "--threads", "2", "--in-process")
    assert result.returncode == 0, result.stderr
    reference = native.Library(str(clean))
    parents = {reference.world_info(w).parent_world for w in reference.world_indices}
    leaves = sorted(w for w in reference.world_indices if w >= 8 and w not in parents)
    assert len(leaves) > 30, "the search refined its worlds"
    faults = dict(zip((leaves[2], leaves[len(leaves) // 2], leaves[-3]), ("abort", "segv", "hang")))
    env = dict(os.environ, MWB_ENGINE_TEST_FAULTS=",".join(f"{w}:{f}" for w, f in faults.items()))
    result = subprocess.run([engine, "seek", "--library", str(faulty), *seek, "--threads", "2", "--world-time-limit", "3"],
                            capture_output=True, text=True, env=env)
    assert result.returncode == 0, result.stderr
    library = native.Library(str(faulty))
    reasons = {world: reason for world, _, reason in library.rejections}
    assert sorted(reasons) == sorted(faults)
    for world, fault in faults.items():
        assert FAULT_WORDS[fault] in reasons[world], reasons[world]
    assert sorted(library.world_indices) == sorted(set(reference.world_indices) - set(faults))
    assert_stored_alike(library, reference, library.world_indices)
    # One worker makes the same worlds as two.
    one = tmp_path / "one.mwb"
    one.write_bytes(base.read_bytes())
    assert run_engine(engine, "seek", "--library", str(one), *seek, "--threads", "1").returncode == 0
    alone = native.Library(str(one))
    assert sorted(alone.world_indices) == sorted(reference.world_indices)
    assert_stored_alike(alone, reference, alone.world_indices)


def test_a_library_whose_worlds_do_not_reproduce_is_refused_by_refine_and_seek_writing_nothing(native, engine,
                                                                                              tmp_path):
    """A header that says another seed and another build than the worlds were made with stands for
    a library of another engine build: the supervised workers find that the world does not come
    out as stored, and refine and seek refuse it in one line naming the build, appending nothing."""
    out = tmp_path / "foreign.mwb"
    sample(engine, out, "--worlds", "0:4")
    data = out.read_bytes()
    size = int.from_bytes(data[12:16], "little")
    header = json.loads(data[16:16 + size])
    header["base_seed"], header["engine"] = 5, "many-worlds 0.0.9; another build"
    text = json.dumps(header).encode()
    out.write_bytes(data[:12] + len(text).to_bytes(4, "little") + text +
                    zlib.crc32(text).to_bytes(4, "little") + data[16 + size + 4:])
    before = out.read_bytes()
    die = native.Scene.from_json(native.Library(str(out)).header.scene_json).body_names.index("Die")
    result = run_engine(engine, "refine", "--library", str(out), "--world", "1", "--bodies", str(die), "--time",
                        "1.0", "--count", "4", "--threads", "2")
    assert result.returncode == 2, result.stderr
    assert "world 1 does not come out as stored" in result.stderr and "another build" in result.stderr, result.stderr
    assert out.read_bytes() == before
    goal = tmp_path / "g.json"
    goal.write_text(json.dumps({"boxes": [], "orientations": [{"objects": ["Die"], "within_deg": 1}]}))
    result = run_engine(engine, "seek", "--library", str(out), "--goal", str(goal), "--budget-worlds", "16")
    assert result.returncode == 2 and "does not come out as stored" in result.stderr, result.stderr
    assert out.read_bytes() == before


def test_worlds_that_start_alike_share_their_prefix_and_store_the_same_bytes(native, engine, tmp_path):
    # The quick start with nothing varied and its toys raised 3 m: every world falls alike for
    # 0.7 s, and later worlds start from the first one's checkpoint at 0.5 s.
    with open(QUICKSTART) as f:
        scene = json.load(f)
    for body in scene["bodies"]:
        body.pop("variation", None)
        if body["type"] == "ACTIVE":
            body["initial"]["location"][2] += 3.0
    alike = tmp_path / "alike.json"
    alike.write_text(json.dumps(scene))
    stored = {}
    for mode, extra in (("workers", []), ("in-process", ["--in-process"]), ("unshared", ["--no-shared-prefix"])):
        out = tmp_path / f"{mode}.mwb"
        result = run_engine(engine, "sample", "--scene", str(alike), "--out", str(out), "--worlds", "0:5",
                            "--threads", "1", *extra)
        assert result.returncode == 0, result.stderr
        stored[mode] = out.read_bytes()
    assert stored["workers"] == stored["unshared"]
    assert stored["in-process"] == stored["unshared"]
    library = native.Library(str(tmp_path / "workers.mwb"))
    ends = {tuple(np.round(library.polyline(w)[:, -1].ravel(), 6)) for w in range(5)}
    assert len(ends) == 5, "the perturbed impacts still end every world elsewhere"


def test_poses_between_recorded_frames_are_what_bake_and_preview_show(native, engine, tmp_path):
    # The module decodes and interpolates a world's tracks itself (sim/PoseInterpolation.h):
    # at recorded frames the poses are the decoded ones, between them on the way from one to the
    # next, past the end held, and the quaternions never flip sign from one frame to the next.
    out = tmp_path / "poses.mwb"
    assert run_engine(engine, "sample", "--scene", QUICKSTART, "--out", str(out), "--worlds", "0:2").returncode == 0
    library = native.Library(str(out))
    world = int(library.world_indices[1])
    positions, orientations = library.positions(world), library.orientations(world)
    frames = positions.shape[1]
    loc, rot = library.poses(world, [0.0, 10.0, frames - 1.0, frames + 50.0])
    assert loc.shape == (positions.shape[0], 4, 3) and rot.shape == (positions.shape[0], 4, 4)
    np.testing.assert_array_equal(loc[:, :3], positions[:, [0, 10, frames - 1]])
    np.testing.assert_array_equal(loc[:, 3], positions[:, frames - 1])
    # At recorded frames, the decoded rotations (a quaternion or its negative: the same rotation).
    dots = np.sum(rot[:, :3] * orientations[:, [0, 10, frames - 1]], axis=-1)
    np.testing.assert_allclose(np.abs(dots), 1, atol=1e-12)
    half, _ = library.poses(world, [10.5])
    np.testing.assert_allclose(half[:, 0], (positions[:, 10] + positions[:, 11]) / 2, atol=1e-12)
    # Chosen bodies, in the order asked; a body outside the scene is refused.
    picked, _ = library.poses(world, [10.0], bodies=[2, 0])
    np.testing.assert_array_equal(picked[:, 0], positions[[2, 0], 10])
    with pytest.raises(IndexError, match="not in the library's scene"):
        library.poses(world, [1.0], bodies=[positions.shape[0]])
    with pytest.raises(ValueError, match="finite"):
        library.poses(world, [float("nan")])
    _, every = library.poses(world, np.arange(frames, dtype=float).tolist())
    assert (np.sum(every[:, 1:] * every[:, :-1], axis=-1) > 0).all()
