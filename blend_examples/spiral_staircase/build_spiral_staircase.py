"""Builds the spiral-staircase example: a simple articulated character tumbles down a three-turn
spiral staircase.

Goal: "the character falls all the way down the staircase without falling off". He is shoved off
the landing; a random run comes to rest within a few steps or goes over the low outer string and
falls to the ground, and only about one in fifty tumbles all the way down. The paper's user chained
rare events with refinement (18 refinements) to get him to the bottom, and culled runs where he slid
down on his back.

The character is 10 capsules and a sphere joined by 10 GENERIC_SPRING constraints: ball joints
(all three linear axes locked) with angular limits, and angular springs whose rest pose is the pose
he is built in, hands over his head. The springs are the "simple set-point controller": they pull
every joint back to the covering pose.

Run:  blender -b --factory-startup --python blend_examples/spiral_staircase/build_spiral_staircase.py -- OUT.blend
Everything is made from nothing with Blender's own rigid-body settings, plus the Many-Worlds
add-on's variation ranges and sampling settings (helpers in ../example_kit.py).
"""
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from example_kit import (  # noqa: E402
    box, camera_and_lights, capsule, constraint, cylinder, material, output_path, rigid_body, scene_settings,
    sphere, variation)

FPS = 24
FRAME_START, FRAME_END = 1, 960         # 40 s: long enough to tumble down all three turns
SUBSTEPS, SOLVER_ITERATIONS = 10, 20    # more iterations keep the joint chain stiff
WORLD_COUNT, SEED = 1000, 1

# staircase
TURNS, STEPS_PER_TURN, RISE = 3, 16, 0.22
STEP_COUNT = TURNS * STEPS_PER_TURN
COLUMN_RADIUS, STAIR_RADIUS, STEP_THICKNESS = 0.2, 1.2, 0.08   # 37° steep at the walking line (0.75 m)
TOP_ANGLE = math.radians(90)            # the first step below the landing; the stair turns clockwise going down
LANDING_STEPS = 3                        # the landing at the top is this many steps wide
TOP_Z = (STEP_COUNT + 1) * RISE          # the landing's top surface; the last step is one rise above the ground
TREAD_FRICTION = 0.4                     # sanded hardwood; with the clothed body 0.16 (Bullet multiplies them)
STRING_HEIGHT, STRING_THICKNESS, STRING_FRICTION = 0.22, 0.05, 0.3   # the outer string stands up past the treads

# character (metres, kilograms), built standing in a local frame: x right, y forward, z up, feet at 0
PART_MASS = {"Pelvis": 4.0, "Torso": 8.0, "Head": 2.5, "UpperArm": 1.2, "Forearm": 0.8, "Thigh": 2.5, "Shin": 1.5}
BODY_FRICTION, BODY_RESTITUTION = 0.4, 0.05
START_RADIUS = 0.75                      # the character stands this far from the axis, mid-tread
START_LEAN = math.radians(12)            # leaning forward over the first step, so he falls with no push
SHOVE = (0.5, 1.5)                       # m/s: the torso's push forward, down the stairs...
PUSH = (0.4, 0.4, 0.1)                   # m/s: ...its range widened by this either way on each world axis
SPIN = (0.5, 0.5, 0.5)                   # rad/s

# --- generic helpers ---------------------------------------------------------------------------

# --- staircase ----------------------------------------------------------------------------------

def step_angle(k):
    return TOP_ANGLE - k * 2 * math.pi / STEPS_PER_TURN


def step(name, angle, top_z, width_steps, mats):
    """A passive box tread from the column to the outer radius, `width_steps` treads wide at the rim."""
    arc = STAIR_RADIUS * 2 * math.pi / STEPS_PER_TURN * width_steps
    radial = STAIR_RADIUS - COLUMN_RADIUS + 0.05
    mid = (STAIR_RADIUS + COLUMN_RADIUS - 0.05) / 2
    tread = box(name, (radial, arc, STEP_THICKNESS),
                location=(mid * math.cos(angle), mid * math.sin(angle), top_z - STEP_THICKNESS / 2),
                rotation=(0, 0, angle), mat=mats["step"])
    rigid_body(tread, "PASSIVE", "BOX", friction=TREAD_FRICTION)


def string_piece(name, angle, top_z, width_steps, mats):
    """A passive piece of the outer string along a tread's outer edge, from the tread's underside
    to STRING_HEIGHT above it."""
    arc = STAIR_RADIUS * 2 * math.pi / STEPS_PER_TURN * width_steps
    r = STAIR_RADIUS - STRING_THICKNESS / 2
    height = STRING_HEIGHT + STEP_THICKNESS
    piece = box(name, (STRING_THICKNESS, arc, height),
                location=(r * math.cos(angle), r * math.sin(angle), top_z - STEP_THICKNESS + height / 2),
                rotation=(0, 0, angle), mat=mats["string"])
    rigid_body(piece, "PASSIVE", "BOX", friction=STRING_FRICTION)


