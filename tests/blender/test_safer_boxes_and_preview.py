"""Boxes test only the bodies the simulation moves, the ranking follows the boxes' objects, and an
edit during a preview is met with a question instead of being undone behind the user's back."""
import bpy
import numpy as np
import pytest

from conftest import add_rigid_body, drop_scene, mesh_object, sample_and_wait, save_blend
from test_queries import PROJECTION, SIZE, VIEW

from many_worlds import preview, scene_boxes
from many_worlds.core.session import SESSION


def select(*names):
    for ob in bpy.data.objects:
        ob.select_set(ob.name in names)
    bpy.context.view_layer.objects.active = bpy.data.objects[names[0]]


def add_box(**kwargs):
    return bpy.ops.mwb.add_box(rect=(0, 0, SIZE[0], SIZE[1]), view_matrix=VIEW.ravel().tolist(),
                               projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE, **kwargs)


@pytest.fixture
def sampled(tmp_path):
    """The drop scene (ground, Box0, Box1) plus an animated box, 6 worlds sampled."""
    drop_scene(bodies=2)
    lift = mesh_object("Lift", location=(-1, 0, 0.2), scale=(0.2, 0.2, 0.05))
    add_rigid_body(lift, "ACTIVE", kinematic=True)
    save_blend(tmp_path)
    sample_and_wait(6, seed=2)
    return SESSION.view


def test_a_box_leaves_out_passive_and_animated_objects_and_says_which(sampled, capfd):
    select("Box0", "Ground", "Lift")
    assert add_box() == {"FINISHED"}
    box = bpy.context.scene.mwb.boxes[-1]
    assert [b.name for b in box.bodies] == ["Box0"]
    warning = capfd.readouterr().out
    assert "Left out" in warning and "Ground" in warning and "Lift" in warning and "Box0" not in warning
    # Named explicitly, the passive ground is still left out.
    assert add_box(bodies="Ground,Box1") == {"FINISHED"}
    assert [b.name for b in bpy.context.scene.mwb.boxes[-1].bodies] == ["Box1"]
    # Only passive objects selected: every simulated body, never the ground.
    select("Ground")
    assert add_box() == {"FINISHED"}
    assert sorted(b.name for b in bpy.context.scene.mwb.boxes[-1].bodies) == ["Box0", "Box1"]


def test_the_panel_names_the_objects_a_new_box_will_test_before_drawing(sampled):
    select("Box1", "Ground")
    with bpy.context.temp_override(selected_objects=[bpy.data.objects["Box1"], bpy.data.objects["Ground"]]):
        tested, left_out = scene_boxes.body_choice(bpy.context)
    assert (tested, left_out) == (["Box1"], ["Ground"])
    assert scene_boxes.left_out_text(left_out) == "Left out (passive or animated): Ground"


def test_the_ranking_follows_the_boxes_objects_not_the_selection(sampled):
    settings = bpy.context.scene.mwb
    assert settings.rank_bodies == "BOXES"
    settings.rank_metric = "path_length_m"
    assert add_box(bodies="Box1") == {"FINISHED"}
    select("Box0")
    by_boxes = scene_boxes.RANKING.get(bpy.context)
    ids, values = by_boxes.ids.tolist(), by_boxes.values.copy()
    select("Box1", "Ground")
    again = scene_boxes.RANKING.get(bpy.context)
    assert again.ids.tolist() == ids and np.array_equal(again.values, values)
    settings.rank_bodies = "LISTED"
    settings.rank_body_names.clear()
    settings.rank_body_names.add().name = "Box1"
    listed = scene_boxes.RANKING.get(bpy.context)
    assert listed.ids.tolist() == ids and np.array_equal(listed.values, values)
    settings.rank_body_names[0].name = "Box0"
    assert not np.array_equal(scene_boxes.RANKING.get(bpy.context).values, values)


def moved_during_preview(world=1, frame=20):
    scene = bpy.context.scene
    assert bpy.ops.mwb.select_world(world=world) == {"FINISHED"}
    scene.frame_set(frame)
    box = bpy.data.objects["Box0"]
    posed = box.matrix_world.copy()
    box.location.x += 0.5
    bpy.context.view_layer.update()
    return box, posed


