"""Export of Blender's rigid-body settings, compared field by field with values worked out from
how the test built the scene (primitive sizes, scales, settings typed in)."""
import json
import math

import bpy
import pytest
from mathutils import Euler

from conftest import add_constraint, add_rigid_body, ensure_world, mesh_from_data, mesh_object

from many_worlds import export


def approx(value, rel=1e-6, abs=1e-6):
    return pytest.approx(value, rel=rel, abs=abs)


def exported():
    result, invalid = export.export_and_validate(bpy.context)
    assert result.scene is not None
    assert invalid == [], invalid
    # What the engine receives is JSON text: check that, not the Python dict.
    scene = json.loads(result.to_json())
    return scene, {b["name"]: b for b in scene["bodies"]}, {c["name"]: c for c in scene["constraints"]}, \
        result.problems


def quat_of_euler(xyz):
    return list(Euler(xyz, "XYZ").to_quaternion())


def test_every_shape_has_blenders_dimensions():
    ground = add_rigid_body(mesh_object("Ground", location=(0, 0, -0.1), scale=(5, 4, 0.1)), "PASSIVE", "BOX")
    add_rigid_body(mesh_object("Ball", "uv_sphere", location=(0, 0, 2), radius=0.5, scale=(2, 2, 2)),
                   shape="SPHERE")
    add_rigid_body(mesh_object("Pill", "cylinder", location=(1, 0, 2), radius=0.2, depth=1.0, scale=(1, 1, 2)),
                   shape="CAPSULE")
    add_rigid_body(mesh_object("Drum", "cylinder", location=(2, 0, 2), rotation=(math.pi / 2, 0, 0), radius=0.3,
                               depth=0.4), shape="CYLINDER")
    add_rigid_body(mesh_object("Cone", "cone", location=(3, 0, 2), radius1=0.25, depth=0.5), shape="CONE")
    hull_points = [(0.2, 0, 0), (-0.2, 0, 0), (0, 0.15, 0), (0, -0.15, 0), (0, 0, 0.25), (0, 0, -0.1)]
    add_rigid_body(mesh_from_data("Rock", hull_points, [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4)],
                                  location=(4, 0, 2), scale=(2, 1, 1)), shape="CONVEX_HULL")
    ramp_vertices = [(-1, -1, 0), (1, -1, 0.5), (1, 1, 0.5), (-1, 1, 0)]
    add_rigid_body(mesh_from_data("Ramp", ramp_vertices, [(0, 1, 2, 3)], location=(0, 3, 0)), "PASSIVE", "MESH")
    # A compound: a parent with two rigid-body children parented to it.
    letter = add_rigid_body(mesh_object("Letter", location=(5, 0, 2), scale=(0.1, 0.1, 0.1)), shape="COMPOUND")
    stem = add_rigid_body(mesh_object("Stem", location=(5, 0, 2.3), scale=(0.05, 0.05, 0.25)), shape="BOX")
    dot = add_rigid_body(mesh_object("Dot", "uv_sphere", location=(5.2, 0, 2), radius=0.06), shape="SPHERE")
    for child in (stem, dot):
        child.parent = letter
        child.matrix_parent_inverse = letter.matrix_world.inverted()
    bpy.context.view_layer.update()

    scene, bodies, _, problems = exported()
    # The one approximation this scene meets: ODE's cylinder contacts against a MESH.
    assert problems == ["Drum: collision_shape: a CYLINDER against the MESH shape of 'Ramp' may tilt or roll "
                        "where Blender's rests"]
    assert sorted(bodies) == ["Ball", "Cone", "Drum", "Ground", "Letter", "Pill", "Ramp", "Rock"]
    assert bodies["Ground"]["shape"] == {"type": "BOX", "half_extents_m": approx([5, 4, 0.1])}
    assert bodies["Ground"]["type"] == "PASSIVE"
    assert bodies["Ground"]["initial"]["location"] == approx([0, 0, -0.1])
    assert bodies["Ball"]["shape"] == {"type": "SPHERE", "radius_m": approx(1.0)}
    # Capsule: radius 0.2; Blender's cylinder part is 2 * (0.5 - 0.2) unscaled, stretched by Z scale 2,
    # plus both caps: 1.2 + 0.4.
    assert bodies["Pill"]["shape"] == {"type": "CAPSULE", "radius_m": approx(0.2), "height_m": approx(1.6)}
    assert bodies["Drum"]["shape"] == {"type": "CYLINDER", "radius_m": approx(0.3), "height_m": approx(0.4)}
    assert bodies["Drum"]["initial"]["rotation"] == approx(quat_of_euler((math.pi / 2, 0, 0)))
    assert bodies["Cone"]["shape"] == {"type": "CONE", "radius_m": approx(0.25), "height_m": approx(0.5)}
    rock = bodies["Rock"]["shape"]
    assert rock["type"] == "CONVEX_HULL"
    assert rock["vertices_m"] == approx([c * s for p in hull_points for c, s in zip(p, (2, 1, 1))])
    ramp = bodies["Ramp"]["shape"]
    assert ramp["type"] == "MESH"
    assert ramp["vertices_m"] == approx([c for p in ramp_vertices for c in p])
    assert len(ramp["triangles"]) == 6 and set(ramp["triangles"]) == {0, 1, 2, 3}
    compound = bodies["Letter"]["shape"]
    assert compound["type"] == "COMPOUND"
    children = {c["type"]: c for c in compound["children"]}
    assert children["BOX"]["half_extents_m"] == approx([0.05, 0.05, 0.25])
    assert children["BOX"]["offset"]["location"] == approx([0, 0, 0.3])
    assert children["SPHERE"]["radius_m"] == approx(0.06, rel=1e-3)
    assert children["SPHERE"]["offset"]["location"] == approx([0.2, 0, 0])
    assert scene["format"] == "mwb-scene" and scene["version"] == 1
    assert ground.rigid_body is not None


