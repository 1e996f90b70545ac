"""Pose parts through the add-on's operators and properties, on worlds the engine sampled from
cubes with Blender's default shape (Convex Hull) dropped with any orientation: "Add Pose" makes
an Upright part for the selected cube in the boxes' list, the match count follows the worlds
where that cube ends upright (checked against the library's decoded rotations at full rate, not
through the index), a negative part keeps the others, As Posed keeps the side that faces up
now, undo and save/reload keep the list as it was, and Seek writes the part into its goal file."""
import json
import math
import time

import bpy
import numpy as np
import pytest
from mathutils import Euler, Quaternion, Vector

from conftest import ensure_world, mesh_object, override, sample_and_wait, save_blend

from many_worlds import compat, scene_boxes
from many_worlds.core import engine as engine_process
from many_worlds.core import goal, library_query, paths
from many_worlds.core.session import SESSION
from many_worlds.operators import run_poller

WORLDS = 32
# Degrees either side of the tolerance within which a world is too close to call from frames at a
# rate other than the index's (a cube still settling as the window opens).
MARGIN_DEG = 2.0


def dice_scene(count=3):
    """A ground and `count` cubes (Blender's default collision shape) dropped from 1 m, each world
    starting them in any orientation."""
    ground = mesh_object("Ground", location=(0, 0, -0.5), scale=(5, 5, 0.5))
    ensure_world()
    with override(ground):
        bpy.ops.rigidbody.object_add(type="PASSIVE")
    dice = []
    for i in range(count):
        die = mesh_object(f"Die{i}", location=(0.6 * i, 0, 1.0), scale=(0.1, 0.1, 0.1))
        with override(die):
            bpy.ops.rigidbody.object_add(type="ACTIVE")
        assert die.rigid_body.collision_shape == "CONVEX_HULL"
        v = die.mwb_variation
        v.rotation_min, v.rotation_max = (-math.pi,) * 3, (math.pi,) * 3
        v.location_min, v.location_max = (-0.05, -0.05, 0), (0.05, 0.05, 0.1)
        dice.append(die)
    scene = bpy.context.scene
    scene.rigidbody_world.point_cache.frame_start, scene.rigidbody_world.point_cache.frame_end = 1, 73
    scene.frame_start, scene.frame_end = 1, 73
    return dice


@pytest.fixture
def dice(tmp_path):
    objects = dice_scene()
    save_blend(tmp_path)
    sample_and_wait(WORLDS, threads=2, seed=5)
    assert len(SESSION.view.world_indices) == WORLDS
    return objects


def add_pose(objects, **settings):
    """Press Add Pose with `objects` selected; returns the parts it added."""
    before = len(bpy.context.scene.mwb.boxes)
    with bpy.context.temp_override(selected_objects=objects, active_object=objects[0] if objects else None):
        assert bpy.ops.mwb.add_pose(**settings) == {"FINISHED"}
    return list(bpy.context.scene.mwb.boxes)[before:]


def matching_worlds():
    view = SESSION.view
    return {w for w, m in zip(view.world_indices, view.matching) if m}


def angles_from_up(name, window):
    """Per world: the degrees between the object's local +Z and world up at every recorded frame
    of `window` (s), from the library's decoded rotations (w, x, y, z), the last pose held once
    the world has ended."""
    library = SESSION.view.library
    body = SESSION.view.body_names.index(name)
    lo, hi = window
    out = {}
    for w in SESSION.view.world_indices:
        q = library.orientations(w)[body]
        hz = library.world_info(w).record_hz
        times = np.arange(len(q)) / hz
        frames = np.flatnonzero((times >= lo) & (times <= hi))
        if times[-1] < lo:
            frames = [len(q) - 1]
        qw, qx, qy, qz = q[frames].T
        # The third column of the rotation matrix: where the object's local +Z points.
        z_up = 1 - 2 * (qx * qx + qy * qy)
        out[w] = np.degrees(np.arccos(np.clip(z_up, -1, 1)))
    return out


