"""Builds the marble-run example, the paper's "refrigerator toy": a marble rolls down chutes and
drops into hinged cups that tip it on, left or right, to the next chute or out of the run.

Goal: "the marble tips Cup1 to Cup7 in turn, each the way the run zigzags, and ends in the goal
basket". Each cup tips one way or the other depending on where the marble lands in it, and the way
the chain needs is the less likely one (about one time in three or four), so random runs complete
the chain in well under one in a thousand: the paper's user chose which way each cup turned, cup
by cup, and so must a search.

Run:  blender -b --factory-startup --python blend_examples/marble_run/build_marble_run.py -- OUT.blend
Everything is made from nothing with Blender's own rigid-body settings, plus the Many-Worlds
add-on's variation ranges and sampling settings (helpers in ../example_kit.py).
"""
import math
import os
import sys

import bpy
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from example_kit import (  # noqa: E402
    box, camera_and_lights, compound, constraint, material, output_path, rigid_body, scene_settings, sphere,
    variation)

FPS = 24
FRAME_START, FRAME_END = 1, 288         # 12 s: a full chain reaches the basket after 9 to 11 s
SUBSTEPS, SOLVER_ITERATIONS = 10, 20    # small fast marble: 240 Hz, extra iterations for the hinges
WORLD_COUNT, SEED = 500, 1

# The toy is flat, as on a fridge door: everything moves in the XZ plane between a back board and a
# front glass pane (not rendered) that keep the marble in the plane.
CHANNEL_HALF_DEPTH = 0.05               # inner faces of board and pane at y = -+0.05
MARBLE_RADIUS, MARBLE_MASS = 0.035, 0.1
PIECE_THICKNESS = 0.02
DROP_GAP = 0.09                         # between a chute's end and its stop wall; the marble drops through
# The gap's centre sits this far short of the cup's hinge, on the side the marble comes from; the
# marble still carries a little speed along the chute when it lands, so the offset sets how often a
# cup tips on (away from the chute that fed it) rather than back. Cup1, fed slowly by the start
# chute, must tip on; the others, fed by a cup's faster pour, must tip back. Both offsets make the
# way the chain needs the less likely one (1 in 3 or 4).
LANDING_SHIFT = 0.014
POUR_LANDING_SHIFT = 0.0
STOP_WALL_HEIGHT = 0.2
BOARD_WIDTH = 1.4

# Cups: a flat-bottomed U with a keel under it. The hinge sits a little above the cup's own centre of
# mass, so an empty cup hangs upright, but below the marble's centre once it is inside, so a full cup
# is unstable and tips towards whichever side the marble landed on.
CUP_INNER_WIDTH, CUP_WALL_HEIGHT, CUP_DEPTH = 0.16, 0.075, 0.08
CUP_MASS, CUP_PIVOT_ABOVE_COM = 0.03, 0.012
CUP_TIP_LIMIT = math.radians(110)
CUP_CLEARANCE = 0.17                    # radius around a hinge that the swinging cup sweeps, with margin

# (name, hinge x, hinge z, the side it must tip to for the chain: +1 right, -1 left): the run
# zigzags down, one level per cup, to the basket a level below the last
CUP_COUNT, LEVEL_DROP, LOWEST_CUP_Z, CUP_X = 7, 0.5, 0.7, 0.3
CUPS = tuple((f"Cup{i + 1}", -CUP_X if i % 2 == 0 else CUP_X, LOWEST_CUP_Z + (CUP_COUNT - 1 - i) * LEVEL_DROP,
              +1 if i % 2 == 0 else -1) for i in range(CUP_COUNT))
BOARD_HEIGHT = CUPS[0][2] + 0.4


# --- generic helpers ---------------------------------------------------------------------------

# --- the scene ---------------------------------------------------------------------------------