def test_preview_is_a_state_that_says_the_rigid_body_world_is_paused(sampled):
    scene = bpy.context.scene
    assert preview.state_text(scene) == ""
    bpy.ops.mwb.select_world(world=2)
    assert scene.rigidbody_world.enabled is False
    assert preview.state_text(scene) == "Previewing world 2: Rigid Body World paused, End Preview to edit"
    bpy.ops.mwb.end_preview()
    assert preview.state_text(scene) == "" and scene.rigidbody_world.enabled


def test_moving_an_object_during_preview_asks_to_end_it_instead_of_undoing_the_move(sampled):
    scene = bpy.context.scene
    before = bpy.data.objects["Box0"].matrix_world.copy()
    box, posed = moved_during_preview()
    assert "Box0 moved" in preview.conflict(scene) and "End Preview" in preview.conflict(scene)
    moved_x = box.matrix_world.translation.x
    assert moved_x == pytest.approx(posed.translation.x + 0.5)
    # Playing on does not pose it back while the question is open.
    scene.frame_set(30)
    assert box.matrix_world.translation.x == pytest.approx(moved_x)
    assert bpy.ops.mwb.end_preview() == {"FINISHED"}
    # Back where it was before the preview: the move made on a posed object is not kept.
    assert np.allclose(np.array(box.matrix_basis), np.array(before), atol=1e-6)
    assert scene.rigidbody_world.enabled and preview.conflict(scene) == ""


def test_keep_previewing_poses_the_world_again(sampled):
    scene = bpy.context.scene
    box, posed = moved_during_preview(frame=20)
    assert bpy.ops.mwb.keep_previewing() == {"FINISHED"}
    assert preview.conflict(scene) == "" and scene.mwb.previewing
    assert np.allclose(np.array(box.matrix_world), np.array(posed), atol=1e-5)


def test_switching_the_rigid_body_world_on_during_preview_is_kept_when_it_ends(sampled):
    scene = bpy.context.scene
    scene.rigidbody_world.enabled = False
    bpy.ops.mwb.select_world(world=0)
    scene.rigidbody_world.enabled = True
    bpy.context.view_layer.update()
    assert "Rigid Body World was switched on" in preview.conflict(scene)
    bpy.ops.mwb.end_preview()
    # Switched off before the preview, on by the user during it: on.
    assert scene.rigidbody_world.enabled is True


def test_the_variation_panel_reads_ranges_around_the_objects_own_place_during_preview(sampled):
    from many_worlds.ui import panels
    scene = bpy.context.scene
    box = bpy.data.objects["Box0"]
    own = panels.around_text(scene, box, "location")
    own_location = box.matrix_world.translation.copy()
    bpy.ops.mwb.select_world(world=1)
    scene.frame_set(40)
    # The world has moved the box (it fell), the ranges still read around where the user put it.
    assert (box.matrix_world.translation - own_location).length > 0.1
    assert panels.around_text(scene, box, "location") == own
    bpy.ops.mwb.end_preview()
    assert panels.around_text(scene, box, "location") == own


def test_the_variation_panel_reads_zero_without_a_sign(sampled):
    """A rotation or place a hair below zero (as a rotation matrix gives back) reads 0, not -0."""
    from many_worlds.ui import panels
    scene = bpy.context.scene
    box = bpy.data.objects["Box0"]
    box.location = (-1e-7, 0.5, -0.001)
    box.rotation_euler = (-1e-7, 0.0, -0.2 / panels.props.DEG_PER_RAD)
    bpy.context.view_layer.update()
    assert panels.around_text(scene, box, "rotation") == "Around 0°, 0°, 0°"
    # A value and its unit are one word (a no-break space) when the panel wraps the line.
    assert panels.around_text(scene, box, "location").startswith("Around 0\u00a0m, "), \
        panels.around_text(scene, box, "location")
    scene.unit_settings.system = "NONE"
    assert panels.around_text(scene, box, "location") == "Around 0.00, 0.50, 0.00"
