"""Ten thousand worlds the engine sampled (the open-library benchmark's library, sampled again when
it is missing or this build cannot read it): opened in the add-on, every world's paths are drawn
within the drawing budget while the path index fills in the background; the complete index
holds every world, answers boxes exactly as testing every segment does, and reads the paths from
the library instead of keeping a copy of its own."""
import fcntl
import os
import subprocess
import time

import bpy
import numpy as np
import pytest

from conftest import ROOT

from many_worlds import _native, scene_boxes
from many_worlds.core import path_budget
from many_worlds.core.paths import engine_path
from many_worlds.core.session import SESSION
from many_worlds.draw import paths
from many_worlds.core import libraries

WORLDS = 10_000
SCENE = os.path.join(ROOT, "tests", "scenes", "quickstart.json")
# Where `tests/bench/run open` keeps the library it samples.
CACHED = os.path.join(ROOT, "build", "bench-results", f"open_library_{WORLDS}.mwb")
INDEX_TIMEOUT_S = 300
# A top view through an orthographic camera 10 m up, 10 m across.
VIEW = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -10], [0, 0, 0, 1]], dtype=np.float64)
PROJECTION = np.array([[0.2, 0, 0, 0], [0, 0.2, 0, 0], [0, 0, -2 / 99.9, -100.1 / 99.9], [0, 0, 0, 1]],
                      dtype=np.float64)
SIZE = (1000, 1000)


def reads_every_world(path):
    try:
        library = _native.Library(path, 0.0)
    except (IOError, ValueError):
        return False
    return len(library.world_indices) == WORLDS and not library.warnings


@pytest.fixture(scope="module")
def library():
    """The benchmark's library; sampled by the engine under a lock, so runs side by side (Blender
    3.4 and 4.3) sample it once and never read it half-written."""
    os.makedirs(os.path.dirname(CACHED), exist_ok=True)
    with open(CACHED + ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not reads_every_world(CACHED):
            part = f"{CACHED}.{os.getpid()}.part"
            subprocess.run([engine_path(), "sample", "--scene", SCENE, "--out", part, "--worlds", f"0:{WORLDS}",
                            "--threads", "2"], check=True, stdout=subprocess.DEVNULL, timeout=1200)
            os.replace(part, CACHED)
    return CACHED


@pytest.fixture
def opened(library):
    paths.OVERLAY.clear()
    assert libraries.open_library(library, bpy.context.scene)
    yield SESSION.view
    SESSION.close()
    paths.OVERLAY.clear()


def wait_for_full_index():
    index = SESSION.query.index
    start = time.perf_counter()
    while index.world_count < WORLDS:
        assert time.perf_counter() - start < INDEX_TIMEOUT_S, f"the index holds {index.world_count} worlds"
        time.sleep(0.01)
    return index


def test_ten_thousand_worlds_are_drawn_within_the_budget(opened):
    overlay = paths.OVERLAY
    assert overlay.update(bpy.context)
    arrays = overlay.arrays
    view = opened
    drawn_bodies = len(view.simulated_bodies())
    full_detail = WORLDS * drawn_bodies * view.library.polyline(view.world_indices[0]).shape[1]
    assert full_detail > path_budget.VERTEX_BUDGET
    # Every world is drawn, its paths thinned on screen to fit the budget.
    assert 0 < arrays.vertex_count <= path_budget.VERTEX_BUDGET
    assert arrays.worlds_drawn == WORLDS and arrays.complete and arrays.coarsest_stride > 1
    assert overlay.budget_text() == ""


def rect_right_of(x_m):
    """The screen rectangle right of world x = x_m, 20 m wide (a pixel is 1 cm, x = 0 at 500 px)."""
    return ((x_m + 5) * 100, 0, (x_m + 25) * 100, SIZE[1])


def rect_left_of(x_m):
    """The screen rectangle left of world x = x_m, 20 m wide."""
    return ((x_m - 15) * 100, 0, (x_m + 5) * 100, SIZE[1])


def test_the_full_index_answers_as_every_segment_does_without_copying_the_paths(opened):
    index = wait_for_full_index()
    view = opened
    assert index.world_count == len(view.world_indices) == WORLDS
    bodies = list(view.simulated_bodies())
    marble = view.body_names.index("Marble")
    sample = [view.library.polyline(w) for w in view.world_indices[::10]]
    # A keep box the Marble enters in about half the worlds (it rolls off to +x), and a reject box
    # on every body that some body enters in about a fifth of them.
    marble_reach = np.median([np.nanmax(p[marble, :, 0]) for p in sample])
    least_x = np.percentile([np.nanmin(p[bodies, :, 0]) for p in sample], 20)
    keep = _native.QueryBox(VIEW, PROJECTION, SIZE, rect_right_of(marble_reach), bodies=[marble])
    reject = _native.QueryBox(VIEW, PROJECTION, SIZE, rect_left_of(least_x), negative=True, bodies=bodies)
    for boxes in ([keep], [reject], [keep, reject]):
        tree = index.query(boxes)
        brute = index.query(boxes, brute_force=True)
        assert np.array_equal(tree.world_indices, brute.world_indices)
        assert np.array_equal(tree.boxes_satisfied, brute.boxes_satisfied)
        assert np.array_equal(tree.matching, brute.matching)
        assert 0.1 * WORLDS < len(tree.matching) < 0.9 * WORLDS, len(tree.matching)
    # The index keeps boxes, not points: less than half of what the 30 Hz paths take as float32,
    # where a copy of them at 16 bits (as the library keeps them) would take half on its own.
    points_bytes = sum(p.nbytes for p in sample) * 10
    assert index.memory_bytes < points_bytes / 2, (index.memory_bytes, points_bytes)
