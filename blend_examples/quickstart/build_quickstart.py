"""Builds the quick-start example: five toys wait behind an animated gate, then tumble down a chute
past a splitter peg into three bins.

Goal: "the marble lands in the left bin". Small on purpose, so it samples in seconds.

Run:  blender -b --factory-startup --python blend_examples/quickstart/build_quickstart.py -- OUT.blend
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
    box, camera_and_lights, capsule, cone, cylinder, material, output_path, rigid_body, scene_settings, sphere,
    variation)

FPS = 24
FRAME_START, FRAME_END = 1, 96          # 4 s: everything has settled in the bins by then
SUBSTEPS, SOLVER_ITERATIONS = 10, 10    # 240 Hz, what the engine steps at too
WORLD_COUNT, SEED = 200, 1

CHUTE_LENGTH, CHUTE_WIDTH, CHUTE_TILT = 3.0, 1.2, math.radians(25)
CHUTE_LOW_END = Vector((0.0, -1.1, 0.55))   # lower edge centre of the chute floor, just behind the bins
GATE_FROM_TOP, GATE_LIFT = 0.9, 0.5
GATE_OPEN_FRAMES = (10, 18)                 # the gate rises between these frames
BIN_WIDTH, BIN_DEPTH, BIN_WALL_HEIGHT = 0.6, 1.0, 0.3
BIN_NAMES = ("Left", "Middle", "Right")     # as seen from the camera (-X is left)
WALL_THICKNESS = 0.05


# --- generic helpers ---------------------------------------------------------------------------

# --- the scene ---------------------------------------------------------------------------------

def build_ground(mats):
    ground = box("Ground", (8, 8, 0.2), location=(0, 0, -0.1), mat=mats["floor"])
    rigid_body(ground, "PASSIVE", "BOX", friction=0.6)


def build_chute(mats):
    """A tilted floor with rails, descending towards the camera (-Y); a splitter peg near the
    bottom sends things left or right, which is what makes the outcome worth sampling."""
    down = Vector((0, -math.cos(CHUTE_TILT), -math.sin(CHUTE_TILT)))   # along the chute, downhill
    normal = Vector((0, -math.sin(CHUTE_TILT), math.cos(CHUTE_TILT)))
    centre = CHUTE_LOW_END - down * (CHUTE_LENGTH / 2) - normal * WALL_THICKNESS / 2
    tilt = (CHUTE_TILT, 0, 0)
    floor = box("Chute", (CHUTE_WIDTH, CHUTE_LENGTH, WALL_THICKNESS), location=centre, rotation=tilt, mat=mats["chute"])
    rigid_body(floor, "PASSIVE", "BOX", friction=0.4)
    for side, sign in (("L", -1), ("R", 1)):
        rail_centre = centre + Vector((sign * (CHUTE_WIDTH + WALL_THICKNESS) / 2, 0, 0)) + normal * 0.1
        rail = box(f"ChuteRail{side}", (WALL_THICKNESS, CHUTE_LENGTH, 0.25), location=rail_centre, rotation=tilt,
                   mat=mats["chute"])
        rigid_body(rail, "PASSIVE", "BOX", friction=0.3)
    peg_centre = CHUTE_LOW_END - down * 0.45 + normal * 0.15
    peg = cylinder("SplitterPeg", 0.07, 0.5, location=peg_centre, rotation=tilt, mat=mats["peg"])
    rigid_body(peg, "PASSIVE", "CYLINDER", restitution=0.3)


def build_gate(mats):
    """An animated passive gate across the chute: it holds the toys while they settle against it,
    then lifts (keyframed, Blender's "Animated" rigid body), so every world starts from a jumble."""
    along = Vector((0, -math.cos(CHUTE_TILT), -math.sin(CHUTE_TILT)))
    normal = Vector((0, -math.sin(CHUTE_TILT), math.cos(CHUTE_TILT)))
    top_edge = CHUTE_LOW_END - along * CHUTE_LENGTH
    closed = top_edge + along * GATE_FROM_TOP + normal * 0.16
    gate = box("Gate", (CHUTE_WIDTH, WALL_THICKNESS, 0.3), location=closed, rotation=(CHUTE_TILT, 0, 0),
               mat=mats["peg"])
    rigid_body(gate, "PASSIVE", "BOX", friction=0.3)
    gate.rigid_body.kinematic = True
    # Keys made linear as they are inserted (Preferences > Animation > Interpolation), the same on
    # every Blender, legacy or slotted actions.
    edit = bpy.context.preferences.edit
    interpolation, edit.keyframe_new_interpolation_type = edit.keyframe_new_interpolation_type, "LINEAR"
    for frame, lift in ((FRAME_START, 0.0), (GATE_OPEN_FRAMES[0], 0.0), (GATE_OPEN_FRAMES[1], GATE_LIFT)):
        gate.location = closed + Vector((0, 0, lift))
        gate.keyframe_insert("location", frame=frame)
    edit.keyframe_new_interpolation_type = interpolation
    gate.location = closed


def build_bins(mats):
    """Three bins side by side in front of the chute's lower end; each has a coloured floor tile
    (BinLeftFloor, ...) so a screen box over one is easy to draw."""
    y_back, y_front = CHUTE_LOW_END.y - 0.05, CHUTE_LOW_END.y - 0.05 - BIN_DEPTH
    width = BIN_WIDTH * len(BIN_NAMES)
    y_mid = (y_back + y_front) / 2
    for i in range(len(BIN_NAMES) + 1):
        x = -width / 2 + i * BIN_WIDTH
        wall = box(f"BinDivider{i}", (WALL_THICKNESS, BIN_DEPTH, BIN_WALL_HEIGHT),
                   location=(x, y_mid, BIN_WALL_HEIGHT / 2), mat=mats["bin"])
        rigid_body(wall, "PASSIVE", "BOX")
    for name, y, height in (("BinBack", y_back, BIN_WALL_HEIGHT), ("BinFront", y_front, 2 * BIN_WALL_HEIGHT)):
        # the front wall is taller: things leave the chute fast and would fly over a low one
        wall = box(name, (width + WALL_THICKNESS, WALL_THICKNESS, height), location=(0, y, height / 2), mat=mats["bin"])
        rigid_body(wall, "PASSIVE", "BOX")
    for i, label in enumerate(BIN_NAMES):
        x = -width / 2 + (i + 0.5) * BIN_WIDTH
        tile = box(f"Bin{label}Floor", (BIN_WIDTH - WALL_THICKNESS, BIN_DEPTH - WALL_THICKNESS, 0.01),
                   location=(x, y_mid, 0.005), mat=mats[f"bin{label}"])
        rigid_body(tile, "PASSIVE", "BOX", friction=0.6)


def build_toys(mats):
    """Five active bodies, one of each primitive shape, at the top of the chute. The marble is the
    one the goal is about; the others get in its way."""
    up_chute = Vector((0, math.cos(CHUTE_TILT), math.sin(CHUTE_TILT)))
    top = CHUTE_LOW_END + up_chute * (CHUTE_LENGTH - 0.35) + Vector((0, 0, 0.2))
    # a centimetre off the chute's centre line: dead centre, it can balance on the splitter peg
    marble = sphere("Marble", 0.1, location=top + Vector((0.01, 0.0, 0.0)), mat=mats["marble"])
    rigid_body(marble, "ACTIVE", "SPHERE", mass=0.3, friction=0.3, restitution=0.5)
    variation(marble, location=(0.15, 0.03, 0.02), linear_velocity=(0.3, 0.1, 0.0))

    die = box("Die", (0.2, 0.2, 0.2), location=top + Vector((-0.35, -0.25, 0.05)), mat=mats["die"])
    rigid_body(die, "ACTIVE", "BOX", mass=0.5, friction=0.5, restitution=0.2)
    variation(die, location=(0.1, 0.1, 0.05), rotation=(0.3, 0.3, 0.3), angular_velocity=(4, 4, 4))

    cone_ = cone("Cone", 0.13, 0.3, location=top + Vector((0.35, -0.25, 0.05)), mat=mats["cone"])
    rigid_body(cone_, "ACTIVE", "CONE", mass=0.3, restitution=0.1)
    variation(cone_, location=(0.1, 0.1, 0.05), rotation=(0.3, 0.3, 0.3), angular_velocity=(3, 3, 3))

    can = cylinder("Can", 0.1, 0.3, location=top + Vector((-0.3, 0.2, 0.15)), rotation=(0, math.pi / 2, 0),
                   mat=mats["can"])
    rigid_body(can, "ACTIVE", "CYLINDER", mass=0.4, friction=0.4, restitution=0.1)
    variation(can, location=(0.05, 0.05, 0.05), rotation=(0.2, 0.2, 0.2), angular_velocity=(1, 1, 1))

    pill = capsule("Pill", 0.07, 0.3, location=top + Vector((0.3, 0.2, 0.15)), rotation=(math.pi / 2, 0, 0.4),
                   mat=mats["pill"])
    rigid_body(pill, "ACTIVE", "CAPSULE", mass=0.2, restitution=0.2)
    variation(pill, location=(0.05, 0.05, 0.05), rotation=(0.3, 0.3, 0.3), angular_velocity=(2, 2, 2))


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "quickstart"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    mats = {k: material(k, rgb) for k, rgb in {
        "floor": (0.5, 0.5, 0.5), "chute": (0.55, 0.4, 0.25), "peg": (0.8, 0.8, 0.8), "bin": (0.35, 0.35, 0.4),
        "binLeft": (0.2, 0.7, 0.25), "binMiddle": (0.75, 0.7, 0.2), "binRight": (0.7, 0.25, 0.2),
        "marble": (0.1, 0.3, 0.9), "die": (0.9, 0.9, 0.85), "cone": (0.95, 0.45, 0.1), "can": (0.7, 0.1, 0.1),
        "pill": (0.6, 0.2, 0.7)}.items()}
    build_ground(mats)
    build_chute(mats)
    build_gate(mats)
    build_bins(mats)
    build_toys(mats)
    camera_and_lights(location=(2.6, -6.6, 4.4), target=(0, -0.3, 0.6), lens=30)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
