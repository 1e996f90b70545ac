"""Box queries and rankings through the module, on worlds the engine sampled."""
import json
import math
import os
import subprocess
import threading
import time

import numpy as np
import pytest

from conftest import SCENES, run_engine
from camera_math import look_at, perspective, screen_of


@pytest.fixture(scope="module")
def sampled(native, engine, tmp_path_factory):
    out = tmp_path_factory.mktemp("query") / "q.mwb"
    result = run_engine(engine, "sample", "--scene", os.path.join(SCENES, "quickstart.json"), "--out", str(out),
                        "--seed", "8", "--worlds", "0:40", "--threads", "2")
    assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    scene = native.Scene.from_json(lib.header.scene_json)
    index = native.PathIndex(native.body_bounding_radii(scene))
    assert index.add_library(lib) == 40
    assert index.add_library(lib) == 0, "indexing again adds nothing"
    return lib, scene, index


def test_box_around_where_a_path_ends_matches_exactly_the_worlds_ending_there(native, sampled):
    lib, scene, index = sampled
    marble = scene.body_names.index("Marble")
    view, projection, size = look_at([3, -8, 6], [3, 0, 0]), perspective(0.9, 1.6, 0.1, 100), (1600, 1000)
    ends = {w: lib.positions(w)[marble, -1] for w in lib.world_indices}
    # A small box around one world's final marble position.
    some_world = sorted(ends)[7]
    x, y = screen_of(view, projection, size, ends[some_world])
    box = native.QueryBox(view, projection, size, (x - 15, y - 15, x + 15, y + 15), bodies=[marble])
    result = index.query([box])
    assert some_world in result.matching
    # Every match really has a marble path point (decoded, full rate) near the box on screen.
    for w in result.matching:
        path = lib.positions(int(w))[marble]
        on_screen = np.array([screen_of(view, projection, size, p) for p in path[::4]])
        assert np.any((np.abs(on_screen[:, 0] - x) < 25) & (np.abs(on_screen[:, 1] - y) < 25))
    negative = native.QueryBox(view, projection, size, (x - 15, y - 15, x + 15, y + 15), negative=True, bodies=[marble])
    both = index.query([box, negative])
    assert len(both.matching) == 0
    flipped = index.query([negative])
    assert set(flipped.matching) == set(lib.world_indices) - set(result.matching)
    assert list(result.boxes_satisfied).count(1) == len(result.matching)


def test_tree_and_brute_force_agree_on_sampled_worlds(native, sampled):
    lib, scene, index = sampled
    view, projection, size = look_at([0, -10, 5], [0, 0, 0.5]), perspective(0.9, 1.6, 0.1, 100), (1600, 1000)
    rng = np.random.default_rng(3)
    for _ in range(60):
        x0, y0 = rng.uniform(0, 1500), rng.uniform(0, 900)
        bodies = sorted(rng.choice(len(scene.body_names), size=2, replace=False).tolist())
        box = native.QueryBox(view, projection, size, (x0, y0, x0 + rng.uniform(5, 300), y0 + rng.uniform(5, 300)),
                              negative=bool(rng.integers(2)), bodies=bodies, swept=bool(rng.integers(2)),
                              time_window=None if rng.integers(2) else (0.5, 2.0))
        fast, slow = index.query([box]), index.query([box], brute_force=True)
        np.testing.assert_array_equal(fast.matching, slow.matching)


def test_ranking_by_stored_metrics(native, sampled):
    lib, scene, index = sampled
    die = scene.body_names.index("Die")
    ranking = index.rank("angular_travel_rad", [die], descending=True)
    ids, values = ranking.world_indices, ranking.values
    assert len(ids) == 40 and np.all(np.diff(values) <= 0)
    assert values[0] == pytest.approx(lib.metrics(int(ids[0]))["angular_travel_rad"][die])
    top_three = ids[:3].tolist()
    ranking = index.rank("collision_count", [die, die + 1], combine="max", only=top_three)
    ids, values = ranking.world_indices, ranking.values
    assert sorted(ids.tolist()) == sorted(top_three)
    expected = [max(lib.metrics(int(w))["collision_count"][die:die + 2]) for w in ids]
    np.testing.assert_array_equal(values, expected)
    upright = index.rank("orientation_to_goal_rad", [die], goals=[(1, 0, 0, 0)]).values
    assert np.all((upright >= 0) & (upright <= math.pi + 1e-9))


def test_query_inputs_are_checked(native, sampled):
    _, _, index = sampled
    view, projection = np.identity(4), perspective(1, 1, 0.1, 10)
    with pytest.raises(ValueError, match="view must be a"):
        native.QueryBox(np.identity(3), projection, (100, 100), (0, 0, 10, 10), bodies=[0])
    with pytest.raises(ValueError, match="empty"):
        native.QueryBox(view, projection, (100, 100), (5, 5, 5, 50), bodies=[0])
    with pytest.raises(ValueError, match="at least one body"):
        native.QueryBox(view, projection, (100, 100), (0, 0, 10, 10), bodies=[])
    with pytest.raises(ValueError, match="time_window"):
        native.QueryBox(view, projection, (100, 100), (0, 0, 10, 10), bodies=[0], time_window=(3, 1))
    with pytest.raises(IndexError):
        index.query([native.QueryBox(view, projection, (100, 100), (0, 0, 10, 10), bodies=[99])])
    with pytest.raises(ValueError, match="unknown metric"):
        index.rank("happiness", [0])
    with pytest.raises(ValueError, match="combine"):
        index.rank("collision_count", [0], combine="median")


