"""Builds the SIGGRAPH-letters example, the paper's own: the eight letters of SIGGRAPH start in a
rack at the top with the word's halves swapped (RAPHSIGG) and fall through a tall board of pegs
into eight slots, one per letter, so every letter must cross the middle of the board (1.9 to
2.4 m) to reach its own slot.

Goal: "every letter in its own slot in the last second, so the slots spell SIGGRAPH". The paper's
user reached it by hand in about an hour, refining the letters with the farthest to travel first.

Run:  blender -b --factory-startup --python blend_examples/siggraph_letters/build_siggraph_letters.py -- OUT.blend
Letters are COMPOUND rigid bodies (a parent with the visible mesh, BOX children it collides with),
made with Blender's own rigid-body settings plus the add-on's variation ranges and sampling
settings (helpers in ../example_kit.py).
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from example_kit import (  # noqa: E402
    box, camera_and_lights, compound, cylinder, material, output_path, rigid_body, scene_settings, variation)

FPS = 24
FRAME_START, FRAME_END = 1, 240         # 10 s: the letters are at rest in the slots after 7-8 s
SUBSTEPS, SOLVER_ITERATIONS = 10, 10
WORLD_COUNT, SEED = 1000, 1

WORD = "SIGGRAPH"
# Flat, like a pachinko machine: everything moves in the XZ plane between a back board and a front
# glass pane (a collider only, not rendered).
CHANNEL_HALF_DEPTH = 0.07
LETTER_DEPTH, LETTER_WIDTH, LETTER_HEIGHT, STROKE = 0.1, 0.36, 0.46, 0.08
LETTER_MASS = 0.5
SLOT_WIDTH, SLOT_WALL_HEIGHT, SLOT_WALL_THICKNESS = 0.62, 0.55, 0.04
BOARD_WIDTH, BOARD_HEIGHT = SLOT_WIDTH * len(WORD) + 0.1, 13.4
# Twelve staggered rows: each peg a letter meets sends it about half a column either way, so the
# rows together can carry a letter across the board (the gaps, 0.7 m, pass a letter any way up).
PEG_RADIUS, PEG_ROWS, PEG_ROW_SPACING, PEG_COLUMN_SPACING = 0.05, 12, 0.6, 0.8
PEG_BOTTOM_ROW_Z = 1.2
# The rack along the top: closer together than the slots, over the pegs, and tiered: neighbours
# start 1.8 m or more apart in height, so they do not all meet the first pegs at once.
LETTER_START_SPACING, LETTER_START_Z, LETTER_TIER_HEIGHT = 0.45, 8.6, 0.6
LETTER_TIER = [0, 3, 6, 1, 4, 7, 2, 5]  # per rack place
# Rack place of each slot's letter: the halves of the word swapped.
RACK_PLACE = [(i + len(WORD) // 2) % len(WORD) for i in range(len(WORD))]


# --- letters ------------------------------------------------------------------------------------

def letter_parts(char):
    """Boxes (size, offset, euler) spelling `char` in a blocky font, in a LETTER_WIDTH x
    LETTER_HEIGHT cell centred on the origin; strokes STROKE wide, LETTER_DEPTH deep along Y."""
    w, h, s, d = LETTER_WIDTH, LETTER_HEIGHT, STROKE, LETTER_DEPTH
    left, right, top, bottom = -(w - s) / 2, (w - s) / 2, (h - s) / 2, -(h - s) / 2

    def bar(x0, z0, x1, z1):
        """A stroke from stroke centre (x0, z0) to (x1, z1), square ends."""
        length = math.hypot(x1 - x0, z1 - z0) + s
        angle = -math.atan2(z1 - z0, x1 - x0)   # about +Y, which turns +X towards -Z
        return (length, d, s), ((x0 + x1) / 2, 0, (z0 + z1) / 2), (0, angle, 0)

    glyphs = {
        "S": [bar(left, top, right, top), bar(left, top - s, left, s / 2), bar(left + s, 0, right - s, 0),
              bar(right, -s / 2, right, bottom + s), bar(left, bottom, right, bottom)],
        "I": [bar(0, top - s, 0, bottom + s), bar(left, top, right, top), bar(left, bottom, right, bottom)],
        "G": [bar(left, top - s, left, bottom + s), bar(left, top, right, top), bar(left, bottom, right, bottom),
              bar(right, bottom + s, right, 0), bar(0, 0, right - s, 0)],
        "R": [bar(left, top, left, bottom), bar(left + s, top, right - s, top), bar(right, top - s, right, s),
              bar(left + s, 0, right - s, 0), bar(0.0, -s, right, bottom)],
        "A": [bar(left, top - s, left, bottom), bar(right, top - s, right, bottom), bar(left, top, right, top),
              bar(left + s, 0, right - s, 0)],
        "P": [bar(left, top, left, bottom), bar(left + s, top, right - s, top), bar(right, top - s, right, s),
              bar(left + s, 0, right - s, 0)],
        "H": [bar(left, top, left, bottom), bar(right, top, right, bottom), bar(left + s, 0, right - s, 0)],
    }
    return glyphs[char]


def letter_name(i):
    """Letter i of WORD is named after its slot: Letter1_S ... Letter8_H."""
    return f"Letter{i + 1}_{WORD[i]}"


def build_letters(mats):
    """One compound body per letter, in the rack along the top: slot i's letter starts at place
    RACK_PLACE[i]."""
    for i, char in enumerate(WORD):
        start = RACK_PLACE[i]
        letter, _ = compound(letter_name(i), letter_parts(char),
                             location=((start - (len(WORD) - 1) / 2) * LETTER_START_SPACING, 0,
                                       LETTER_START_Z + LETTER_TIER_HEIGHT * LETTER_TIER[start]),
                             mat=mats[f"letter{i % 3}"], mass=LETTER_MASS, friction=0.4, restitution=0.3)
        # +-3 cm, a small in-plane tilt and spin, and a sideways toss of up to 0.5 m/s: where a
        # letter meets the first pegs decides which way each later one sends it.
        variation(letter, location=(0.03, 0.005, 0.03), rotation=(0.0, 0.05, 0.0),
                  linear_velocity=(0.5, 0.0, 0.0), angular_velocity=(0.0, 0.5, 0.0))


# --- board --------------------------------------------------------------------------------------

def slot_centre_x(i):
    return (i - (len(WORD) - 1) / 2) * SLOT_WIDTH


def build_board(mats):
    """Back board, glass, side walls and floor. The glass is a collider only: wire, not rendered."""
    floor = box("Floor", (BOARD_WIDTH, 2 * CHANNEL_HALF_DEPTH + 0.2, 0.1), location=(0, 0, -0.05), mat=mats["frame"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.6)
    board = box("Board", (BOARD_WIDTH, 0.04, BOARD_HEIGHT), location=(0, CHANNEL_HALF_DEPTH + 0.02, BOARD_HEIGHT / 2),
                mat=mats["board"])
    rigid_body(board, "PASSIVE", "BOX", friction=0.1)
    glass = box("Glass", (BOARD_WIDTH, 0.04, BOARD_HEIGHT), location=(0, -CHANNEL_HALF_DEPTH - 0.02, BOARD_HEIGHT / 2))
    glass.display_type, glass.hide_render = "WIRE", True
    rigid_body(glass, "PASSIVE", "BOX", friction=0.0)
    for side, sign in (("L", -1), ("R", 1)):
        wall = box(f"SideWall{side}", (0.05, 2 * CHANNEL_HALF_DEPTH, BOARD_HEIGHT),
                   location=(sign * (BOARD_WIDTH / 2 + 0.025), 0, BOARD_HEIGHT / 2), mat=mats["frame"])
        rigid_body(wall, "PASSIVE", "BOX", friction=0.2)


def build_pegs(mats):
    """Staggered rows of passive cylinders across the channel (their axis along Y)."""
    # a peg closer to a side wall than a letter's diagonal would wedge letters against the wall
    usable = BOARD_WIDTH / 2 - PEG_RADIUS - math.hypot(LETTER_WIDTH, LETTER_HEIGHT) - 0.02
    for row in range(PEG_ROWS):
        z = PEG_BOTTOM_ROW_Z + row * PEG_ROW_SPACING
        offset = 0.0 if row % 2 == 0 else PEG_COLUMN_SPACING / 2
        count = int(usable // PEG_COLUMN_SPACING) + 1
        for col in range(-count, count + 1):
            x = col * PEG_COLUMN_SPACING + offset
            if abs(x) > usable:
                continue
            peg = cylinder(f"Peg_r{row}_c{col + count:02d}", PEG_RADIUS, 2 * CHANNEL_HALF_DEPTH, location=(x, 0, z),
                           rotation=(math.pi / 2, 0, 0), mat=mats["peg"])
            rigid_body(peg, "PASSIVE", "CYLINDER", friction=0.3, restitution=0.4)


def build_slots(mats):
    """Dividers between the slots; each slot has a floor tile in its letter's colour, for the eye
    and for drawing screen boxes."""
    for i in range(1, len(WORD)):
        x = slot_centre_x(i) - SLOT_WIDTH / 2
        divider = box(f"SlotDivider{i}", (SLOT_WALL_THICKNESS, 2 * CHANNEL_HALF_DEPTH, SLOT_WALL_HEIGHT),
                      location=(x, 0, SLOT_WALL_HEIGHT / 2), mat=mats["frame"])
        rigid_body(divider, "PASSIVE", "BOX", friction=0.3)
    for i, char in enumerate(WORD):
        tile = box(f"Slot{i + 1}_{char}", (SLOT_WIDTH - SLOT_WALL_THICKNESS, 2 * CHANNEL_HALF_DEPTH, 0.01),
                   location=(slot_centre_x(i), 0, 0.005), mat=mats[f"letter{i % 3}"])
        rigid_body(tile, "PASSIVE", "BOX", friction=0.6)


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "siggraph_letters"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    mats = {k: material(k, rgb) for k, rgb in {
        "frame": (0.3, 0.3, 0.35), "board": (0.9, 0.88, 0.82), "peg": (0.75, 0.75, 0.8),
        "letter0": (0.85, 0.2, 0.15), "letter1": (0.15, 0.45, 0.85), "letter2": (0.95, 0.7, 0.1)}.items()}
    build_board(mats)
    build_pegs(mats)
    build_slots(mats)
    build_letters(mats)
    camera_and_lights(location=(0.0, -21.0, 6.5), target=(0, 0, 6.4), lens=35)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