def test_body_settings_world_and_variation():
    scene = bpy.context.scene
    crate = add_rigid_body(mesh_object("Crate", location=(1, 2, 3), rotation=(0.1, 0.2, 0.3)), mass=2.5,
                           friction=0.3, restitution=0.7, use_margin=True, collision_margin=0.01,
                           linear_damping=0.2, angular_damping=0.3)
    collections = [False] * 20
    for k in (0, 3, 19):
        collections[k] = True
    crate.rigid_body.collision_collections = collections
    off = add_rigid_body(mesh_object("Off", location=(4, 0, 0)), enabled=False)
    v = crate.mwb_variation
    v.location_min, v.location_max = (-0.1, -0.2, 0), (0.1, 0.2, 0.3)
    v.rotation_min, v.rotation_max = (0, 0, -0.5), (0, 0, 0.5)
    v.linear_velocity_min, v.linear_velocity_max = (1, 0, 0), (2, 0, 0)
    v.angular_velocity_min, v.angular_velocity_max = (0, -3, 0), (0, 3, 0)
    rbw = scene.rigidbody_world
    rbw.time_scale, rbw.substeps_per_frame, rbw.solver_iterations = 0.5, 20, 30
    rbw.point_cache.frame_start, rbw.point_cache.frame_end = 5, 80
    scene.gravity = (0, 1, -5)
    scene.render.fps, scene.render.fps_base = 30, 1.0
    # An animated passive platform: rises 1 m between frames 5 and 15.
    platform = add_rigid_body(mesh_object("Platform", location=(0, 0, 0)), "PASSIVE", kinematic=True)
    for frame, z in ((5, 0.0), (15, 1.0)):
        platform.location.z = z
        platform.keyframe_insert("location", index=2, frame=frame)

    world, bodies, _, problems = exported()
    assert problems == []
    assert world["world"] == {"gravity": approx([0, 1, -5]), "time_scale": approx(0.5), "substeps_per_frame": 20,
                              "solver_iterations": 30, "frame_start": 5, "frame_end": 80, "fps": approx(30)}
    c = bodies["Crate"]
    assert (c["mass_kg"], c["friction"], c["restitution"]) == (approx(2.5), approx(0.3), approx(0.7))
    assert (c["use_margin"], c["collision_margin_m"]) == (True, approx(0.01))
    assert (c["linear_damping"], c["angular_damping"]) == (approx(0.2), approx(0.3))
    assert c["collision_collections"] == 1 + 8 + 2 ** 19
    assert c["initial"]["location"] == approx([1, 2, 3])
    assert c["initial"]["rotation"] == approx(quat_of_euler((0.1, 0.2, 0.3)))
    assert c["enabled"] is True and bodies["Off"]["enabled"] is False
    assert c["variation"] == {"location_min_m": approx([-0.1, -0.2, 0]), "location_max_m": approx([0.1, 0.2, 0.3]),
                              "rotation_min_rad": approx([0, 0, -0.5]), "rotation_max_rad": approx([0, 0, 0.5]),
                              "linear_velocity_min": approx([1, 0, 0]), "linear_velocity_max": approx([2, 0, 0]),
                              "angular_velocity_min": approx([0, -3, 0]),
                              "angular_velocity_max": approx([0, 3, 0])}
    assert "variation" not in bodies["Off"]
    p = bodies["Platform"]
    assert p["kinematic"] is True
    animation = p["animation"]
    assert animation["times_s"] == approx([(f - 5) / 30 for f in range(5, 81)])
    z = [t["location"][2] for t in animation["transforms"]]
    assert z[0] == approx(0) and z[10] == approx(1) and z[-1] == approx(1)
    assert all(b >= a - 1e-9 for a, b in zip(z, z[1:]))
    assert off.rigid_body.enabled is False


