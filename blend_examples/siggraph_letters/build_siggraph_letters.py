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
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from example_kit import camera_and_lights, compound, output_path, scene_settings, variation  # noqa: E402
from peg_board import (  # noqa: E402
    LETTER_MASS, Board, build_peg_board, letter_parts)

FPS = 24
FRAME_START, FRAME_END = 1, 240         # 10 s: the letters are at rest in the slots after 7-8 s
SUBSTEPS, SOLVER_ITERATIONS = 10, 10
WORLD_COUNT, SEED = 1000, 1

WORD = "SIGGRAPH"
# Twelve staggered rows: each peg a letter meets sends it about half a column either way, so the
# rows together can carry a letter across the board (the gaps, 0.7 m, pass a letter any way up).
BOARD = Board(WORD, height=13.4, peg_rows=12, wall_bumps=True)
# The rack along the top: closer together than the slots, over the pegs, and tiered: neighbours
# start 1.8 m or more apart in height, so they do not all meet the first pegs at once.
LETTER_START_SPACING, LETTER_START_Z, LETTER_TIER_HEIGHT = 0.45, 8.6, 0.6
LETTER_TIER = [0, 3, 6, 1, 4, 7, 2, 5]  # per rack place
# Rack place of each slot's letter: the halves of the word swapped.
RACK_PLACE = [(i + len(WORD) // 2) % len(WORD) for i in range(len(WORD))]


# --- letters ------------------------------------------------------------------------------------

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


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "siggraph_letters"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    build_letters(build_peg_board(BOARD))
    camera_and_lights(location=(0.0, -21.0, 6.5), target=(0, 0, 6.4), lens=35)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
