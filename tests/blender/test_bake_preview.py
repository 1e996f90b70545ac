"""Preview and bake of a sampled world, checked against the world re-simulated in this process
(the raw, uncompressed motion): what the user sees and keys is within the codec's bounds."""
import math

import bpy
import numpy as np
import pytest


from conftest import drop_scene, sample_and_wait, save_blend

from many_worlds import _native, compat
from many_worlds.core.session import SESSION

POSITION_BOUND_M = 0.001
ROTATION_BOUND_RAD = 0.5 * math.pi / 180
# Keys are float32 in Blender: a few micrometres on top of the codec bound.
FLOAT_SLACK_M = 2e-5


def raw_world(world):
    """Re-simulate one world in-process from the library's own header (same scene, parameters, seed)."""
    header = SESSION.view.library.header
    scene = _native.Scene.from_json(header.scene_json)
    (result,) = _native.sample(scene, header.parameters, header.base_seed, world, 1, threads=1)
    return scene.body_names, result.positions, result.orientations, result.record_hz


def rotation_angle(q1, q2):
    return 2 * math.acos(min(1.0, abs(float(np.dot(q1, q2)))))


def check_pose(ob, names, positions, orientations, world_frame):
    i = names.index(ob.name)
    location, rotation, _ = ob.matrix_world.decompose()
    assert np.linalg.norm(np.array(location) - positions[i, world_frame]) <= POSITION_BOUND_M + FLOAT_SLACK_M
    assert rotation_angle(np.array(rotation), orientations[i, world_frame]) <= ROTATION_BOUND_RAD + 1e-4


@pytest.fixture
def sampled(tmp_path):
    _, boxes = drop_scene(bodies=2)
    save_blend(tmp_path)
    sample_and_wait(3, seed=3)
    return boxes


def test_selecting_a_world_poses_the_objects_and_end_restores_the_scene(sampled):
    scene = bpy.context.scene
    before = {ob.name: ob.matrix_world.copy() for ob in sampled}
    assert bpy.ops.mwb.select_world(world=2) == {"FINISHED"}
    assert scene.mwb.selected_world == 2 and scene.mwb.previewing
    # Blender's own simulation is off while previewing, so it cannot fight the preview.
    assert scene.rigidbody_world.enabled is False
    names, positions, orientations, hz = raw_world(2)
    for frame in (1, 5, 13, 30):
        scene.frame_set(frame)
        for ob in sampled:
            check_pose(ob, names, positions, orientations, min(round((frame - 1) / 24 * hz), positions.shape[1] - 1))
    assert bpy.ops.mwb.end_preview() == {"FINISHED"}
    assert scene.rigidbody_world.enabled is True and not scene.mwb.previewing
    scene.frame_set(1)
    for ob in sampled:
        assert np.allclose(np.array(ob.matrix_world), np.array(before[ob.name]), atol=1e-6)


def test_bake_writes_keys_that_match_the_world_and_removes_rigid_bodies(sampled):
    scene = bpy.context.scene
    bpy.ops.mwb.select_world(world=1)
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    assert not scene.mwb.previewing and scene.rigidbody_world.enabled
    names, positions, orientations, hz = raw_world(1)
    # Keys run to the end of the frame range, also when the world came to rest earlier.
    last_frame = scene.frame_end
    for ob in sampled:
        # The keys rule through "Animated"; the rigid body and its settings stay for sampling again.
        assert ob.rigid_body is not None and ob.rigid_body.kinematic
        assert ob.rotation_mode == "QUATERNION"
        fcurves = {(f.data_path, f.array_index): f for f in compat.object_fcurves(ob)}
        assert len(fcurves) == 7
        keys = fcurves[("location", 0)].keyframe_points
        assert len(keys) == last_frame and keys[0].co.x == 1 and keys[-1].co.x == last_frame
    for frame in range(1, last_frame + 1):
        scene.frame_set(frame)
        for ob in sampled:
            check_pose(ob, names, positions, orientations, min(round((frame - 1) / 24 * hz), positions.shape[1] - 1))


