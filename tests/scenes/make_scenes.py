#!/usr/bin/python3
"""Writes the engine's test and benchmark scenes as scene JSON (format "mwb-scene" v1).

Run from anywhere: /usr/bin/python3 tests/scenes/make_scenes.py
The JSON files are committed; this script is how they were made and how to change them.
"""
import json
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.join(os.path.dirname(HERE), "bench")


def quat_axis_angle(axis, angle):
    s = math.sin(angle / 2)
    return [math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s]


def body(name, shape, location, body_type="ACTIVE", **fields):
    out = {"name": name, "type": body_type, "shape": shape, "initial": {"location": list(location)}}
    out.update(fields)
    return out


def box(hx, hy, hz):
    return {"type": "BOX", "half_extents_m": [hx, hy, hz]}


def ground(half=10.0):
    return body("Ground", box(half, half, 0.5), (0, 0, -0.5), "PASSIVE")


def tumble(spread=0.1, spin=2.0):
    return {"location_min_m": [-spread, -spread, 0], "location_max_m": [spread, spread, spread],
            "angular_velocity_min": [-spin] * 3, "angular_velocity_max": [spin] * 3}


def scene(name, bodies, constraints=(), frame_end=121):
    return {"format": "mwb-scene", "version": 1, "name": name,
            "world": {"fps": 24, "frame_start": 1, "frame_end": frame_end},
            "bodies": bodies, "constraints": list(constraints)}


def ramp_mesh():
    # A chute: a tilted floor with two side rails, as a passive triangle mesh.
    v = [-2, -0.6, 1.2, 2, -0.6, 0.2, 2, 0.6, 0.2, -2, 0.6, 1.2,
         -2, -0.6, 1.5, 2, -0.6, 0.5, -2, 0.6, 1.5, 2, 0.6, 0.5]
    t = [0, 1, 2, 0, 2, 3, 0, 4, 5, 0, 5, 1, 3, 2, 7, 3, 7, 6]
    return {"type": "MESH", "vertices_m": v, "triangles": t}


def quickstart():
    bodies = [ground(),
              body("Chute", ramp_mesh(), (0, 0, 0), "PASSIVE", friction=0.4),
              body("Marble", {"type": "SPHERE", "radius_m": 0.12}, (-1.7, 0, 1.5), restitution=0.5,
                   variation=tumble(0.05, 0)),
              body("Die", box(0.1, 0.1, 0.1), (-1.2, 0.1, 1.6), variation=tumble(0.1, 4)),
              body("Cone", {"type": "CONE", "radius_m": 0.15, "height_m": 0.3}, (-0.7, -0.1, 1.5),
                   variation=tumble(0.1, 3)),
              body("Can", {"type": "CYLINDER", "radius_m": 0.1, "height_m": 0.3}, (1.2, 0, 0.5),
                   variation=tumble(0.05, 1))]
    return scene("quickstart", bodies, frame_end=97)


