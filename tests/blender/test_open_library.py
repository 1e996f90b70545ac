"""Opening a library the engine made: paths are drawn while the path index still fills in the
background, the Boxes panel says how far it got, a box evaluated meanwhile answers for exactly the
worlds indexed so far, and once the index is complete every world is there and the answer equals
that of an index built in full before querying.

The fill is held back a step at a time (a gate in front of each step of the real fill), so what
the test sees while it fills does not depend on the machine's speed.
"""
import os
import subprocess
import threading
import time

import bpy
import numpy as np
import pytest

from conftest import ROOT

from many_worlds import _native, scene_boxes
from many_worlds.core import library_query as core_query
from many_worlds.core import path_budget
from many_worlds.core.library_view import LibraryView
from many_worlds.core.paths import engine_path
from many_worlds.core.session import SESSION
from many_worlds.draw import paths
from many_worlds.core import libraries

WORLDS = 600
STEP_WORLDS = 100
BODY = "Marble"
TIMEOUT_S = 60
# A top view through an orthographic camera 10 m up, 10 m across: a pixel column is a world x.
VIEW = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, -10], [0, 0, 0, 1]], dtype=np.float64)
PROJECTION = np.array([[0.2, 0, 0, 0], [0, 0.2, 0, 0], [0, 0, -2 / 99.9, -100.1 / 99.9], [0, 0, 0, 1]],
                      dtype=np.float64)
SIZE = (1000, 1000)


class GatedFill(core_query.IndexFill):
    """The add-on's background fill, each step waiting until the test lets one through."""
    gate = threading.Semaphore(0)

    def _step(self):
        while not self.gate.acquire(timeout=0.05):
            if self.stopping:
                return 0
        return super()._step()


@pytest.fixture(scope="module")
def library(tmp_path_factory):
    """A library of the quick-start scene made by the engine."""
    path = str(tmp_path_factory.mktemp("open") / "quickstart.mwb")
    subprocess.run([engine_path(), "sample", "--scene", os.path.join(ROOT, "tests", "scenes", "quickstart.json"),
                    "--out", path, "--worlds", f"0:{WORLDS}", "--threads", "2"], check=True,
                   stdout=subprocess.DEVNULL, timeout=300)
    return path


@pytest.fixture
def gated(monkeypatch):
    monkeypatch.setattr(core_query, "IndexFill", GatedFill)
    monkeypatch.setattr(core_query, "FILL_STEP_WORLDS", STEP_WORLDS)
    GatedFill.gate = threading.Semaphore(0)
    yield GatedFill.gate
    # Whatever the test left waiting finishes or stops before the add-on is unregistered.
    SESSION.close()
    paths.OVERLAY.clear()


def box_rect_splitting_worlds(view):
    """A screen rectangle the Marble's path enters in about half the worlds: x from the median of
    the paths' largest x to the right edge."""
    body = view.body_names.index(BODY)
    reach = np.array([np.nanmax(view.library.polyline(w)[body, :, 0]) for w in view.world_indices])
    x = float(np.median(reach))
    return ((x + 5) * 100, 0, SIZE[0], SIZE[1])


def full_answer(path, rect):
    """(match flags, boxes met per world, ranking) of an index built in full before querying."""
    view = LibraryView(_native, path)
    lq = core_query.LibraryQuery(_native, view)
    spec = scene_boxes.drag_spec(view, VIEW, PROJECTION, SIZE, rect, False, [BODY])
    result = lq.evaluate([spec])
    return result.matching, result.boxes_satisfied, lq.rank("path_length_m", spec.bodies)


def wait_until(condition):
    deadline = time.monotonic() + TIMEOUT_S
    while not condition():
        assert time.monotonic() < deadline, "the background index did not get there"
        time.sleep(0.01)


