"""Builds the dice example: five dice are thrown onto a felt-topped table with low rails, tumble,
bounce off the rails and come to rest.

Goal: "the dice come up one, two, three, four, five": Die1 shows one, Die2 two, ... Die5 five,
over the last second. Each die is a pose part of the goal: its face's own axis (below) within
20 degrees of straight up.

Faces: every die is numbered the same way, each number facing along one of the die's own
(local) axes, opposite faces adding up to seven:

    six  +Z    one   -Z
    five +Y    two   -Y
    four +X    three -X

So "n up" means the die's local axis for n points at world +Z (one up: local -Z up).

Run:  blender -b --factory-startup --python blend_examples/dice/build_dice.py -- OUT.blend
The dice are bevelled cubes at Blender's default shape for a rigid body, Convex Hull; their pips
are shallow recesses, inside the hull, so they do not change how a die rolls. Everything else is
Blender's own rigid-body settings plus the add-on's variation ranges and sampling settings
(helpers in ../example_kit.py).
"""
import math
import os
import sys

import bmesh
import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from example_kit import (  # noqa: E402
    box, camera_and_lights, material, mesh_object, output_path, rigid_body, scene_settings, variation)

FPS = 24
FRAME_START, FRAME_END = 1, 96          # 4 s: nine dice in ten have stopped rolling by 1.3 s
SUBSTEPS, SOLVER_ITERATIONS = 10, 10    # 240 Hz, what the engine steps at too
WORLD_COUNT, SEED = 1000, 1

# The die's own axis each number faces along (see the module's docstring).
FACE_AXES = {6: (0, 0, 1), 1: (0, 0, -1), 5: (0, 1, 0), 2: (0, -1, 0), 4: (1, 0, 0), 3: (-1, 0, 0)}
# Pip places on a face's 3 x 3 grid, (column, row) from -1 to 1.
PIPS = {1: [(0, 0)], 2: [(-1, -1), (1, 1)], 3: [(-1, -1), (0, 0), (1, 1)],
        4: [(-1, -1), (-1, 1), (1, -1), (1, 1)], 5: [(-1, -1), (-1, 1), (0, 0), (1, -1), (1, 1)],
        6: [(-1, -1), (-1, 0), (-1, 1), (1, -1), (1, 0), (1, 1)]}

DIE_SIZE, DIE_BEVEL = 0.025, 0.0025     # metres: a large board-game die, its edges rounded
DIE_MASS = 0.018                        # kg, acrylic
PIP_RADIUS, PIP_DEPTH = 0.0023, 0.0006  # metres
# Body colour and pips of Die1 ... Die5: red, ivory, green, blue, yellow.
DICE = [((0.75, 0.08, 0.06), "pip_light"), ((0.92, 0.9, 0.84), "pip_dark"), ((0.1, 0.45, 0.2), "pip_light"),
        ((0.1, 0.2, 0.6), "pip_light"), ((0.9, 0.65, 0.1), "pip_dark")]

TABLE_TOP_Z = 0.75                      # the felt's top, metres above the floor
TABLE_LENGTH, TABLE_WIDTH = 0.9, 0.6    # inside the rails, along X and Y
RAIL_HEIGHT, RAIL_THICKNESS = 0.08, 0.05

# The throw: the dice leave the hand together above the left end of the table, 15 cm up, towards
# the far (right) rail; each world throws each die a little differently.
HAND = Vector((-0.3, 0.0, TABLE_TOP_Z + 0.15))
HAND_PLACES = [(0.0, 0.0), (0.0, -0.06), (0.0, 0.06), (-0.06, -0.03), (-0.06, 0.03)]
THROW_MIN, THROW_MAX = (1.0, -0.25, -0.3), (1.8, 0.25, 0.3)    # m/s, world axes
SPIN = 15.0                             # rad/s either way about each world axis
PLACE_SPREAD = 0.005                    # metres either way


def die_geometry(bm):
    """A cube DIE_SIZE wide with bevelled edges; on each flat face its number as round pips
    recessed PIP_DEPTH into it (material 1), inside the convex hull the die collides as."""
    bmesh.ops.create_cube(bm, size=DIE_SIZE)
    bmesh.ops.bevel(bm, geom=list(bm.edges), offset=DIE_BEVEL, segments=2, profile=0.5, affect="EDGES")
    for f in bm.faces:
        f.smooth = max(abs(c) for c in f.normal) < 0.999     # the rounded edges and corners
    half, flat = DIE_SIZE / 2, DIE_SIZE - 2 * DIE_BEVEL
    for number, axis in FACE_AXES.items():
        normal = Vector(axis)
        face = next(f for f in bm.faces
                    if f.normal.dot(normal) > 0.999 and f.calc_center_median().dot(normal) > half - 1e-6)
        # Split the flat face into the 3 x 3 grid the pips sit on.
        bmesh.ops.subdivide_edges(bm, edges=list(face.edges), cuts=2, use_grid_fill=True)
        u, v = face_axes(normal)
        cell = flat / 3
        cells = {}
        for f in bm.faces:
            centre = f.calc_center_median()
            if f.normal.dot(normal) > 0.999 and abs(centre.dot(normal) - half) < 1e-6:
                place = (round(centre.dot(u) / cell), round(centre.dot(v) / cell))
                if max(abs(place[0]), abs(place[1])) <= 1 and f.calc_area() < 1.1 * cell * cell:
                    cells[place] = f
        pips = [cells[place] for place in PIPS[number]]
        bmesh.ops.inset_individual(bm, faces=pips, thickness=(cell / 2 - PIP_RADIUS) * 0.7, depth=-PIP_DEPTH)
        for pip in pips:
            # A round pip: the inset square's edges cut in three, its corners pulled onto a circle.
            bmesh.ops.subdivide_edges(bm, edges=list(pip.edges), cuts=2)
            centre = pip.calc_center_median()
            for vert in pip.verts:
                vert.co = centre + (vert.co - centre).normalized() * PIP_RADIUS
            pip.material_index = 1


