"""A greyed-out Sample or Seek says why, in the panel and in the button's tooltip (the operator's
poll message, which Blender also gives when a script calls it): no Rigid Body World, nothing to
simulate, no place for the library, nothing that varies, nothing to seek. A box too small to be one
is refused saying so, and a wrapped message keeps each value with its unit."""
import bpy
import pytest

from conftest import add_rigid_body, drop_scene, mesh_object, save_blend, sample_and_wait

from many_worlds.operators import sampling, seeking


def refused(operator):
    """The message Blender gives when `operator`'s poll refuses it."""
    assert not operator.poll()
    with pytest.raises(RuntimeError) as refusal:
        operator()
    return str(refusal.value)


def test_without_a_rigid_body_world_sample_says_to_add_one(tmp_path):
    save_blend(tmp_path)
    assert bpy.context.scene.rigidbody_world is None
    message = refused(bpy.ops.mwb.sample)
    assert "Add a Rigid Body World" in message
    assert "Save the .blend" not in message


def test_with_only_passive_bodies_sample_says_there_is_nothing_to_simulate(tmp_path):
    ground = mesh_object("Ground", location=(0, 0, -0.5), scale=(5, 5, 0.5))
    add_rigid_body(ground, "PASSIVE")
    save_blend(tmp_path)
    assert "Nothing to simulate" in refused(bpy.ops.mwb.sample)


def test_an_unsaved_file_without_a_library_path_says_to_save_or_set_one():
    drop_scene(bodies=1)
    assert "Save the .blend first" in refused(bpy.ops.mwb.sample)
    bpy.context.scene.mwb.library_path = "/tmp/unsaved.mwb"
    assert sampling.sample_blocker(bpy.context.scene) == ""


def test_a_run_that_could_only_make_identical_worlds_is_refused(tmp_path):
    _, boxes = drop_scene(bodies=1)
    save_blend(tmp_path)
    for box in boxes:
        v = box.mwb_variation
        v.location_min = v.location_max = v.angular_velocity_min = v.angular_velocity_max = (0, 0, 0)
    bpy.context.scene.mwb.alpha = 0
    assert "Every world would be the same" in refused(bpy.ops.mwb.sample)
    bpy.context.scene.mwb.alpha = 0.1
    assert bpy.ops.mwb.sample.poll()


def test_seek_says_what_it_needs_first(tmp_path):
    drop_scene(bodies=1)
    save_blend(tmp_path)
    assert "Open or sample a library first" in refused(bpy.ops.mwb.seek)
    sample_and_wait(2, threads=2)
    assert "Draw a box or add a pose first" in refused(bpy.ops.mwb.seek)
    assert seeking.seek_problem(bpy.context.scene).startswith("Draw a box or add a pose first")


def test_a_box_too_small_to_be_one_is_refused_saying_so():
    from test_queries import PROJECTION, SIZE, VIEW
    drop_scene(bodies=1)
    through = dict(view_matrix=VIEW.ravel().tolist(), projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE)
    with pytest.raises(RuntimeError, match=r"The box was too small \(1×50 px\)"):
        bpy.ops.mwb.add_box(rect=(10, 10, 11, 60), bodies="Box0", **through)
    assert len(bpy.context.scene.mwb.boxes) == 0
    assert bpy.ops.mwb.add_box(rect=(10, 10, 13, 60), bodies="Box0", **through) == {"FINISHED"}


def test_a_wrapped_message_keeps_each_value_with_its_unit():
    from many_worlds.ui import fit
    nbsp = fit.NO_BREAK_SPACE
    text = f"Around 12.25{nbsp}m, -3.50{nbsp}m, 8{nbsp}m"
    # From the width of the longest word (narrower, a word is broken inside, as it must be).
    widest = max(fit.text_width(word, 1.0) for word in text.split(" "))
    for width in range(int(widest) + 1, 200, 5):
        lines = fit.wrap(text, width, 1.0)
        assert all(not line.startswith("m") for line in lines), (width, lines)
        assert " ".join(lines) == text


def test_an_object_deleted_after_sampling_leaves_the_legend_the_new_box_and_the_drawing(tmp_path):
    from many_worlds import scene_boxes
    from many_worlds.core.session import SESSION
    from many_worlds.draw import paths
    from many_worlds.ui import legend
    _, boxes = drop_scene(bodies=2)
    save_blend(tmp_path)
    sample_and_wait(2, threads=2)
    for ob in bpy.context.view_layer.objects:
        ob.select_set(False)
    assert [name for name, _ in legend.legend_entries(bpy.context)] == ["Box0", "Box1"]
    bpy.data.objects.remove(boxes[1])
    assert [name for name, _ in legend.legend_entries(bpy.context)] == ["Box0"]
    assert scene_boxes.body_choice(bpy.context) == (["Box0"], [])
    drawn = paths.chosen_bodies(bpy.context, SESSION.view)
    assert [SESSION.view.body_names[i] for i in drawn] == ["Box0"]
