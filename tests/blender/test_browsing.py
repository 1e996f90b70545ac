"""Browsing worlds side by side: stepping through the ranking, the colour legend, and posing a
world's frame for a picture (thumbnails and the command line's contact sheet) without leaving a
trace in the scene."""
import bpy
import numpy as np
import pytest

from conftest import drop_scene, sample_and_wait, save_blend

from many_worlds import posing, scene_boxes
from many_worlds.core import palette
from many_worlds.core.session import SESSION
from many_worlds.operators.browsing import stepped_world
from many_worlds.ui import legend


@pytest.fixture
def sampled(tmp_path):
    _, boxes = drop_scene(bodies=3)
    save_blend(tmp_path)
    sample_and_wait(6, seed=5)
    return boxes


def ranked_worlds():
    return [int(w) for w in scene_boxes.RANKING.get(bpy.context).ids]


def test_step_world_previews_the_next_and_previous_world_of_the_ranking(sampled):
    settings = bpy.context.scene.mwb
    settings.rank_metric = "path_length_m"
    ranked = ranked_worlds()
    assert len(ranked) == 6 and ranked != sorted(ranked), "the ranking should not be the library's order"
    seen = []
    for _ in range(7):
        assert bpy.ops.mwb.step_world(step=1) == {"FINISHED"}
        seen.append(settings.selected_world)
    # From no selection the first world, then down the ranking, round to the first again.
    assert seen == ranked + ranked[:1]
    assert settings.previewing
    assert bpy.ops.mwb.step_world(step=-1) == {"FINISHED"}
    assert settings.selected_world == ranked[-1]
    # The ranking changes: stepping follows it.
    settings.rank_descending = not settings.rank_descending
    assert bpy.ops.mwb.step_world(step=1) == {"FINISHED"}
    assert settings.selected_world == ranked_worlds()[ranked_worlds().index(ranked[-1]) + 1]
    # Undoable, but no redo panel (registered operators get one), which would cover the viewport's
    # label of the world stepped to.
    assert bpy.types.MWB_OT_step_world.bl_options == {"UNDO"}


def test_stepping_skips_the_worlds_the_boxes_reject():
    assert stepped_world([4, 1, 9], 1, 1) == 9
    assert stepped_world([4, 1, 9], 9, 1) == 4
    assert stepped_world([4, 1, 9], 4, -1) == 9
    # A world the ranking no longer lists (rejected by a new box): the first or the last one.
    assert stepped_world([4, 1, 9], 7, 1) == 4 and stepped_world([4, 1, 9], 7, -1) == 9
    assert stepped_world([], 3, 1) is None


def test_the_legend_names_each_drawn_object_in_its_own_colour(sampled):
    settings = bpy.context.scene.mwb
    settings.path_bodies = "ACTIVE"
    entries = legend.legend_entries(bpy.context)
    assert [name for name, _ in entries] == ["Box0", "Box1", "Box2"]
    assert len({colour for _, colour in entries}) == 3
    # The colours the overlay gives each body are the legend's.
    view = SESSION.view
    by_body = palette.body_colours(view.body_names, view.simulated_bodies())
    assert {view.body_names[b]: by_body[b] for b in view.simulated_bodies()} == dict(entries)
    # A rejected world is greyer and fainter than a matching one, and keeps a hint of the hue.
    for _, colour in entries:
        faded, bright = palette.rejected(colour), palette.matching(colour)
        assert faded[3] < 0.3 * bright[3]
        assert np.ptp(faded[:3]) < 0.5 * np.ptp(bright[:3]) and np.ptp(faded[:3]) > 0
    bpy.ops.object.select_all(action="DESELECT")
    sampled[1].select_set(True)
    settings.path_bodies = "SELECTED"
    assert [name for name, _ in legend.legend_entries(bpy.context)] == ["Box1"]


def test_posing_a_world_for_a_picture_leaves_the_scene_as_it_was(sampled):
    scene, view_layer = bpy.context.scene, bpy.context.view_layer
    view = SESSION.view
    before = {ob.name: ob.matrix_world.copy() for ob in sampled}
    world = view.world_indices[2]
    last = posing.last_frame(view.library, world)
    with posing.posed(scene, view_layer, view, world, last):
        assert scene.rigidbody_world.enabled is False
        for ob in sampled:
            body = view.body_names.index(ob.name)
            expected = view.library.positions(world)[body, last]
            assert np.allclose(ob.matrix_world.translation, expected, atol=1e-4)
            # Evaluated as well: what a draw or a render sees.
            evaluated = ob.evaluated_get(bpy.context.evaluated_depsgraph_get())
            assert np.allclose(evaluated.matrix_world.translation, expected, atol=1e-4)
    assert scene.rigidbody_world.enabled is True
    for ob in sampled:
        assert np.allclose(np.array(ob.matrix_world), np.array(before[ob.name]))


def test_posing_during_a_preview_is_not_taken_for_an_edit(sampled):
    scene, view_layer = bpy.context.scene, bpy.context.view_layer
    view = SESSION.view
    assert bpy.ops.mwb.select_world(world=view.world_indices[0]) == {"FINISHED"}
    previewed = {ob.name: ob.matrix_world.copy() for ob in sampled}
    with posing.posed(scene, view_layer, view, view.world_indices[3], 0):
        pass
    from many_worlds import preview
    preview.check_edits(scene)
    assert preview.conflict(scene) == ""
    for ob in sampled:
        assert np.allclose(np.array(ob.matrix_world), np.array(previewed[ob.name]))
    assert scene.rigidbody_world.enabled is False


def test_filmstrip_frames_run_from_the_start_to_the_last_frame():
    assert posing.filmstrip_frames(100, 5) == [0, 25, 50, 74, 99]
    assert posing.filmstrip_frames(3, 5) == [0, 1, 2]
    assert posing.filmstrip_frames(0, 5) == []
