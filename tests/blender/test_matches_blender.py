"""The engine and Blender's own simulation (Bullet) read the same settings the same way: run one
scene both ways and compare where things end up. Catches sign and axis conventions that a
field-by-field export test cannot see."""
import math

import bpy
import numpy as np
import pytest

from conftest import add_constraint, add_rigid_body, ensure_world, mesh_object
from many_worlds import compat


def simulate_in_blender(ob, frame_end):
    scene = bpy.context.scene
    for frame in range(scene.frame_start, frame_end + 1):
        scene.frame_set(frame)
    return ob.matrix_world.copy()


def simulate_in_engine(body_name):
    from many_worlds import _native
    from many_worlds.export import export_and_validate
    result, problems = export_and_validate(bpy.context)
    assert result.scene is not None and not problems and not result.problems, (problems, result.problems)
    scene = _native.Scene.from_json(result.to_json())
    params = _native.SimulationParameters()
    params.perturb = False
    params.stop_at_rest = False
    world = _native.sample(scene, params, 0, 0, 1, threads=1)[0]
    body = scene.body_names.index(body_name)
    return world.positions[body, -1], world.orientations[body, -1]


def arm_angle_about_y(orientation_wxyz):
    """Angle of the arm's +X axis about world +Y, degrees (positive: tip goes down)."""
    w, x, y, z = orientation_wxyz
    tip = np.array([1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)])
    return math.degrees(math.atan2(-tip[2], tip[0]))


def test_hinge_limits_stop_the_arm_on_the_same_side_in_both():
    # Posts (object 1, passive) and arms (object 2) hinged at the posts about Y. The arms start
    # horizontal and gravity swings them down; asymmetric limits let one fall 60°, the other 5°.
    ensure_world()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 72
    scene.rigidbody_world.point_cache.frame_start, scene.rigidbody_world.point_cache.frame_end = 1, 72
    cases = {}
    for k, limits in enumerate(((-5, 60), (-60, 5))):
        y = 2.0 * k
        post = add_rigid_body(mesh_object(f"Post{k}", location=(0, y, 1), scale=(0.05, 0.05, 0.05)), "PASSIVE")
        arm = add_rigid_body(mesh_object(f"Arm{k}", location=(0.5, y, 1), scale=(0.5, 0.05, 0.05)), "ACTIVE")
        arm.rigid_body.linear_damping = arm.rigid_body.angular_damping = 0.5
        hinge = add_constraint(f"Hinge{k}", "HINGE", post, arm, location=(0, y, 1), rotation=(math.pi / 2, 0, 0))
        rbc = hinge.rigid_body_constraint
        rbc.use_limit_ang_z = True
        rbc.limit_ang_z_lower, rbc.limit_ang_z_upper = math.radians(limits[0]), math.radians(limits[1])
        cases[arm] = limits
    scene.frame_set(1)
    in_blender = {arm: arm_angle_about_y(simulate_in_blender(arm, 72).to_quaternion()) for arm in cases}
    scene.frame_set(1)
    for arm, limits in cases.items():
        _, orientation = simulate_in_engine(arm.name)
        engine_angle = arm_angle_about_y(orientation)
        # Gravity swings the arm down to whichever limit is on the falling side (60° or 5° here):
        # the engine must stop it at the same limit as Blender.
        assert abs(in_blender[arm] - limits[1]) < 3, (limits, in_blender[arm])
        assert abs(engine_angle - in_blender[arm]) < 3, (limits, in_blender[arm], engine_angle)