def build_frame(mats):
    """Floor, end walls, back board and front glass, so a marble that leaves the run stays in the box.
    The glass is a collider only: wire in the viewport, not rendered."""
    floor = box("Floor", (BOARD_WIDTH, 0.4, 0.05), location=(0, 0, -0.025), mat=mats["floor"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.6)
    for side, sign in (("L", -1), ("R", 1)):
        wall = box(f"EndWall{side}", (PIECE_THICKNESS, 2 * CHANNEL_HALF_DEPTH, BOARD_HEIGHT),
                   location=(sign * (BOARD_WIDTH - PIECE_THICKNESS) / 2, 0, BOARD_HEIGHT / 2), mat=mats["board"])
        rigid_body(wall, "PASSIVE", "BOX")
    board = box("Board", (BOARD_WIDTH, PIECE_THICKNESS, BOARD_HEIGHT),
                location=(0, CHANNEL_HALF_DEPTH + PIECE_THICKNESS / 2, BOARD_HEIGHT / 2), mat=mats["board"])
    rigid_body(board, "PASSIVE", "BOX", friction=0.2)
    glass = box("Glass", (BOARD_WIDTH, PIECE_THICKNESS, BOARD_HEIGHT),
                location=(0, -CHANNEL_HALF_DEPTH - PIECE_THICKNESS / 2, BOARD_HEIGHT / 2))
    glass.display_type, glass.hide_render = "WIRE", True
    rigid_body(glass, "PASSIVE", "BOX", friction=0.0)


def chute(name, start, end, mats):
    """A passive chute whose top surface runs from `start` to `end` (x, z), with a stop wall beyond the
    low end that catches the marble so it drops, slowed, through the gap into the cup below."""
    start, end = Vector((start[0], 0, start[1])), Vector((end[0], 0, end[1]))
    along = end - start
    tilt = math.atan2(-along.z, abs(along.x)) * (1 if along.x > 0 else -1)   # about +Y, downhill towards end
    half_normal = Vector((math.sin(tilt), 0, math.cos(tilt))) * (PIECE_THICKNESS / 2)
    slab = box(name, (along.length, 2 * CHANNEL_HALF_DEPTH, PIECE_THICKNESS), location=(start + end) / 2 - half_normal,
               rotation=(0, tilt, 0), mat=mats["chute"])
    rigid_body(slab, "PASSIVE", "BOX", friction=0.3)
    side = 1 if along.x > 0 else -1
    # reaches below the chute's end: a fast marble leaves the chute on a parabola and would pass under
    wall = box(f"{name}Stop", (PIECE_THICKNESS, 2 * CHANNEL_HALF_DEPTH, STOP_WALL_HEIGHT),
               location=(end.x + side * (DROP_GAP + PIECE_THICKNESS / 2), 0, end.z - 0.07 + STOP_WALL_HEIGHT / 2),
               mat=mats["chute"])
    rigid_body(wall, "PASSIVE", "BOX", friction=0.3, restitution=0.0)


def cup(name, hinge_x, hinge_z, mats):
    """A hinged compound cup (bottom, two walls, keel) turning about the Y axis through its hinge."""
    half = CUP_INNER_WIDTH / 2 + PIECE_THICKNESS / 2
    parts = [((CUP_INNER_WIDTH + 2 * PIECE_THICKNESS, CUP_DEPTH, PIECE_THICKNESS), (0, 0, 0)),
             ((PIECE_THICKNESS, CUP_DEPTH, CUP_WALL_HEIGHT), (-half, 0, (CUP_WALL_HEIGHT + PIECE_THICKNESS) / 2)),
             ((PIECE_THICKNESS, CUP_DEPTH, CUP_WALL_HEIGHT), (half, 0, (CUP_WALL_HEIGHT + PIECE_THICKNESS) / 2)),
             ((0.06, CUP_DEPTH, 0.04), (0, 0, -0.03))]
    # place the cup so that its centre of mass ends up CUP_PIVOT_ABOVE_COM under the hinge
    volumes = [s[0] * s[1] * s[2] for s, _ in parts]
    com_z = sum(o[2] * v for (_, o), v in zip(parts, volumes)) / sum(volumes)
    body, _ = compound(name, parts, location=(hinge_x, 0, hinge_z - CUP_PIVOT_ABOVE_COM - com_z), mat=mats["cup"],
                       mass=CUP_MASS, friction=0.4, damping=(0.1, 0.8))
    # the empty's local Z is the hinge axis: turn it onto world Y
    constraint(f"{name}Hinge", "HINGE", bpy.data.objects["Board"], body, location=(hinge_x, 0, hinge_z),
               rotation=(math.pi / 2, 0, 0), use_limit_ang_z=True,
               limit_ang_z_lower=-CUP_TIP_LIMIT, limit_ang_z_upper=CUP_TIP_LIMIT)
    return body


def build_run(mats):
    """A start chute into Cup1, then one chute per cup, each starting under the rim the cup must tip
    over and ending above the next cup (or the goal basket), so the run zigzags down the board."""
    _, x0, z0, _ = CUPS[0]
    chute("Chute0", (x0 - 0.35, z0 + 0.28), (x0 - DROP_GAP / 2 - LANDING_SHIFT, z0 + 0.22), mats)
    for i, (name, x, z, side) in enumerate(CUPS):
        cup(name, x, z, mats)
        target_x = CUPS[i + 1][1] if i + 1 < len(CUPS) else -x
        # starts under the hinge, below the circle the swinging cup sweeps, to catch the marble wherever
        # it leaves the rim; slopes down towards the next cup
        chute(f"Chute{i + 1}", (x - side * 0.02, z - CUP_CLEARANCE - 0.01),
              (target_x - side * (DROP_GAP / 2 + POUR_LANDING_SHIFT), z - CUP_CLEARANCE - 0.09), mats)
    basket_x, basket_z = -CUPS[-1][1], CUPS[-1][2] - LEVEL_DROP
    for part, size, offset in (("Bottom", (0.24, 0.1, 0.02), (0, 0, 0)), ("WallL", (0.02, 0.1, 0.1), (-0.11, 0, 0.05)),
                               ("WallR", (0.02, 0.1, 0.1), (0.11, 0, 0.05))):
        piece = box(f"GoalBasket{part}", size, location=(basket_x + offset[0], 0, basket_z + offset[2]),
                    mat=mats["goal"])
        rigid_body(piece, "PASSIVE", "BOX", friction=0.6)


def build_marble(mats):
    _, x0, z0, _ = CUPS[0]
    marble = sphere("Marble", MARBLE_RADIUS, location=(x0 - 0.3, 0, z0 + 0.27 + MARBLE_RADIUS), mat=mats["marble"])
    rigid_body(marble, "ACTIVE", "SPHERE", mass=MARBLE_MASS, friction=0.3, restitution=0.1, damping=(0.0, 0.05))
    # +-2 cm along the chute and a nudge either way decide how it meets each cup; y stays in the channel
    variation(marble, location=(0.02, 0.005, 0.0), linear_velocity=(0.05, 0.0, 0.0), angular_velocity=(0.0, 1.0, 0.0))


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "marble_run"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    mats = {k: material(k, rgb) for k, rgb in {
        "floor": (0.45, 0.45, 0.45), "board": (0.85, 0.85, 0.8), "chute": (0.2, 0.45, 0.8),
        "cup": (0.9, 0.55, 0.1), "goal": (0.2, 0.7, 0.25), "marble": (0.8, 0.1, 0.15)}.items()}
    build_frame(mats)
    build_run(mats)
    build_marble(mats)
    # the whole board in view, whatever its height
    distance = 5.4 * BOARD_HEIGHT / 2.6
    camera_and_lights(location=(0.6, -distance, BOARD_HEIGHT / 2 + 0.2), target=(0, 0, BOARD_HEIGHT / 2), lens=35)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
