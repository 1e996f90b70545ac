"""The goal of a seek without Blender: boxes in their order (which box is met after which, also
once some are left out or deleted), the goal file the engine reads, the seek's command, progress
lines and summary."""
import json

import numpy as np
import pytest

from many_worlds.core import engine, goal
from many_worlds.core.library_query import BoxSpec, closes_order_cycle, order_after_removing, order_among

VIEW = np.arange(16, dtype=np.float64).reshape(4, 4) / 7
PROJECTION = np.eye(4) * 1.5


def box(rect=(10, 20, 110, 220), after=-1, **fields):
    return BoxSpec(view=VIEW, projection=PROJECTION, size=(1600, 1000), rect=rect, bodies=(2, 4), after=after,
                   **fields)


def test_the_goal_file_holds_each_box_as_it_was_given(tmp_path):
    specs = [box(), box((0.5, 1.5, 30.25, 40), negative=True, swept=True, time_window=(1.0, 2.5)),
             box((5, 5, 6, 6), after=0)]
    path = goal.write_goal(str(tmp_path / "shot.goal.json"), specs)
    with open(path) as f:
        boxes = json.load(f)["boxes"]
    assert len(boxes) == 3
    for spec, written in zip(specs, boxes):
        assert written["view"] == spec.view.ravel().tolist()
        assert written["projection"] == spec.projection.ravel().tolist()
        assert (tuple(written["viewport"]), tuple(written["rect"]), written["negative"], tuple(written["bodies"]),
                written["swept"]) == (spec.size, spec.rect, spec.negative, spec.bodies, spec.swept)
    assert [b["time_window"] for b in boxes] == [None, [1.0, 2.5], None]
    assert [b["after"] for b in boxes] == [None, None, 0]


def test_the_goal_file_has_the_engines_fields_row_major_and_the_order_by_position(tmp_path):
    specs = [box(after=2), box(), box(time_window=(3.0, 4.0), after=1)]
    document = json.loads(open(goal.write_goal(str(tmp_path / "g.json"), specs)).read())
    boxes = document["boxes"]
    assert [b["after"] for b in boxes] == [2, None, 1]
    first = boxes[0]
    assert set(first) == {"view", "projection", "viewport", "rect", "bodies", "negative", "swept", "time_window",
                          "after"}
    # Row-major: the second number is the first row's second column.
    assert first["view"][1] == VIEW[0, 1] and first["view"][4] == VIEW[1, 0] and len(first["projection"]) == 16
    assert first["viewport"] == [1600, 1000] and first["rect"] == [10, 20, 110, 220] and first["bodies"] == [2, 4]
    assert first["time_window"] is None and boxes[2]["time_window"] == [3.0, 4.0]


@pytest.mark.parametrize("specs,phrase", [
    ([], "a goal needs at least one box"),
    ([box(), box(after=1)], "part 2 is to be met after itself"),
    ([box(after=2), box()], "part 1 is to be met after part 3, but the goal has 2 parts"),
    ([BoxSpec(view=VIEW, projection=PROJECTION, size=(10, 10), rect=(0, 0, 1, 1))], "box 1 tests no bodies"),
    ([box(time_window=(4.0, 3.0))], "box 1 has a time window"),
    ([box(after=1), box(after=0)], "cycle"),
])
def test_a_goal_that_cannot_be_met_is_refused_before_the_engine_starts(tmp_path, specs, phrase):
    with pytest.raises(ValueError, match=phrase):
        goal.write_goal(str(tmp_path / "g.json"), specs)
    assert not (tmp_path / "g.json").exists()


def test_the_order_counts_among_the_boxes_passed_on():
    # Boxes 0..4; box 1 is disabled. Box 2 after 0, box 3 after 1 (left out: unordered), box 4 after 3.
    afters = [-1, -1, 0, 1, 3]
    assert order_among(afters, [True, False, True, True, True]) == [-1, 0, -1, 2]
    assert order_among(afters, [True] * 5) == afters
    assert order_among(afters, [False] * 5) == []


def test_deleting_a_box_keeps_the_order_of_the_others():
    afters = [-1, 0, 1, 0, 2]
    # Box 1 goes: box 2 (after it) loses its order, box 4 (after box 2, now box 1) follows it down.
    assert order_after_removing(afters, 1) == [-1, -1, 0, 1]
    assert order_after_removing(afters, 0) == [-1, 0, -1, 1]
    assert order_after_removing(afters, 4) == [-1, 0, 1, 0]