def test_an_upright_pose_keeps_the_worlds_where_the_die_ends_upright(dice):
    settings = bpy.context.scene.mwb
    (part,) = add_pose([dice[0]])
    assert (part.kind, part.pose_mode, part.negative, part.within_deg) == ("POSE", "UPRIGHT", False, 15.0)
    assert [b.name for b in part.bodies] == ["Die0"] and settings.box_index == 0
    # A new positive pose is tested over the run's last second: where a die has landed.
    end = (73 - 1) / 24
    assert part.use_time_window and (part.time_start_s, part.time_end_s) == pytest.approx((end - 1, end))
    body = SESSION.view.body_names.index("Die0")
    assert scene_boxes.enabled_specs(bpy.context.scene, SESSION.view) == [library_query.PoseSpec(
        bodies=(body,), within_deg=15.0, axis=(0.0, 0.0, 1.0), target=(0.0, 0.0, 1.0),
        time_window=pytest.approx((end - 1, end)))]

    angles = angles_from_up("Die0", (part.time_start_s, part.time_end_s))
    upright = {w for w, a in angles.items() if a.max() < 15 - MARGIN_DEG}
    fallen = {w for w, a in angles.items() if a[-1] > 15 + MARGIN_DEG}
    assert len(upright) + len(fallen) >= WORLDS - 2, "too many worlds still settling in the last second"
    assert upright and fallen, "the dice should land both ways"
    matching = matching_worlds()
    assert upright <= matching and not fallen & matching
    assert scene_boxes.match_text() == f"{len(matching)} of {WORLDS} worlds match"

    # Goal Parts Met counts the pose part: 1 for the worlds it keeps, 0 for the others.
    settings.rank_metric, settings.rank_descending = library_query.BOXES_MET, True
    assert settings.bl_rna.properties["rank_metric"].enum_items[library_query.BOXES_MET].name == "Goal Parts Met"
    ranking = scene_boxes.RANKING.get(bpy.context)
    assert {int(w) for w, v in zip(ranking.ids, ranking.values) if v == 1} == matching
    assert len(ranking.ids) == WORLDS

    # Negative: the worlds where the die never faces up in the last second.
    part.negative = True
    never_up = {w for w, a in angles.items() if a.min() > 15 + MARGIN_DEG}
    once_up = {w for w, a in angles.items() if a.min() < 15 - MARGIN_DEG}
    negative_matching = matching_worlds()
    assert never_up <= negative_matching and not once_up & negative_matching
    assert not negative_matching & matching and upright | never_up <= negative_matching | matching
    part.enabled = False
    assert matching_worlds() == set(SESSION.view.world_indices)


def test_add_pose_says_why_it_is_greyed_out():
    dice = dice_scene(count=1)
    with bpy.context.temp_override(selected_objects=[]):
        assert not bpy.ops.mwb.add_pose.poll()
        with pytest.raises(RuntimeError, match="To add a pose, select objects the simulation moves"):
            bpy.ops.mwb.add_pose()
    ground = bpy.data.objects["Ground"]
    with bpy.context.temp_override(selected_objects=[ground]):
        with pytest.raises(RuntimeError, match=r"the simulation moves \(Ground is passive or animated\)"):
            bpy.ops.mwb.add_pose()
    # A passive object beside a die is left out of the part.
    (part,) = add_pose([ground, dice[0]])
    assert [b.name for b in part.bodies] == ["Die0"]


def test_as_posed_keeps_the_side_facing_up_now(dice):
    die = dice[1]
    die.rotation_euler = Euler((math.radians(90), 0, math.radians(30)))
    bpy.context.view_layer.update()
    (part,) = add_pose([die], mode="AS_POSED")
    # The side facing up, R⁻¹·up: the object's local +Y once turned 90° about X.
    up_side = die.matrix_world.to_quaternion().inverted() @ Vector((0, 0, 1))
    assert np.allclose(part.pose_captured_axis, up_side, atol=1e-6)
    assert np.allclose(part.pose_captured_axis, (0, 1, 0), atol=1e-6)
    (spec,) = scene_boxes.enabled_specs(bpy.context.scene, SESSION.view)
    assert np.allclose(spec.axis, up_side, atol=1e-6) and spec.target == (0.0, 0.0, 1.0)
    # Use Current Pose captures the pose the object has at this frame.
    die.rotation_euler = Euler((0, math.radians(-90), 0))
    bpy.context.view_layer.update()
    assert bpy.ops.mwb.pose_use_current() == {"FINISHED"}
    assert np.allclose(part.pose_captured_axis, (1, 0, 0), atol=1e-6)
    # Two objects As Posed: one part each, each with its own side.
    parts = add_pose([dice[0], die], mode="AS_POSED")
    assert [[b.name for b in p.bodies] for p in parts] == [["Die0"], ["Die1"]]
    assert np.allclose(parts[0].pose_captured_axis, (0, 0, 1), atol=1e-6)
    assert np.allclose(parts[1].pose_captured_axis, (1, 0, 0), atol=1e-6)


def test_a_pose_is_undone_and_saved_with_the_blend_like_a_box(dice, tmp_path):
    bpy.ops.ed.undo_push(message="before the pose")
    (part,) = add_pose([dice[2]])
    # In the UI Blender pushes the step after an UNDO operator; background mode needs it by hand.
    bpy.ops.ed.undo_push(message="Add Pose")
    assert "UNDO" in bpy.types.MWB_OT_add_pose.bl_options
    assert matching_worlds() != set(SESSION.view.world_indices)
    bpy.ops.ed.undo()
    assert len(bpy.context.scene.mwb.boxes) == 0
    assert matching_worlds() == set(SESSION.view.world_indices)

    # Undo gave the objects back as new Python objects: look them up again.
    (part,) = add_pose([bpy.data.objects["Die2"]])
    part.pose_mode, part.pose_axis, part.pose_direction = "AXIS", "NEG_X", "POS_Y"
    part.within_deg, part.negative, part.longer_than_s = 40.0, True, 0.5
    part.use_time_window = False
    before = matching_worlds()
    bpy.ops.wm.save_mainfile()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.open_mainfile(filepath=str(tmp_path / "shot.blend"))
    (loaded,) = bpy.context.scene.mwb.boxes
    assert (loaded.kind, loaded.pose_mode) == ("POSE", "AXIS")
    assert (loaded.pose_axis, loaded.pose_direction) == ("NEG_X", "POS_Y")
    assert (loaded.within_deg, loaded.negative, loaded.longer_than_s) == (40.0, True, 0.5)
    (spec,) = scene_boxes.enabled_specs(bpy.context.scene, SESSION.view)
    assert (spec.axis, spec.target, spec.longer_than_s, spec.time_window) == ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0),
                                                                              0.5, None)
    assert matching_worlds() == before