def test_a_world_that_came_to_rest_is_baked_and_previewed_at_rest_to_the_last_frame(tmp_path):
    _, boxes = drop_scene(bodies=2, frame_end=145)  # 6 s: the boxes rest long before
    save_blend(tmp_path)
    sample_and_wait(2, seed=5)
    scene = bpy.context.scene
    names, positions, orientations, hz = raw_world(0)
    world_end_frame = 1 + (positions.shape[1] - 1) / hz * 24
    assert world_end_frame < scene.frame_end - 24, "the world must end (at rest) well before the frame range"
    bpy.ops.mwb.select_world(world=0)
    scene.frame_set(scene.frame_end)
    for ob in boxes:
        check_pose(ob, names, positions, orientations, positions.shape[1] - 1)
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    for ob in boxes:
        keys = compat.find_fcurve(ob, "location", 0).keyframe_points
        assert keys[-1].co.x == scene.frame_end
    for frame in (math.ceil(world_end_frame) + 1, scene.frame_end):
        scene.frame_set(frame)
        for ob in boxes:
            check_pose(ob, names, positions, orientations, positions.shape[1] - 1)


def test_bake_of_200_objects_by_600_frames_matches_its_input():
    from many_worlds import bake
    objects = []
    for i in range(200):
        ob = bpy.data.objects.new(f"Body{i:03d}", None)
        bpy.context.scene.collection.objects.link(ob)
        objects.append(ob)
    frames = np.arange(1, 601, dtype=np.float64)
    t = frames[None, :, None] / 600
    rng = np.random.default_rng(1)
    locations = rng.normal(size=(200, 1, 3)) + t * rng.normal(size=(200, 1, 3))
    angles = (t[..., 0] * rng.uniform(1, 3, size=(200, 1)))
    rotations = np.stack([np.cos(angles / 2), np.sin(angles / 2), 0 * angles, 0 * angles], axis=-1)
    bake.bake_objects(objects, frames, locations, rotations)
    scene = bpy.context.scene
    scene.frame_end = 600
    for frame in (1, 250, 600):
        scene.frame_set(frame)
        for k in (0, 99, 199):
            m = objects[k].matrix_world
            assert np.allclose(m.to_translation(), locations[k, frame - 1], atol=1e-5)
            assert np.allclose(m.to_quaternion(), rotations[k, frame - 1], atol=1e-5)


def test_bake_is_undoable(sampled):
    names = [ob.name for ob in sampled]
    bpy.ops.mwb.select_world(world=0)
    bpy.ops.mwb.end_preview()
    bpy.ops.ed.undo_push(message="before bake")
    assert "UNDO" in bpy.types.MWB_OT_bake_world.bl_options
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    # In the UI Blender pushes the step after an UNDO operator; background mode needs it by hand.
    bpy.ops.ed.undo_push(message="Bake World")
    assert all(bpy.data.objects[n].rigid_body.kinematic for n in names)
    bpy.ops.ed.undo()
    for name in names:
        ob = bpy.data.objects[name]
        assert ob.rigid_body is not None and ob.rigid_body.type == "ACTIVE" and not ob.rigid_body.kinematic
        assert ob.animation_data is None or ob.animation_data.action is None


def test_bake_says_it_set_quaternion_rotation_and_undo_gives_the_mode_back(sampled):
    from many_worlds import bake
    names = [ob.name for ob in sampled]
    assert all(bpy.data.objects[n].rotation_mode == "XYZ" for n in names)
    bpy.ops.mwb.select_world(world=0)
    bpy.ops.mwb.end_preview()
    bpy.ops.ed.undo_push(message="before bake")
    outcome = bake.bake_world(bpy.context, 0)
    bpy.ops.ed.undo_push(message="Bake World")
    assert sorted(outcome.to_quaternion) == sorted(names)
    assert f"set the rotation mode of 2 to Quaternion ({', '.join(outcome.to_quaternion)})" in outcome.text(0), \
        outcome.text(0)
    bpy.ops.ed.undo()
    assert all(bpy.data.objects[n].rotation_mode == "XYZ" for n in names)