def _set(rbc, **values):
    for key, value in values.items():
        setattr(rbc, key, value)


def test_every_constraint_type_with_limits_springs_and_motors():
    a = add_rigid_body(mesh_object("A", location=(0, 0, 1), scale=(0.2, 0.2, 0.2)), "PASSIVE")
    b = add_rigid_body(mesh_object("B", location=(1, 0, 1), scale=(0.2, 0.2, 0.2)))
    fixed = add_constraint("Fixed", "FIXED", a, b, location=(0.5, 0, 1))
    _set(fixed.rigid_body_constraint, use_breaking=True, breaking_threshold=3.5, disable_collisions=False)
    add_constraint("Point", "POINT", None, b, location=(1, 0, 1.2))
    hinge = add_constraint("Hinge", "HINGE", a, b, location=(0.5, 0, 1), rotation=(0, math.pi / 2, 0))
    _set(hinge.rigid_body_constraint, use_limit_ang_z=True, limit_ang_z_lower=-1.0, limit_ang_z_upper=0.5)
    slider = add_constraint("Slider", "SLIDER", a, b)
    _set(slider.rigid_body_constraint, use_limit_lin_x=True, limit_lin_x_lower=-0.3, limit_lin_x_upper=0.4)
    piston = add_constraint("Piston", "PISTON", a, b)
    _set(piston.rigid_body_constraint, use_limit_lin_x=True, limit_lin_x_lower=-0.1, limit_lin_x_upper=0.2,
         use_limit_ang_x=True, limit_ang_x_lower=-0.7, limit_ang_x_upper=0.8)
    generic = add_constraint("Generic", "GENERIC", a, b)
    rbc = generic.rigid_body_constraint
    for axis in "xyz":
        _set(rbc, **{f"use_limit_lin_{axis}": True, f"limit_lin_{axis}_lower": 0.0, f"limit_lin_{axis}_upper": 0.0})
    _set(rbc, use_limit_ang_x=True, limit_ang_x_lower=-1.5, limit_ang_x_upper=0.1, use_limit_ang_z=True,
         limit_ang_z_lower=-0.2, limit_ang_z_upper=0.3)
    spring = add_constraint("Spring", "GENERIC_SPRING", a, b)
    rbc = spring.rigid_body_constraint
    for axis in "xyz":
        _set(rbc, **{f"use_limit_lin_{axis}": True, f"limit_lin_{axis}_lower": 0.0, f"limit_lin_{axis}_upper": 0.0})
    _set(rbc, spring_type="SPRING2", use_spring_ang_x=True, spring_stiffness_ang_x=5.0, spring_damping_ang_x=0.25,
         use_spring_ang_y=True, spring_stiffness_ang_y=7.0, spring_damping_ang_y=0.5)
    motor = add_constraint("Motor", "MOTOR", a, b)
    _set(motor.rigid_body_constraint, use_motor_ang=True, motor_ang_target_velocity=4.0, motor_ang_max_impulse=0.05,
         use_motor_lin=True, motor_lin_target_velocity=-1.0, motor_lin_max_impulse=2.0, enabled=False)

    _, _, constraints, problems = exported()
    # Breaking and spring damping are the settings here the engine approximates: each breakable
    # constraint says so, and the damped spring.
    breaking = [line for line in problems if ": breaking_threshold: breaking is approximated" in line]
    assert len(breaking) == sum(1 for c in constraints.values() if c["breakable"]) > 0
    assert sorted(set(problems) - set(breaking)) == [
        "Spring: spring_damping_ang: angular spring damping is approximated: small swings settle sooner than in "
        "Blender"]
    assert sorted(constraints) == ["Fixed", "Generic", "Hinge", "Motor", "Piston", "Point", "Slider", "Spring"]
    f = constraints["Fixed"]
    assert (f["type"], f["body_a"], f["body_b"]) == ("FIXED", "A", "B")
    assert (f["breakable"], f["breaking_threshold"], f["disable_collisions"]) == (True, approx(3.5), False)
    assert f["frame"]["location"] == approx([0.5, 0, 1])
    assert (constraints["Point"]["body_a"], constraints["Point"]["body_b"]) == ("", "B")
    h = constraints["Hinge"]
    assert h["angular_limits"] == {"enabled": [False, False, True], "lower": approx([0, 0, -1.0]),
                                   "upper": approx([0, 0, 0.5])}
    assert h["frame"]["rotation"] == approx(quat_of_euler((0, math.pi / 2, 0)))
    assert constraints["Slider"]["linear_limits"] == {"enabled": [True, False, False], "lower": approx([-0.3, 0, 0]),
                                                      "upper": approx([0.4, 0, 0])}
    p = constraints["Piston"]
    assert p["linear_limits"]["lower"] == approx([-0.1, 0, 0]) and p["linear_limits"]["upper"] == approx([0.2, 0, 0])
    assert p["angular_limits"] == {"enabled": [True, False, False], "lower": approx([-0.7, 0, 0]),
                                   "upper": approx([0.8, 0, 0])}
    g = constraints["Generic"]
    assert g["linear_limits"] == {"enabled": [True] * 3, "lower": approx([0, 0, 0]), "upper": approx([0, 0, 0])}
    angular = g["angular_limits"]
    assert angular["enabled"] == [True, False, True]
    # A disabled axis keeps whatever Blender stores; only the enabled ones are compared.
    assert [angular["lower"][k] for k in (0, 2)] == approx([-1.5, -0.2])
    assert [angular["upper"][k] for k in (0, 2)] == approx([0.1, 0.3])
    s = constraints["Spring"]["angular_springs"]
    assert s == {"enabled": [True, True, False], "stiffness": approx([5, 7, s["stiffness"][2]]),
                 "damping": approx([0.25, 0.5, s["damping"][2]])}
    m = constraints["Motor"]
    assert (m["motor_angular_enabled"], m["motor_linear_enabled"], m["enabled"]) == (True, True, False)
    assert (m["motor_angular_target_velocity"], m["motor_angular_max_impulse"]) == (approx(4), approx(0.05))
    assert (m["motor_linear_target_velocity"], m["motor_linear_max_impulse"]) == (approx(-1), approx(2))