def face_axes(normal):
    """Two directions across a face with this axis-aligned normal, for the pip grid."""
    u = Vector((0, 1, 0)) if abs(normal.x) > 0.5 else Vector((1, 0, 0))
    return u, normal.cross(u)


def build_table(mats):
    """The felt, the rails around it and the floor under the table; the legs are for the picture
    only (no rigid body)."""
    felt = box("Table", (TABLE_LENGTH, TABLE_WIDTH, 0.04), location=(0, 0, TABLE_TOP_Z - 0.02), mat=mats["felt"])
    rigid_body(felt, "PASSIVE", "BOX", friction=0.8, restitution=0.4)
    outer_length = TABLE_LENGTH + 2 * RAIL_THICKNESS
    height = RAIL_HEIGHT + 0.04        # from the underside of the table top to RAIL_HEIGHT above the felt
    z = TABLE_TOP_Z + RAIL_HEIGHT - height / 2
    for name, size, location in (
            ("RailBack", (outer_length, RAIL_THICKNESS, height), (0, (TABLE_WIDTH + RAIL_THICKNESS) / 2, z)),
            ("RailFront", (outer_length, RAIL_THICKNESS, height), (0, -(TABLE_WIDTH + RAIL_THICKNESS) / 2, z)),
            ("RailLeft", (RAIL_THICKNESS, TABLE_WIDTH, height), (-(TABLE_LENGTH + RAIL_THICKNESS) / 2, 0, z)),
            ("RailRight", (RAIL_THICKNESS, TABLE_WIDTH, height), ((TABLE_LENGTH + RAIL_THICKNESS) / 2, 0, z))):
        rail = box(name, size, location=location, mat=mats["rail"])
        rigid_body(rail, "PASSIVE", "BOX", friction=0.5, restitution=0.6)
    for k, (sx, sy) in enumerate(((-1, -1), (1, -1), (-1, 1), (1, 1)), 1):
        leg_height = TABLE_TOP_Z - 0.04
        box(f"TableLeg{k}", (0.05, 0.05, leg_height), mat=mats["rail"],
            location=(sx * (TABLE_LENGTH / 2 - 0.02), sy * (TABLE_WIDTH / 2 - 0.02), leg_height / 2))
    floor = box("Floor", (4, 4, 0.2), location=(0, 0, -0.1), mat=mats["floor"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.6)


def build_dice(mats):
    """Five dice in the hand above the table's left end, thrown towards the right rail: each
    starts turned any way at all (±180° about every axis) and spinning, so every face is as
    likely to come up."""
    for k, ((dx, dy), (_, pips)) in enumerate(zip(HAND_PLACES, DICE), 1):
        die = mesh_object(f"Die{k}", die_geometry, location=HAND + Vector((dx, dy, 0)), mat=mats[f"die{k}"])
        die.data.materials.append(mats[pips])
        rigid_body(die, "ACTIVE", "CONVEX_HULL", mass=DIE_MASS, friction=0.5, restitution=0.5)
        throw(die)


def throw(die):
    """The add-on's variation ranges for a throw: a linear velocity from THROW_MIN to THROW_MAX (a
    range not centred on zero: the add-on's min/max), spin ±SPIN, any rotation, a small offset."""
    variation(die, location=(PLACE_SPREAD,) * 3, rotation=(math.pi,) * 3, angular_velocity=(SPIN,) * 3,
              linear_velocity_range=(THROW_MIN, THROW_MAX))


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "dice"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    mats = {k: material(k, rgb) for k, rgb in {
        "felt": (0.05, 0.3, 0.12), "rail": (0.3, 0.17, 0.08), "floor": (0.45, 0.42, 0.4),
        "pip_dark": (0.02, 0.02, 0.02), "pip_light": (0.95, 0.95, 0.92),
        **{f"die{k}": rgb for k, (rgb, _) in enumerate(DICE, 1)}}.items()}
    build_table(mats)
    build_dice(mats)
    camera_and_lights(location=(0.05, -0.62, 1.45), target=(0.02, 0.02, TABLE_TOP_Z), lens=30)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
