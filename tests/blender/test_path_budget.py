"""The viewport's drawing budget on a sampled library: with a budget lowered below what every path
needs, no more vertices are prepared than it allows, the selected world and the matched worlds'
selected objects are kept, and the panel says a subset is shown; batches are built once per change
of their inputs, not per redraw."""
import bpy
import numpy as np
import pytest

from conftest import drop_scene, sample_and_wait, save_blend

from many_worlds.core import path_budget
from many_worlds.core.session import SESSION
from many_worlds.draw import paths

WORLDS = 12


@pytest.fixture
def sampled(tmp_path):
    _, boxes = drop_scene(bodies=3)
    save_blend(tmp_path)
    sample_and_wait(WORLDS, seed=3)
    yield boxes
    paths.OVERLAY.vertex_budget = path_budget.VERTEX_BUDGET
    paths.OVERLAY.clear()


def select_only(objects):
    for ob in bpy.data.objects:
        ob.select_set(ob in objects)


def full_paths(view, world, bodies):
    """Line-list vertices of the full paths of those of `bodies` that `world` has."""
    return path_budget.line_segments(view.library.polyline(world), view.present_bodies(world, bodies), 1)


def drawn_bodies(arrays, world):
    """The body tuples drawn of `world`."""
    return {bodies for w, bodies, _ in arrays.drawn if w == world}


def test_a_small_budget_keeps_the_selected_world_and_the_matched_worlds_selected_objects(sampled):
    overlay = paths.OVERLAY
    view = SESSION.view
    settings = bpy.context.scene.mwb
    select_only([])
    overlay.clear()
    assert overlay.update(bpy.context)
    full = overlay.arrays
    assert full.worlds_drawn == WORLDS and full.complete and overlay.budget_text() == ""
    worlds = list(view.world_indices)
    matched = worlds[::3]
    view.set_matching([w in matched for w in worlds])
    # A rejected world selected, the paths of one object preferred.
    selected = worlds[1]
    settings.selected_world = selected
    select_only([sampled[1]])
    box1 = view.body_names.index(sampled[1].name)
    selected_size = len(full_paths(view, selected, tuple(view.simulated_bodies())))
    matched_size = sum(len(full_paths(view, w, (box1,))) for w in matched)
    overlay.vertex_budget = selected_size + matched_size + full.vertex_count // 10
    assert overlay.vertex_budget < full.vertex_count
    assert overlay.update(bpy.context)
    arrays = overlay.arrays
    assert arrays.vertex_count <= overlay.vertex_budget
    assert len(arrays.others) == len(arrays.other_colours) and arrays.other_colours.shape[1] == 4
    # The selected world in full, though rejected.
    full_selected = full_paths(view, selected, tuple(view.simulated_bodies()))
    assert np.array_equal(arrays.selected, full_selected, equal_nan=True)
    # Every matched world draws the preferred object's path; not every world is drawn.
    for w in matched:
        assert any(box1 in bodies for bodies in drawn_bodies(arrays, w)), w
    assert arrays.worlds_drawn < WORLDS and not arrays.complete
    text = overlay.budget_text()
    assert text == f"Showing {arrays.worlds_drawn} of {WORLDS} worlds' paths (drawing budget)"


def test_a_budget_below_full_detail_thins_paths_before_leaving_worlds_out(sampled):
    overlay = paths.OVERLAY
    select_only([])
    overlay.clear()
    overlay.update(bpy.context)
    full = overlay.arrays.vertex_count
    overlay.vertex_budget = int(full * 0.6)
    assert overlay.update(bpy.context)
    arrays = overlay.arrays
    assert arrays.vertex_count <= overlay.vertex_budget
    assert arrays.coarsest_stride > 1 and arrays.complete and arrays.worlds_drawn == WORLDS
    assert overlay.budget_text() == ""


def test_batches_are_rebuilt_only_when_their_inputs_change(sampled):
    overlay = paths.OVERLAY
    view = SESSION.view
    settings = bpy.context.scene.mwb
    overlay.clear()
    overlay.update(bpy.context)
    count = overlay.rebuilds
    # Redraws and settings the batches do not depend on: nothing is rebuilt.
    for _ in range(3):
        assert not overlay.update(bpy.context)
    settings.path_width = 4.0
    assert not overlay.update(bpy.context) and overlay.rebuilds == count
    # Each input: the match state, the selected world, the selected objects, the chosen bodies.
    view.set_matching(np.arange(len(view.world_indices)) % 2 == 0)
    assert overlay.update(bpy.context) and overlay.rebuilds == count + 1
    settings.selected_world = view.world_indices[2]
    assert overlay.update(bpy.context) and overlay.rebuilds == count + 2
    select_only([sampled[0]])
    assert overlay.update(bpy.context) and overlay.rebuilds == count + 3
    settings.path_bodies = "SELECTED"
    assert overlay.update(bpy.context) and overlay.rebuilds == count + 4
    assert not overlay.update(bpy.context) and overlay.rebuilds == count + 4
    # Paths off: nothing to draw, nothing built.
    settings.show_paths = False
    assert overlay.update(bpy.context) and overlay.arrays is None and overlay.rebuilds == count + 4