def test_unsupported_settings_are_listed_by_object_and_setting():
    ensure_world()
    scene = bpy.context.scene
    scene.rigidbody_world.use_split_impulse = True
    add_rigid_body(mesh_object("Ground", location=(0, 0, -1), scale=(5, 5, 1)), "PASSIVE")
    add_rigid_body(mesh_object("Mirrored", location=(0, 0, 1), scale=(-1, 1, 1)))
    add_rigid_body(mesh_object("Egg", "uv_sphere", location=(2, 0, 1), scale=(1, 1, 2)), shape="SPHERE")
    add_rigid_body(mesh_object("Sleepy", location=(4, 0, 1)), use_deactivation=True)
    add_rigid_body(mesh_object("Statue", "monkey", location=(6, 0, 1)), shape="MESH")
    a = add_rigid_body(mesh_object("A", location=(8, 0, 1)))
    free = add_constraint("Free", "GENERIC", a, None)
    free.rigid_body_constraint.use_limit_lin_x = False
    orphan = add_constraint("Orphan", "POINT", a, bpy.data.objects["Ground"])
    orphan.rigid_body_constraint.object2 = mesh_object("NotABody", location=(9, 0, 0))

    result, invalid = export.export_and_validate(bpy.context)
    assert invalid == []
    text = "\n".join(result.problems)
    for expected in ("Rigid Body World: use_split_impulse:", "Mirrored: scale: negative",
                     "Egg: scale: non-uniform scale on a SPHERE",
                     "Statue: collision_shape: MESH on an active body", "Free: linear limits:",
                     "Orphan: object2: 'NotABody' is not an exported rigid body"):
        assert expected in text, text
    bodies = {b["name"]: b for b in result.scene["bodies"]}
    assert bodies["Statue"]["shape"]["type"] == "CONVEX_HULL"
    # Deactivation is Bullet's sleeping, which the engine reproduces: exported, not warned about.
    assert "Sleepy:" not in text
    assert bodies["Sleepy"]["deactivation"] == {"enabled": True, "start_deactivated": False,
                                                "linear_speed": pytest.approx(0.4), "angular_speed": pytest.approx(0.5)}
    assert result.scene["constraints"] == []