def all_shapes_and_joints():
    hull = [0.2, 0, 0, -0.2, 0, 0, 0, 0.15, 0, 0, -0.15, 0, 0, 0, 0.25, 0, 0, -0.1, 0.05, 0.05, 0.05]
    letter = {"type": "COMPOUND", "children": [
        dict(box(0.05, 0.05, 0.25), offset={"location": [-0.1, 0, 0]}),
        dict(box(0.1, 0.05, 0.05), offset={"location": [0.05, 0, 0.2]}),
        dict({"type": "SPHERE", "radius_m": 0.06}, offset={"location": [0.1, 0, -0.2]})]}
    bodies = [ground(),
              body("Ramp", ramp_mesh(), (0, 3, 0), "PASSIVE"),
              body("Crate", box(0.2, 0.2, 0.2), (0, 0, 1), variation=tumble()),
              body("Ball", {"type": "SPHERE", "radius_m": 0.2}, (0.8, 0, 1.2), restitution=0.6, variation=tumble()),
              body("Pill", {"type": "CAPSULE", "radius_m": 0.1, "height_m": 0.5}, (-0.8, 0, 1.2), variation=tumble()),
              body("Drum", {"type": "CYLINDER", "radius_m": 0.2, "height_m": 0.3}, (0, 0.8, 1.2), variation=tumble()),
              body("Cone", {"type": "CONE", "radius_m": 0.2, "height_m": 0.4}, (0, -0.8, 1.2), variation=tumble()),
              body("Rock", {"type": "CONVEX_HULL", "vertices_m": hull}, (-1.5, 3, 1.6), variation=tumble()),
              body("Letter", letter, (0.8, 0.8, 1.6), variation=tumble()),
              body("Post", box(0.05, 0.05, 1), (3, 0, 1), "PASSIVE"),
              body("Door", box(0.4, 0.03, 0.6), (3.45, 0, 1), angular_damping=0.1,
                   initial_angular_velocity=[0, 0, 1.5]),
              body("Rail", box(1.5, 0.05, 0.05), (3, -2, 1), "PASSIVE"),
              body("Carriage", box(0.1, 0.1, 0.1), (3, -2, 1.2), initial_linear_velocity=[1, 0, 0]),
              body("Plunger", box(0.3, 0.05, 0.05), (-3, -2, 1.2), initial_linear_velocity=[0.5, 0, 0],
                   initial_angular_velocity=[3, 0, 0]),
              body("UpperArm", {"type": "CAPSULE", "radius_m": 0.06, "height_m": 0.4}, (-3, 0, 2.2)),
              body("LowerArm", {"type": "CAPSULE", "radius_m": 0.05, "height_m": 0.35}, (-3, 0, 1.77)),
              body("Spring", box(0.1, 0.1, 0.1), (-3, 2, 1.5), initial_angular_velocity=[2, 0, 0]),
              body("Wheel", {"type": "CYLINDER", "radius_m": 0.3, "height_m": 0.1}, (0, -3, 0.5)),
              body("Lamp", {"type": "SPHERE", "radius_m": 0.15}, (2, 2, 2.5), mass_kg=3),
              body("Platform", box(0.5, 0.5, 0.05), (-1.5, -1.5, 0.05), "PASSIVE", kinematic=True,
                   animation={"times_s": [0, 1, 2], "transforms": [
                       {"location": [-1.5, -1.5, 0.05]}, {"location": [-1.5, -1.5, 0.6]},
                       {"location": [-1.5, -1.5, 0.6], "rotation": quat_axis_angle([0, 0, 1], 0.8)}]}),
              body("Rider", box(0.1, 0.1, 0.1), (-1.5, -1.5, 0.2))]
    lock = {"enabled": [True, True, True], "lower": [0, 0, 0], "upper": [0, 0, 0]}
    constraints = [
        {"name": "DoorHinge", "type": "HINGE", "body_a": "Post", "body_b": "Door",
         "frame": {"location": [3.05, 0, 1]},
         "angular_limits": {"enabled": [False, False, True], "lower": [0, 0, -1.2], "upper": [0, 0, 1.2]}},
        {"name": "Track", "type": "SLIDER", "body_a": "Rail", "body_b": "Carriage", "frame": {"location": [3, -2, 1.2]},
         "linear_limits": {"enabled": [True, False, False], "lower": [-1, 0, 0], "upper": [1, 0, 0]}},
        {"name": "Bore", "type": "PISTON", "body_a": "Plunger", "frame": {"location": [-3, -2, 1.2]},
         "linear_limits": {"enabled": [True, False, False], "lower": [-0.5, 0, 0], "upper": [0.5, 0, 0]}},
        {"name": "Shoulder", "type": "POINT", "body_a": "UpperArm", "frame": {"location": [-3, 0, 2.45]}},
        {"name": "Elbow", "type": "GENERIC", "body_a": "UpperArm", "body_b": "LowerArm",
         "frame": {"location": [-3, 0, 1.98]}, "linear_limits": lock,
         "angular_limits": {"enabled": [True, True, True], "lower": [-1.5, -0.1, -0.1], "upper": [0.1, 0.1, 0.1]}},
        {"name": "Coil", "type": "GENERIC_SPRING", "body_a": "Spring", "frame": {"location": [-3, 2, 1.5]},
         "linear_limits": lock,
         "angular_springs": {"enabled": [True, True, True], "stiffness": [5, 5, 5], "damping": [0.1, 0.1, 0.1]}},
        {"name": "Drive", "type": "MOTOR", "body_a": "Ground", "body_b": "Wheel", "frame": {"location": [0, -3, 0.5]},
         "motor_angular_enabled": True, "motor_angular_target_velocity": 4, "motor_angular_max_impulse": 0.05},
        {"name": "Axle", "type": "HINGE", "body_a": "Ground", "body_b": "Wheel",
         "frame": {"location": [0, -3, 0.5], "rotation": quat_axis_angle([0, 1, 0], math.pi / 2)}},
        {"name": "Weld", "type": "FIXED", "body_a": "Crate", "body_b": "Ball", "enabled": False},
        {"name": "LampCord", "type": "POINT", "body_a": "Lamp", "frame": {"location": [2, 2, 2.9]},
         "breakable": True, "breaking_threshold": 0.05}]
    return scene("all_shapes_and_joints", bodies, constraints, frame_end=97)