def test_bake_names_the_objects_deleted_since_sampling(sampled):
    from many_worlds import bake
    gone = sampled[1].name
    bpy.data.objects.remove(sampled[1])
    bpy.ops.mwb.select_world(world=1)
    bpy.ops.mwb.end_preview()
    outcome = bake.bake_world(bpy.context, 1)
    assert outcome.baked == [sampled[0].name] and outcome.skipped == [gone]
    assert outcome.text(1).startswith(f"Baked world 1 onto 1 objects; skipped 1 no longer in the file ({gone})")


def _keys(ob, data_path, index=0):
    fcurve = compat.find_fcurve(ob, data_path, index)
    assert fcurve is not None, f"{ob.name} has no {data_path}[{index}] keys"
    return [tuple(k.co) for k in fcurve.keyframe_points]


def test_bake_keeps_the_animators_own_keys_and_follows_the_world(tmp_path):
    # The animator keyed the box's scale and a custom property before sampling: the bake writes
    # its own channels (location, rotation) and leaves theirs as they were.
    _, boxes = drop_scene(bodies=2)
    box = boxes[0]
    for frame in (1, 49):
        box.keyframe_insert("scale", frame=frame)
    box["glow"] = 0.0
    box.keyframe_insert('["glow"]', frame=1)
    box["glow"] = 1.0
    box.keyframe_insert('["glow"]', frame=49)
    own = {(path, k): _keys(box, path, k) for path, k in (("scale", 0), ("scale", 1), ("scale", 2), ('["glow"]', 0))}
    save_blend(tmp_path)
    sample_and_wait(2, seed=11)
    scene = bpy.context.scene
    bpy.ops.mwb.select_world(world=1)
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    for (path, k), keys in own.items():
        assert _keys(box, path, k) == keys, f"the bake changed the animator's {path}[{k}] keys"
    assert len(_keys(box, "location", 2)) == scene.frame_end
    names, positions, orientations, hz = raw_world(1)
    scene.rigidbody_world.enabled = False  # the keys alone move the box
    for frame in (1, 25, 49):
        scene.frame_set(frame)
        check_pose(box, names, positions, orientations, min(round((frame - 1) / 24 * hz), positions.shape[1] - 1))
        assert box.scale.x == pytest.approx(0.1, abs=1e-6) and box["glow"] == pytest.approx((frame - 1) / 48, abs=1e-3)


def test_baking_an_object_whose_animation_is_shared_warns_and_leaves_the_other_alone(tmp_path):
    from many_worlds import bake
    _, boxes = drop_scene(bodies=1)
    box = boxes[0]
    bpy.ops.object.empty_add(location=(2, 0, 0))
    marker = bpy.context.active_object
    marker.name = "Marker"
    for frame in (1, 49):
        box.keyframe_insert("scale", frame=frame)
    # Object > Link/Transfer Data > Link Animation Data: the marker plays the box's keys.
    bpy.ops.object.select_all(action="DESELECT")
    marker.select_set(True)
    box.select_set(True)
    bpy.context.view_layer.objects.active = box
    bpy.ops.object.make_links_data(type="ANIMATION")
    assert marker.animation_data.action == box.animation_data.action
    save_blend(tmp_path)
    sample_and_wait(1, seed=2)
    bpy.ops.mwb.select_world(world=0)
    from many_worlds import preview
    preview.end(bpy.context.scene)
    outcome = bake.bake_world(bpy.context, 0)
    assert outcome.baked == [box.name] and outcome.hidden == [] and outcome.skipped == []
    assert any(w.startswith(f"{box.name}: its animation is shared with Marker") for w in outcome.warnings), \
        outcome.warnings
    assert marker.animation_data.action != box.animation_data.action
    assert compat.find_fcurve(marker, "location", 0) is None, "the bake keyed the marker too"
    assert len(_keys(marker, "scale", 0)) == 2
    assert len(_keys(box, "scale", 0)) == 2 and len(_keys(box, "location", 0)) > 2
