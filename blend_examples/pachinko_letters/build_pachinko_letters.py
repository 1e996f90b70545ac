"""Builds the pachinko-letters example: the letters of WORLDS fall through a board of pegs into a
row of slots.

Goal: "every letter lands in its own slot, so the slots spell WORLDS". A random run puts one or two
letters in place; the paper's user got all of them there by refining one or two letters at a time.

Run:  blender -b --factory-startup --python blend_examples/pachinko_letters/build_pachinko_letters.py -- OUT.blend
Letters are COMPOUND rigid bodies (Blender 3.4's "Compound Parent" shape): the letter object holds
the visible mesh, its children are the BOX parts it collides with. Everything is made from nothing
with Blender's own rigid-body settings, plus the Many-Worlds add-on's variation ranges and sampling
settings (helpers in ../example_kit.py).
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from example_kit import camera_and_lights, compound, output_path, scene_settings, variation  # noqa: E402
from peg_board import (  # noqa: E402
    LETTER_MASS, Board, build_peg_board, letter_parts, slot_centre_x)

FPS = 24
FRAME_START, FRAME_END = 1, 144         # 6 s: the letters are at rest in the slots after 4-5 s
SUBSTEPS, SOLVER_ITERATIONS = 10, 10
WORLD_COUNT, SEED = 1000, 1

WORD = "WORLDS"
# The board and what falls through it: ../peg_board.py.
BOARD = Board(WORD, height=5.2, peg_rows=5)
LETTER_START_Z = (4.3, 4.9)             # alternate letters start at two heights so they do not collide at once


# --- letters ------------------------------------------------------------------------------------

def build_letters(mats):
    """One compound body per letter, each above its own slot."""
    for i, char in enumerate(WORD):
        x = slot_centre_x(BOARD, i)
        z = LETTER_START_Z[i % 2]
        letter, _ = compound(f"Letter{i + 1}_{char}", letter_parts(char), location=(x, 0, z), mat=mats[f"letter{i % 3}"],
                          mass=LETTER_MASS, friction=0.4, restitution=0.3)
        # +-2 cm and a small in-plane spin; the pegs turn these into very different falls
        variation(letter, location=(0.02, 0.005, 0.02), rotation=(0.0, 0.05, 0.0), angular_velocity=(0.0, 0.5, 0.0))


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "pachinko_letters"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    build_letters(build_peg_board(BOARD))
    camera_and_lights(location=(0.0, -9.5, 2.6), target=(0, 0, 2.5), lens=35)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
