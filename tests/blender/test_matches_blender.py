"""The engine and Blender's own simulation (Bullet) read the same settings the same way: run one
scene both ways and compare where things end up. Catches sign and axis conventions that a
field-by-field export test cannot see."""
import math

import bpy
import numpy as np

from conftest import add_constraint, add_rigid_body, ensure_world, mesh_object


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
    # A post (object 1, passive) and an arm (object 2) hinged at the post about Y. The arm starts
    # horizontal and gravity swings it down; asymmetric limits let it fall 60° one way, 5° the other.
    ensure_world()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 72
    scene.rigidbody_world.point_cache.frame_start, scene.rigidbody_world.point_cache.frame_end = 1, 72
    post = add_rigid_body(mesh_object("Post", location=(0, 0, 1), scale=(0.05, 0.05, 0.05)), "PASSIVE")
    arm = add_rigid_body(mesh_object("Arm", location=(0.5, 0, 1), scale=(0.5, 0.05, 0.05)), "ACTIVE", mass=1.0)
    arm.rigid_body.linear_damping = arm.rigid_body.angular_damping = 0.5
    for limits in ((-5, 60), (-60, 5)):
        hinge = add_constraint(f"Hinge{limits[1]}", "HINGE", post, arm, location=(0, 0, 1), rotation=(math.pi / 2, 0, 0))
        rbc = hinge.rigid_body_constraint
        rbc.use_limit_ang_z = True
        rbc.limit_ang_z_lower, rbc.limit_ang_z_upper = math.radians(limits[0]), math.radians(limits[1])
        bpy.context.scene.frame_set(1)
        blender_angle = arm_angle_about_y(simulate_in_blender(arm, 72).to_quaternion())
        scene.frame_set(1)
        _, orientation = simulate_in_engine("Arm")
        engine_angle = arm_angle_about_y(orientation)
        # Gravity swings the arm down to whichever limit is on the falling side (60° or 5° here):
        # the engine must stop it at the same limit as Blender.
        assert abs(blender_angle - limits[1]) < 3, (limits, blender_angle)
        assert abs(engine_angle - blender_angle) < 3, (limits, blender_angle, engine_angle)
        bpy.data.objects.remove(hinge)
        bpy.ops.ptcache.free_bake_all()