def test_worlds_and_refined_children_hold_their_rest_pose_to_the_runs_end(native, engine, tmp_path):
    """A box around where a body rests, with a time window at the very end of the run, matches
    every world (sampled or refined, ending earlier or later than its parent); the same box as
    a negative box rejects every world."""
    out = tmp_path / "rest.mwb"
    # The quick start's die and its chute (round toys roll on for ever); over eight seconds every
    # world comes to rest and ends before the run does.
    with open(os.path.join(SCENES, "quickstart.json")) as f:
        scene_json = json.load(f)
    scene_json["bodies"] = [b for b in scene_json["bodies"] if b["name"] in ("Ground", "Chute", "Die")]
    die_scene = tmp_path / "die.json"
    die_scene.write_text(json.dumps(scene_json))
    assert run_engine(engine, "sample", "--scene", str(die_scene), "--out", str(out), "--seed", "8",
                      "--worlds", "0:6", "--duration", "8").returncode == 0
    lib = native.Library(str(out))
    scene = native.Scene.from_json(lib.header.scene_json)
    die = scene.body_names.index("Die")
    result = run_engine(engine, "refine", "--library", str(out), "--world", "2", "--bodies", str(die),
                        "--time", "1.0", "--count", "6")
    assert result.returncode == 0, result.stderr
    lib = native.Library(str(out))
    index = native.PathIndex(native.body_bounding_radii(scene))
    index.add_library(lib)
    run_end_s = lib.run_last_frame / 120
    frame_counts = {w: lib.frame_count(w) for w in lib.world_indices}
    assert any(c - 1 < lib.run_last_frame - 120 for c in frame_counts.values()), "some world must end early"
    children = [w for w in lib.world_indices if lib.world_info(w).parent_world == 2]
    assert len(children) == 6 and any(frame_counts[c] != frame_counts[2] for c in children)
    view, projection, size = look_at([3, -8, 6], [3, 0, 0]), perspective(0.9, 1.6, 0.1, 100), (1600, 1000)
    for body in (die,):
        for w in lib.world_indices:
            x, y = screen_of(view, projection, size, lib.positions(w)[body, -1])
            rect = (x - 4, y - 4, x + 4, y + 4)
            for swept in (False, True):
                box = native.QueryBox(view, projection, size, rect, bodies=[body], swept=swept,
                                      time_window=(run_end_s - 0.05, run_end_s))
                negative = native.QueryBox(view, projection, size, rect, negative=True, bodies=[body], swept=swept,
                                           time_window=(run_end_s - 0.05, run_end_s))
                for brute_force in (False, True):
                    assert w in index.query([box], brute_force=brute_force).matching, (w, body, swept)
                    assert w not in index.query([negative], brute_force=brute_force).matching, (w, body, swept)


def test_indexing_in_steps_takes_worlds_in_file_order_while_the_library_grows(native, engine, tmp_path):
    """The add-on's background fill: add_library(limit=) indexes the next worlds in file order on
    one thread while the main thread polls the library the engine is still appending to; nothing
    is lost or indexed twice, and queries answer as on an index built at once."""
    out = tmp_path / "growing.mwb"
    scene_path = os.path.join(SCENES, "quickstart.json")
    assert run_engine(engine, "sample", "--scene", scene_path, "--out", str(out), "--seed", "8",
                      "--worlds", "0:30").returncode == 0
    lib = native.Library(str(out))
    radii = native.body_bounding_radii(native.Scene.from_json(lib.scene_json))
    index = native.PathIndex(radii)
    assert index.add_library(lib, threads=1, limit=7) == 7
    box_all = native.QueryBox(look_at([0, -10, 5], [0, 0, 0.5]), perspective(0.9, 1.6, 0.1, 100), (1600, 1000),
                              (0, 0, 1600, 1000), bodies=[2, 3, 4, 5])
    assert list(index.query([box_all]).world_indices) == sorted(lib.world_indices[:7])

    engine_run = subprocess.Popen([engine, "sample", "--scene", scene_path, "--out", str(out), "--seed", "8",
                                   "--worlds", "30:90", "--threads", "1"], stdout=subprocess.DEVNULL)
    added, errors = [], []

    def fill():
        try:
            while len(lib.world_indices) < 90 or index.world_count < 90:
                added.append(index.add_library(lib, threads=1, limit=3))
                if not added[-1]:
                    time.sleep(0.001)
        except Exception as error:  # the assertion below names it
            errors.append(error)

    filler = threading.Thread(target=fill)
    filler.start()
    deadline = time.monotonic() + 120
    while engine_run.poll() is None or len(lib.world_indices) < 90:
        assert time.monotonic() < deadline, "the engine did not append its worlds"
        lib.poll()
        time.sleep(0.002)
    filler.join(60)
    assert not filler.is_alive() and not errors, errors
    assert engine_run.returncode == 0 and sum(added) == 90 - 7 and index.world_count == 90
    whole = native.PathIndex(radii)
    whole.add_library(lib)
    view, projection, size = look_at([3, -8, 6], [3, 0, 0]), perspective(0.9, 1.6, 0.1, 100), (1600, 1000)
    rng = np.random.default_rng(5)
    for _ in range(20):
        x0, y0 = rng.uniform(0, 1400), rng.uniform(0, 800)
        box = native.QueryBox(view, projection, size, (x0, y0, x0 + 200, y0 + 200), bodies=[2, 3])
        got, expected = index.query([box]), whole.query([box])
        assert np.array_equal(got.world_indices, expected.world_indices)
        assert np.array_equal(got.matching, expected.matching)