def test_a_pose_after_a_box_is_ordered_like_boxes(dice):
    from test_queries import PROJECTION, SIZE, VIEW
    assert bpy.ops.mwb.add_box(rect=(0, 0, SIZE[0], SIZE[1]), view_matrix=VIEW.ravel().tolist(),
                               projection_matrix=PROJECTION.ravel().tolist(), region_size=SIZE,
                               bodies="Die0") == {"FINISHED"}
    (part,) = add_pose([dice[0]])
    box = bpy.context.scene.mwb.boxes[0]
    # The After menus name each part by its kind and place.
    assert bpy.types.UILayout.enum_item_name(part, "after", "0") == "Box 1"
    assert bpy.types.UILayout.enum_item_name(box, "after", "1") == "Pose 2"
    part.after = "0"
    assert part.after_box == 0
    specs = scene_boxes.enabled_specs(bpy.context.scene, SESSION.view)
    assert [type(s).__name__ for s in specs] == ["BoxSpec", "PoseSpec"] and specs[1].after == 0
    assert bpy.ops.mwb.remove_box(index=0) == {"FINISHED"}
    assert bpy.context.scene.mwb.boxes[0].after_box == -1


def test_seek_writes_the_pose_into_its_goal(dice):
    add_pose([dice[0]])
    settings = bpy.context.scene.mwb
    settings.seek_want, settings.seek_budget_worlds, settings.threads = 1, 16, 2
    assert bpy.ops.mwb.seek() == {"FINISHED"}
    run = SESSION.run
    while run_poller.poll_run() is not None:
        time.sleep(0.05)
    assert SESSION.last_error == "", SESSION.last_error
    # The engine, reading the goal file, finds the worlds the add-on's query keeps.
    outcome = engine_process.SeekOutcome.from_summary(run.summary())
    assert outcome.reached and sorted(outcome.found) == sorted(matching_worlds()), SESSION.status
    with open(paths.goal_json_path(SESSION.view.path)) as f:
        document = json.load(f)
    body = SESSION.view.body_names.index("Die0")
    (written,) = document["orientations"]
    assert written["bodies"] == [body] and written["within_deg"] == 15.0 and written["negative"] is False
    assert written["axis"] == [0.0, 0.0, 1.0] and written["target"] == [0.0, 0.0, 1.0]
    assert document["boxes"] == []
    assert document == goal.goal_document(scene_boxes.enabled_specs(bpy.context.scene, SESSION.view))


FACES = {"POS_X": (1, 0, 0), "NEG_X": (-1, 0, 0), "POS_Y": (0, 1, 0), "NEG_Y": (0, -1, 0), "POS_Z": (0, 0, 1),
         "NEG_Z": (0, 0, -1)}


def test_seek_lands_the_die_on_a_face_no_sampled_world_shows_and_bake_keys_it(dice):
    # "This die lands on that face", made in the sidebar for its rarest face: Seek makes one more
    # world where it does than sampling found, and Bake keys that world onto the die.
    die = dice[1]
    (part,) = add_pose([die], mode="AXIS")
    part.within_deg = 12.0
    shown = {}
    for face in FACES:
        part.pose_axis = face
        shown[face] = len(matching_worlds())
    face = min(FACES, key=lambda f: (shown[f], f))
    part.pose_axis = face
    settings = bpy.context.scene.mwb
    settings.seek_want, settings.seek_budget_worlds, settings.threads = shown[face] + 1, 600, 2
    assert bpy.ops.mwb.seek() == {"FINISHED"}
    run = SESSION.run
    while run_poller.poll_run() is not None:
        time.sleep(0.05)
    outcome = engine_process.SeekOutcome.from_summary(run.summary())
    assert outcome.reached, SESSION.status
    world = max(outcome.found)
    assert world >= WORLDS and set(outcome.found) <= matching_worlds()
    bpy.ops.mwb.select_world(world=world)
    assert bpy.ops.mwb.bake_world() == {"FINISHED"}
    # The die's baked rotation keys have that face up at the end.
    end = bpy.context.scene.frame_end
    keyed = Quaternion([compat.find_fcurve(die, "rotation_quaternion", k).evaluate(end) for k in range(4)])
    up = keyed.to_matrix() @ Vector(FACES[face])
    assert math.degrees(up.normalized().angle(Vector((0, 0, 1)))) < 12 + MARGIN_DEG