def pile(count=50):
    wall = 1.6
    bodies = [ground()]
    for k, (x, y, hx, hy) in enumerate([(-wall, 0, 0.1, wall), (wall, 0, 0.1, wall),
                                        (0, -wall, wall, 0.1), (0, wall, wall, 0.1)]):
        bodies.append(body(f"Wall{k}", box(hx, hy, 1.5), (x, y, 1.5), "PASSIVE"))
    for i in range(count):
        layer, cell = divmod(i, 16)
        x = -1.05 + 0.7 * (cell % 4)
        y = -1.05 + 0.7 * (cell // 4)
        bodies.append(body(f"Box{i:02d}", box(0.2, 0.2, 0.2), (x, y, 0.5 + 0.6 * layer), variation=tumble(0.08, 3)))
    return scene("pile50", bodies, frame_end=121)


def chain(links=10):
    bodies = [body("Anchor", box(0.1, 0.1, 0.1), (0, 0, 3), "PASSIVE")]
    constraints = []
    for i in range(links):
        name = f"Link{i}"
        bodies.append(body(name, {"type": "CAPSULE", "radius_m": 0.04, "height_m": 0.3},
                           (0.25 * (i + 1), 0, 3), initial={"location": [0.25 * (i + 1), 0, 3],
                                                            "rotation": quat_axis_angle([0, 1, 0], math.pi / 2)},
                           variation={"angular_velocity_min": [0, -0.5, 0], "angular_velocity_max": [0, 0.5, 0]}))
        constraints.append({"name": f"Joint{i}", "type": "POINT", "body_a": bodies[-2]["name"], "body_b": name,
                            "frame": {"location": [0.25 * i + 0.125, 0, 3]}})
    bodies.append(ground())
    return scene("chain", bodies, constraints, frame_end=121)


def f32(x):
    """A coordinate as Blender stores it (32-bit float)."""
    return struct.unpack("f", struct.pack("f", x))[0]


def hull(points):
    return {"type": "CONVEX_HULL", "vertices_m": [f32(c) for p in points for c in p]}


def cube_points(half):
    return [(sx * half, sy * half, sz * half) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]


def uv_sphere_points(radius, segments=32, rings=16):
    points = [(0, 0, radius), (0, 0, -radius)]
    for j in range(1, rings):
        theta = math.pi * j / rings
        for i in range(segments):
            phi = 2 * math.pi * i / segments
            points.append((radius * math.sin(theta) * math.cos(phi), radius * math.sin(theta) * math.sin(phi),
                           radius * math.cos(theta)))
    return points


def cylinder_points(radius, depth, segments=32):
    return [(radius * math.cos(2 * math.pi * i / segments), radius * math.sin(2 * math.pi * i / segments), z)
            for z in (-depth / 2, depth / 2) for i in range(segments)]


def lathed_bottle_points(segments=16, rings=40):
    """A bottle as Spin makes it from a profile: each ring closes on a duplicate of its first vertex
    (the seam), the profile starts and ends on the axis, and the origin is at the base."""
    points = [(0, 0, 0)]
    for k in range(rings + 1):
        z = 0.3 * k / rings
        shoulder = math.cos(min(1.0, max(0.0, (z - 0.15) / 0.08)) * math.pi / 2)
        r = 0.04 + z if z < 0.01 else 0.015 + 0.035 * shoulder * shoulder
        points += [(r * math.cos(2 * math.pi * i / segments), r * math.sin(2 * math.pi * i / segments), z)
                   for i in range(segments + 1)]
    return points + [(0, 0, 0.3)]


def voronoi_cells(half, seeds):
    """Cell Fracture's pieces of a box: each seed's Voronoi cell, as (centre, corners about it)."""
    cells = []
    for s in seeds:
        planes = [(n, half[a]) for a in range(3) for n in ([1 if k == a else 0 for k in range(3)],
                                                              [-1 if k == a else 0 for k in range(3)])]
        for o in seeds:
            if o is s:
                continue
            n = [o[k] - s[k] for k in range(3)]
            planes.append((n, sum(n[k] * (o[k] + s[k]) / 2 for k in range(3))))
        corners = []
        for i in range(len(planes)):
            for j in range(i + 1, len(planes)):
                for k in range(j + 1, len(planes)):
                    m = [planes[i][0], planes[j][0], planes[k][0]]
                    det = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                           + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
                    if abs(det) < 1e-12:
                        continue
                    d = [planes[i][1], planes[j][1], planes[k][1]]
                    x = []
                    for c in range(3):
                        mc = [[d[r] if col == c else m[r][col] for col in range(3)] for r in range(3)]
                        x.append((mc[0][0] * (mc[1][1] * mc[2][2] - mc[1][2] * mc[2][1])
                                  - mc[0][1] * (mc[1][0] * mc[2][2] - mc[1][2] * mc[2][0])
                                  + mc[0][2] * (mc[1][0] * mc[2][1] - mc[1][1] * mc[2][0])) / det)
                    if all(sum(n[q] * x[q] for q in range(3)) <= dist + 1e-9 for n, dist in planes):
                        corners.append(x)
        lo = [min(c[q] for c in corners) for q in range(3)]
        hi = [max(c[q] for c in corners) for q in range(3)]
        centre = [(lo[q] + hi[q]) / 2 for q in range(3)]
        cells.append((centre, [[c[q] - centre[q] for q in range(3)] for c in corners]))
    return cells


def blender_defaults():
    """A scene as an animator builds it from Blender's defaults: every active body at the default
    shape (Convex Hull) with float coordinates, a Plane as passive MESH, a lathed bottle, and a
    Cell Fracture wall of a cube, knocked over by a UV sphere."""
    plane = {"type": "MESH", "vertices_m": [-10, -10, 0, 10, -10, 0, -10, 10, 0, 10, 10, 0], "triangles": [0, 1, 3, 0, 3, 2]}
    bodies = [body("Plane", plane, (0, 0, 0), "PASSIVE")]
    for i in range(6):
        bodies.append(body("Cube" if i == 0 else f"Cube.{i:03d}", hull(cube_points(0.25)),
                           (-1.5 + 0.6 * (i % 3), 1.2 + 0.6 * (i // 3), 0.25 + 0.6 * (i % 2)), variation=tumble(0.05, 1)))
    bodies.append(body("Sphere", hull(uv_sphere_points(0.3)), (-2.5, 0, 0.3), initial_linear_velocity=[6, 0, 0],
                       variation={"location_min_m": [0, -0.2, 0], "location_max_m": [0, 0.2, 0]}))
    bodies.append(body("Sphere.001", hull(uv_sphere_points(0.2)), (1.5, 1.5, 2.0), variation=tumble(0.3, 2)))
    bodies.append(body("Cylinder", hull(cylinder_points(0.2, 0.5)), (1.5, -1.5, 0.25), variation=tumble(0.05, 1)))
    for i in range(3):
        bodies.append(body(f"Bottle.{i:03d}", hull(lathed_bottle_points()), (1.2 + 0.25 * i, 0.2, 0.0)))
    rng_seeds = [(-0.35, -0.05, -0.3), (0.1, 0.05, -0.35), (0.3, -0.05, -0.1), (-0.2, 0.0, 0.05),
                 (0.25, 0.05, 0.3), (-0.3, -0.05, 0.35), (0.0, 0.0, 0.2), (-0.05, 0.05, -0.05)]
    for k, (centre, corners) in enumerate(voronoi_cells((0.5, 0.1, 0.5), rng_seeds)):
        bodies.append(body(f"Wall_cell.{k:03d}", hull(corners), (centre[0], centre[1] - 0.5, centre[2] + 0.5)))
    return scene("blender_defaults", bodies, frame_end=73)


def write(path, data):
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    write(os.path.join(HERE, "quickstart.json"), quickstart())
    write(os.path.join(HERE, "all_shapes_and_joints.json"), all_shapes_and_joints())
    write(os.path.join(HERE, "blender_defaults.json"), blender_defaults())
    write(os.path.join(BENCH, "pile50.json"), pile(50))
    write(os.path.join(BENCH, "chain.json"), chain(10))