def test_an_order_that_would_close_a_cycle_is_recognised():
    afters = [-1, 0, 1, -1]   # 2 after 1 after 0
    assert closes_order_cycle(afters, 0, 2) and closes_order_cycle(afters, 0, 1) and closes_order_cycle(afters, 1, 1)
    assert not closes_order_cycle(afters, 2, 0) and not closes_order_cycle(afters, 0, 3)
    assert not closes_order_cycle(afters, 3, -1)


def test_seek_request_and_the_outcome_read_from_its_summary():
    argv = engine.SeekRequest("l.mwb", "l.goal.json", 3, 2000, threads=2).arguments()
    assert argv[:5] == ["seek", "--library", "l.mwb", "--goal", "l.goal.json"]
    assert argv[argv.index("--want") + 1] == "3" and argv[argv.index("--budget-worlds") + 1] == "2000"
    assert argv[argv.index("--threads") + 1] == "2"
    assert "--budget-s" not in argv and "--seed" not in argv and "--json" not in argv
    argv = engine.SeekRequest("l.mwb", "g", 1, 10, budget_s=60, seed=4).arguments()
    assert argv[argv.index("--budget-s") + 1] == "60.0" and argv[argv.index("--seed") + 1] == "4"

    reached = engine.SeekOutcome.from_summary({"reached": True, "found": [412, 415, 430], "best": 412,
                                               "best_boxes_met": 6, "boxes": 6, "worlds_made": 1204, "seconds": 61.2,
                                               "text": "Goal reached: 3 worlds meet all 6 parts"})
    assert reached.found == (412, 415, 430) and reached.best == 412
    # The engine words the outcome (RunWords, held by the native tests); the add-on shows it as it is.
    assert reached.text == "Goal reached: 3 worlds meet all 6 parts"
    # Another command's summary is not a seek's outcome.
    assert engine.SeekOutcome.from_summary({"stored": 3, "rejected": 0, "text": "sampled 3 worlds"}) is None


def test_worlds_meeting_an_orientation_goal_are_those_whose_recorded_rotations_keep_within_it(native, engine,
                                                                                              tmp_path):
    """An orientation part, "the die's top stays within N degrees of up over the last second", is
    met by exactly the worlds whose recorded rotations (at the path's points) say so; a bad part is a
    GoalError (a ValueError) naming it."""
    import subprocess
    from conftest import SCENES
    library = str(tmp_path / "q.mwb")
    subprocess.run([engine, "sample", "--scene", f"{SCENES}/quickstart.json", "--out", library, "--worlds", "0:16"],
                   check=True, capture_output=True)
    lib = native.Library(library)
    names = list(native.Scene.from_json(lib.scene_json).body_objects)
    die = names.index("Die")
    hz, window = 120.0, (3.0, 4.0)
    worst_tilt = {}
    for w in lib.world_indices:
        up = orientations_up(lib.orientations(int(w))[die])
        stride, last = lib.polyline_stride(int(w)), lib.frame_count(int(w)) - 1
        frames = sorted({min(k * stride, last) for k in range(last // stride + 2)})
        inside = [f for f in frames if window[0] <= f / hz <= window[1]] or ([last] if last / hz < window[0] else [])
        worst_tilt[int(w)] = max(np.degrees(np.arccos(np.clip(up[f], -1, 1))) for f in inside)
    tilts = sorted(worst_tilt.values())
    # A tolerance in the widest gap between two worlds' worst tilts, so that no world sits on it.
    gaps = [(b - a, (a + b) / 2) for a, b in zip(tilts, tilts[1:]) if 1 < (a + b) / 2 < 179]
    tolerance = max(gaps)[1]
    expected = sorted(w for w, t in worst_tilt.items() if t <= tolerance)
    assert 0 < len(expected) < 16, tilts
    part = {"objects": ["Die"], "within_deg": tolerance, "time_window": list(window)}
    met = native.worlds_meeting_goal(library, json.dumps({"boxes": [], "orientations": [part]}))
    assert list(met) == expected
    with pytest.raises(ValueError, match="orientation part 1 has a tolerance"):
        native.worlds_meeting_goal(library, json.dumps({"boxes": [], "orientations": [dict(part, within_deg=0)]}))


def orientations_up(quaternions):
    """cos of the angle between each rotation's local up (z) and the world's."""
    w, x, y, z = quaternions[:, 0], quaternions[:, 1], quaternions[:, 2], quaternions[:, 3]
    return 1 - 2 * (x * x + y * y)