def build_staircase(mats):
    """Treads descending clockwise round a central column, three full turns, and the outer string
    standing 22 cm up past them, with no balustrade on it: the string turns a body sliding or
    rolling down with the stairs, one tumbling higher goes over it, and falling off is exactly what
    the user wants to avoid."""
    column = cylinder("Column", COLUMN_RADIUS, TOP_Z + 1.0, location=(0, 0, (TOP_Z + 1.0) / 2), mat=mats["column"])
    rigid_body(column, "PASSIVE", "CYLINDER", friction=0.4)
    ground = box("Ground", (12, 12, 0.2), location=(0, 0, -0.1), mat=mats["ground"])
    rigid_body(ground, "PASSIVE", "BOX", friction=0.8)
    landing_angle = step_angle(-(LANDING_STEPS + 1) / 2)
    step("Landing", landing_angle, TOP_Z, LANDING_STEPS, mats)
    for k in range(STEP_COUNT):
        step(f"Step{k + 1:02d}", step_angle(k), TOP_Z - (k + 1) * RISE, 1.05, mats)
        string_piece(f"String{k + 1:02d}", step_angle(k), TOP_Z - (k + 1) * RISE, 1.05, mats)


# --- character ----------------------------------------------------------------------------------

def joints_local():
    """Joint positions of the covering-the-head pose in the character's local frame."""
    j = {"waist": (0, 0, 0.76), "neck": (0, 0, 1.16), "head": (0, 0.01, 1.27)}
    for side, s in (("L", -1), ("R", 1)):
        j[f"shoulder{side}"] = (s * 0.19, 0, 1.06)
        j[f"elbow{side}"] = (s * 0.24, 0.2, 1.2)      # upper arms forward and up...
        j[f"hand{side}"] = (s * 0.1, 0.17, 1.4)       # ...forearms crossing in front of the face
        j[f"hip{side}"] = (s * 0.09, 0, 0.64)
        j[f"knee{side}"] = (s * 0.09, 0.03, 0.35)
        j[f"ankle{side}"] = (s * 0.09, 0, 0.06)
    return {k: Vector(v) for k, v in j.items()}


def limb(name, start, end, radius, mass, placement, mats):
    """A capsule whose axis runs from joint `start` to joint `end` (local points), its caps reaching a
    radius beyond both, placed in the world by `placement`."""
    axis = end - start
    local = Matrix.Translation((start + end) / 2) @ Vector((0, 0, 1)).rotation_difference(axis).to_matrix().to_4x4()
    world = placement @ local
    part = capsule(name, radius, axis.length + 2 * radius, location=world.to_translation(),
                   rotation=world.to_euler(), mat=mats["body"])
    return part, mass


def build_character(mats):
    """11 bodies, 10 joints. Collision collections: every part has its own, the staircase has all of
    them, so the character hits the stairs but not himself (his forearms sit close to his head)."""
    heading = step_angle(-0.5) + math.pi             # facing clockwise, down the stairs
    feet = Vector((START_RADIUS * math.cos(step_angle(-0.7)), START_RADIUS * math.sin(step_angle(-0.7)),
                   TOP_Z + 0.005))
    placement = Matrix.Translation(feet) @ Matrix.Rotation(heading, 4, "Z") @ Matrix.Rotation(-START_LEAN, 4, "X")
    j = joints_local()
    parts = {
        "Pelvis": limb("Pelvis", j["hipL"] + Vector((0, 0, 0.04)), j["hipR"] + Vector((0, 0, 0.04)), 0.08,
                       PART_MASS["Pelvis"], placement, mats),
        "Torso": limb("Torso", j["waist"] + Vector((0, 0, 0.08)), j["neck"] - Vector((0, 0, 0.1)), 0.11,
                      PART_MASS["Torso"], placement, mats),
    }
    head_world = placement @ j["head"]
    parts["Head"] = (sphere("Head", 0.1, location=head_world, mat=mats["head"]), PART_MASS["Head"])
    for side in ("L", "R"):
        parts[f"UpperArm{side}"] = limb(f"UpperArm{side}", j[f"shoulder{side}"], j[f"elbow{side}"], 0.045,
                                        PART_MASS["UpperArm"], placement, mats)
        parts[f"Forearm{side}"] = limb(f"Forearm{side}", j[f"elbow{side}"], j[f"hand{side}"], 0.04,
                                       PART_MASS["Forearm"], placement, mats)
        parts[f"Thigh{side}"] = limb(f"Thigh{side}", j[f"hip{side}"], j[f"knee{side}"], 0.06,
                                     PART_MASS["Thigh"], placement, mats)
        parts[f"Shin{side}"] = limb(f"Shin{side}", j[f"knee{side}"], j[f"ankle{side}"], 0.05,
                                    PART_MASS["Shin"], placement, mats)
    for i, (name, (obj, mass)) in enumerate(parts.items()):
        shape = "SPHERE" if name == "Head" else "CAPSULE"
        rigid_body(obj, "ACTIVE", shape, mass=mass, friction=BODY_FRICTION, restitution=BODY_RESTITUTION,
                   damping=(0.05, 0.2), collections={1 + i})
    body = {name: obj for name, (obj, _) in parts.items()}
    build_joints(body, j, placement)
    # Only the torso varies, and only in velocity: a shove down the stairs. Offsetting the location of
    # one part of a jointed body would just tear the joint; a velocity is passed on to the rest through
    # the joints. The range is not centred on zero: every world starts with a shove forward.
    forward = placement.to_3x3() @ Vector((0, 1, 0))
    forward.z = 0
    centre = forward.normalized() * (SHOVE[0] + SHOVE[1]) / 2
    half = Vector(PUSH) + Vector([abs(c) for c in forward.normalized() * (SHOVE[1] - SHOVE[0]) / 2])
    shove_range(body["Torso"], centre - half, centre + half, SPIN)