def test_dropped_shapes_come_to_rest_at_the_same_height_in_both():
    # Collision margins: Bullet keeps a box's or a sphere's margin inside the shape, and so must we.
    ensure_world()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 48
    scene.rigidbody_world.point_cache.frame_start, scene.rigidbody_world.point_cache.frame_end = 1, 48
    add_rigid_body(mesh_object("Ground", location=(0, 0, -0.5), scale=(5, 5, 0.5)), "PASSIVE")
    crate = add_rigid_body(mesh_object("Crate", location=(0, 0, 1.0), scale=(0.3, 0.3, 0.3)), "ACTIVE")
    ball = add_rigid_body(mesh_object("Ball", "uv_sphere", location=(2, 0, 1.0), radius=0.25), "ACTIVE", shape="SPHERE")
    for ob in (crate, ball):
        ob.rigid_body.collision_margin = 0.04
    scene.frame_set(1)
    in_blender = {ob.name: simulate_in_blender(ob, 48).translation.z for ob in (crate, ball)}
    scene.frame_set(1)
    for ob, rest in ((crate, 0.3), (ball, 0.25)):
        position, _ = simulate_in_engine(ob.name)
        assert abs(in_blender[ob.name] - rest) < 0.01, (ob.name, in_blender[ob.name])
        assert abs(position[2] - in_blender[ob.name]) < 0.01, (ob.name, position[2], in_blender[ob.name])


def test_a_ball_thrown_by_keyed_animated_flies_on_as_in_blender():
    # The usual throw: "Animated" keyed on for the first frames while the ball is keyed moving
    # sideways, then keyed off; Blender lets it go with the animation's velocity, and it flies on
    # in a parabola. A ball exported as animated throughout would stop dead at its last key.
    ensure_world()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 36
    scene.rigidbody_world.point_cache.frame_start, scene.rigidbody_world.point_cache.frame_end = 1, 36
    ball = add_rigid_body(mesh_object("Ball", "uv_sphere", location=(0, 0, 3), radius=0.2), "ACTIVE", shape="SPHERE")
    ball.rigid_body.linear_damping = ball.rigid_body.angular_damping = 0.0
    for frame, x, animated in ((1, 0.0, True), (10, 1.5, True), (11, 1.5, False)):
        ball.location.x = x
        ball.keyframe_insert("location", frame=frame)
        ball.rigid_body.kinematic = animated
        ball.keyframe_insert("rigid_body.kinematic", frame=frame)
    for curve in compat.object_fcurves(ball):
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"
    from many_worlds.export import export_scene
    exported = next(b for b in export_scene(scene).scene["bodies"] if b["name"] == "Ball")
    assert exported["kinematic"] is False and exported["animated_until_s"] == pytest.approx(9 / 24)
    scene.frame_set(1)
    in_blender = simulate_in_blender(ball, 36).translation
    scene.frame_set(1)
    position, _ = simulate_in_engine("Ball")
    # Keyed at 1.5 m per 9 frames (4 m/s): 26 free frames later it is far along x and has fallen.
    assert in_blender.x > 4.0 and in_blender.z < 2.0, tuple(in_blender)
    assert np.linalg.norm(np.array(position) - np.array(in_blender)) < 0.1, (tuple(position), tuple(in_blender))


def test_grounds_of_every_shape_hold_a_dropped_box_at_blenders_height():
    # A plane as ground with each collision shape Blender offers for it, default margins (0.04 m,
    # "Collision Margin" unchecked): BOX (a flat box), MESH (thickened by the margin), CONVEX_HULL.
    ensure_world()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 48
    scene.rigidbody_world.point_cache.frame_start, scene.rigidbody_world.point_cache.frame_end = 1, 48
    crates = []
    for k, shape in enumerate(("BOX", "MESH", "CONVEX_HULL")):
        plane = mesh_object(f"Ground{shape}", "plane", location=(4 * k, 0, 0), size=3)
        add_rigid_body(plane, "PASSIVE", shape=shape)
        crate = add_rigid_body(mesh_object(f"Crate{shape}", location=(4 * k, 0, 1), scale=(0.2, 0.2, 0.2)), "ACTIVE")
        crates.append(crate)
    scene.frame_set(1)
    in_blender = {ob.name: simulate_in_blender(ob, 48).translation.z for ob in crates}
    scene.frame_set(1)
    for ob in crates:
        position, _ = simulate_in_engine(ob.name)
        assert 0.15 < in_blender[ob.name] < 0.3, (ob.name, in_blender[ob.name])
        assert abs(position[2] - in_blender[ob.name]) < 0.01, (ob.name, position[2], in_blender[ob.name])