def test_paths_are_drawn_while_the_index_fills_and_queries_answer_for_the_worlds_indexed(library, gated):
    scene = bpy.context.scene
    rect = box_rect_splitting_worlds(LibraryView(_native, library))
    matching, satisfied, (ranked_ids, ranked_values) = full_answer(library, rect)
    assert 0.2 * WORLDS < matching.sum() < 0.8 * WORLDS
    scene_boxes.store_box(scene, VIEW, PROJECTION, SIZE, rect, False, [BODY])

    assert libraries.open_library(library, scene)
    view, lq = SESSION.view, SESSION.query
    assert len(view.world_indices) == WORLDS and lq.indexed_count == 0 and lq.filling
    # Paths are drawn before a single world is indexed, within the budget.
    paths.OVERLAY.clear()
    assert paths.OVERLAY.update(bpy.context)
    arrays = paths.OVERLAY.arrays
    assert 0 < arrays.vertex_count <= path_budget.VERTEX_BUDGET and arrays.worlds_drawn == WORLDS
    assert lq.indexed_count == 0
    assert scene_boxes.index_progress_text() == f"Indexing 0 of {WORLDS} worlds"
    assert not view.matching.any(), "a world matched before it was indexed"

    # Three steps of the fill: the boxes answer for the first 300 worlds, as the full index does.
    for _ in range(3):
        gated.release()
    wait_until(lambda: lq.indexed_count == 3 * STEP_WORLDS)
    assert scene_boxes.poll_index_fill() == scene_boxes.INDEX_POLL_S
    indexed = 3 * STEP_WORLDS
    assert lq.result.indexed == indexed
    assert scene_boxes.index_progress_text() == f"Indexing {indexed} of {WORLDS} worlds"
    assert np.array_equal(view.matching[:indexed], matching[:indexed]) and view.matching[:indexed].any()
    assert not view.matching[indexed:].any()
    assert np.array_equal(lq.result.boxes_satisfied[:indexed], satisfied[:indexed])
    # The ranking lists the matched worlds indexed so far, in the full ranking's order.
    so_far = set(view.world_indices[:indexed])
    ids, values = lq.rank("path_length_m", scene_boxes.body_indices([BODY], view))
    keep = [k for k, w in enumerate(ranked_ids) if int(w) in so_far]
    assert np.array_equal(ids, ranked_ids[keep]) and np.array_equal(values, ranked_values[keep])
    # The paths follow the new answer: drawn again, matched worlds among them.
    assert paths.OVERLAY.update(bpy.context)
    assert paths.OVERLAY.arrays.worlds_drawn == WORLDS

    # The rest of the fill: every world indexed, the same answer as the full index, the timer stops.
    for _ in range(WORLDS):
        gated.release()
    wait_until(lambda: not lq.filling)
    assert scene_boxes.poll_index_fill() is None
    assert lq.indexed_count == WORLDS and lq.result.indexed == WORLDS
    assert scene_boxes.index_progress_text() == ""
    assert np.array_equal(view.matching, matching)
    assert np.array_equal(lq.result.boxes_satisfied, satisfied)
    ids, values = lq.rank("path_length_m", scene_boxes.body_indices([BODY], view))
    assert np.array_equal(ids, ranked_ids) and np.array_equal(values, ranked_values)
    assert not view.library.warnings


def test_closing_the_library_stops_the_fill_and_reopening_indexes_everything(library, gated):
    scene = bpy.context.scene
    assert libraries.open_library(library, scene)
    gated.release()
    lq = SESSION.query
    wait_until(lambda: lq.indexed_count == STEP_WORLDS)
    SESSION.close()
    for _ in range(WORLDS):
        gated.release()
    time.sleep(0.2)
    assert lq.indexed_count == STEP_WORLDS, "the fill went on after the library was closed"
    # Without the gate: the fill runs to the end by itself.
    GatedFill.gate = threading.Semaphore(WORLDS)
    assert libraries.open_library(library, scene)
    wait_until(lambda: not SESSION.query.filling)
    assert SESSION.query.indexed_count == WORLDS