# (name, parent, child, joint, angular limit x/y/z in radians, spring stiffness N*m/rad)
JOINTS = [("Waist", "Pelvis", "Torso", "waist", (0.6, 0.4, 0.5), 300.0),
          ("Neck", "Torso", "Head", "neck", (0.6, 0.4, 0.8), 60.0)]
for _side in ("L", "R"):
    JOINTS += [(f"Shoulder{_side}", "Torso", f"UpperArm{_side}", f"shoulder{_side}", (1.0, 0.8, 0.8), 40.0),
               (f"Elbow{_side}", f"UpperArm{_side}", f"Forearm{_side}", f"elbow{_side}", (1.0, 0.2, 0.3), 20.0),
               (f"Hip{_side}", "Pelvis", f"Thigh{_side}", f"hip{_side}", (1.2, 0.5, 0.4), 200.0),
               (f"Knee{_side}", f"Thigh{_side}", f"Shin{_side}", f"knee{_side}", (1.2, 0.15, 0.2), 120.0)]
SPRING_DAMPING = 2.0                     # N*m*s/rad with SPRING2 springs: settles a limb within a fraction of a second


def build_joints(body, j, placement):
    """GENERIC_SPRING ball joints in the character's frame (X: pitch, Y: roll, Z: twist), limits
    symmetric about the built pose, springs pulling back to it."""
    orientation = placement.to_euler()
    for name, parent, child, at, limits, stiffness in JOINTS:
        settings = {"spring_type": "SPRING2"}
        for axis in "xyz":
            settings[f"use_limit_lin_{axis}"] = True                 # a ball joint: no linear freedom
            settings[f"limit_lin_{axis}_lower"] = settings[f"limit_lin_{axis}_upper"] = 0.0
        for axis, limit in zip("xyz", limits):
            settings[f"use_limit_ang_{axis}"] = True
            settings[f"limit_ang_{axis}_lower"], settings[f"limit_ang_{axis}_upper"] = -limit, limit
            settings[f"use_spring_ang_{axis}"] = True
            settings[f"spring_stiffness_ang_{axis}"] = stiffness
            settings[f"spring_damping_ang_{axis}"] = SPRING_DAMPING
        constraint(f"Joint{name}", "GENERIC_SPRING", body[parent], body[child], location=placement @ j[at],
                   rotation=orientation, **settings)


def shove_range(obj, low, high, spin):
    """The add-on's variation ranges with a linear velocity from `low` to `high` (world axes, m/s)
    and an angular velocity of ±spin (rad/s)."""
    variation(obj, angular_velocity=spin, linear_velocity_range=(low, high))


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "spiral_staircase"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    mats = {k: material(k, rgb) for k, rgb in {
        "ground": (0.35, 0.38, 0.35), "column": (0.7, 0.68, 0.62), "step": (0.55, 0.42, 0.3),
        "string": (0.3, 0.22, 0.16),
        "body": (0.2, 0.45, 0.8), "head": (0.95, 0.75, 0.6)}.items()}
    build_staircase(mats)
    build_character(mats)
    camera_and_lights(location=(13.0, -13.0, TOP_Z / 2 + 4.0), target=(0, 0, TOP_Z / 2 - 0.3), lens=30)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