def test_no_rigid_body_world_is_reported():
    result, invalid = export.export_and_validate(bpy.context)
    assert result.scene is None
    assert "rigid body world" in result.problems[0]


def test_animated_set_by_a_driver_or_the_nla_is_named_not_misread():
    # The add-on reads "Animated" from the object's own keys; a driver or an NLA strip that sets it
    # is named with the object, so the user knows why the engine does not follow it.
    ensure_world()
    add_rigid_body(mesh_object("Ground", location=(0, 0, -1), scale=(5, 5, 1)), "PASSIVE")
    driven = add_rigid_body(mesh_object("Driven", location=(0, 0, 1)))
    driver = driven.driver_add("rigid_body.kinematic").driver
    driver.expression = "frame < 10"
    layered = add_rigid_body(mesh_object("Layered", location=(3, 0, 1)))
    layered.rigid_body.kinematic = True
    layered.keyframe_insert("rigid_body.kinematic", frame=1)
    # Push Down: the keys move from the object's action into an NLA strip.
    action = layered.animation_data.action
    layered.animation_data.nla_tracks.new().strips.new("Throw", 1, action)
    layered.animation_data.action = None
    keyed = add_rigid_body(mesh_object("Keyed", location=(6, 0, 1)))
    keyed.keyframe_insert("rigid_body.kinematic", frame=1)

    result, invalid = export.export_and_validate(bpy.context)
    assert invalid == []
    text = "\n".join(result.problems)
    assert "Driven: kinematic: \"Animated\" set by a driver is not read" in text, text
    assert "Layered: kinematic: \"Animated\" set by the NLA is not read" in text, text
    assert "Keyed:" not in text, "an object's own keys are read without a warning"
