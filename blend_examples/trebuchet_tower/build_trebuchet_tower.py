"""Builds the trebuchet-and-tower example: a counterweight trebuchet throws a rock at a tower of
192 stacked blocks, with three bystanders standing around the tower.

Goals (queries in the paper): "the rock hits the tower" and "... the falling blocks miss the
bystanders".

Mechanism, the simplest that works: the arm (beam, counterweight and a cup joined by FIXED
constraints) turns on a HINGE; the rock rests in the cup on the arm's leading face, at its tip. When the falling
counterweight has swung the arm up, the hinge's upper limit stops it dead and the rock flies on.

Run:  blender -b --factory-startup --python blend_examples/trebuchet_tower/build_trebuchet_tower.py -- OUT.blend
Everything is made from nothing with Blender's own rigid-body settings, plus the Many-Worlds
add-on's variation ranges and sampling settings (helpers in ../example_kit.py).
"""
import math
import os
import sys

import bpy
from mathutils import Euler, Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from example_kit import (  # noqa: E402
    box, camera_and_lights, capsule, compound, constraint, material, output_path, rigid_body, scene_settings,
    sphere, variation)

FPS = 24
FRAME_START, FRAME_END = 1, 168         # 7 s: swing, flight, and the tower has finished falling
SUBSTEPS, SOLVER_ITERATIONS = 10, 10
WORLD_COUNT, SEED = 300, 1

# trebuchet, throwing along +X; the arm swings in the XZ plane about the Y axis
PIVOT = Vector((0.0, 0.0, 3.2))
LONG_ARM, SHORT_ARM, BEAM_SECTION = 4.0, 1.2, 0.15
COUNTERWEIGHT_SIZE, COUNTERWEIGHT_MASS = 0.9, 300.0
BEAM_MASS = 50.0
CUP_LENGTH, CUP_WIDTH, PLATE, CUP_MASS = 0.5, 0.5, 0.04, 5.0
COCKED_ANGLE = math.radians(225)        # long arm direction at the start, from +X towards +Z
RELEASE_ANGLE = math.radians(120)       # the hinge limit stops the arm here: a throw 30 degrees up
ROCK_RADIUS, ROCK_MASS = 0.18, 20.0
FRAME_HALF_GAP = 0.55                   # uprights either side of the arm, clear of the counterweight

# tower: 12 layers of 16 blocks in a pinwheel ring; alternate layers are mirrored so joints overlap
TOWER_CENTRE = Vector((11.0, 0.0, 0.0))        # the rock, thrown as built, meets the tower at about 2.7 m
LAYERS, BLOCKS_PER_SIDE = 12, 4
BLOCK_LENGTH, BLOCK_DEPTH, BLOCK_HEIGHT, BLOCK_MASS = 0.5, 0.25, 0.25, 5.0
# (x, y) of the passive figures: two behind the tower, 2.4 m from its centre either side of the
# throw, where the blocks it knocks off land (1.5-3.5 m behind it), and one beside it
BYSTANDERS = ((TOWER_CENTRE.x + 2.1, 1.2), (TOWER_CENTRE.x + 2.1, -1.2), (TOWER_CENTRE.x - 0.6, 2.4))


# --- generic helpers ---------------------------------------------------------------------------

# --- trebuchet ----------------------------------------------------------------------------------

def arm_rotation():
    """The arm's Euler rotation: about +Y, which turns +X towards -Z, so local +X (the long arm)
    points along COCKED_ANGLE and local -Z is the leading face, the way the tip moves."""
    return (0.0, -COCKED_ANGLE, 0.0)


def build_frame(mats):
    """Two passive uprights and a base; the arm hangs between the uprights on its hinge."""
    for side, sign in (("L", -1), ("R", 1)):
        upright = box(f"Upright{side}", (0.3, 0.1, PIVOT.z + 0.2),
                      location=(PIVOT.x, sign * (FRAME_HALF_GAP + 0.05), (PIVOT.z + 0.2) / 2), mat=mats["wood"])
        rigid_body(upright, "PASSIVE", "BOX", friction=0.5)
        skid = box(f"Skid{side}", (3.0, 0.2, 0.2), location=(PIVOT.x, sign * (FRAME_HALF_GAP + 0.05), 0.1),
                   mat=mats["wood"])
        rigid_body(skid, "PASSIVE", "BOX", friction=0.5)


def build_arm(mats):
    """Beam, counterweight and cup joined by FIXED constraints (the heavy parts are plain boxes, so
    their inertia is exact in Blender and in the engine; a Blender COMPOUND takes its inertia from
    the bounding box), hinged to an upright; the hinge stops at RELEASE_ANGLE. The rock rests in
    the cup on the leading face."""
    half = BEAM_SECTION / 2
    rotation = arm_rotation()
    place = Matrix.Translation(PIVOT) @ Euler(rotation).to_matrix().to_4x4()
    beam = box("Arm", (LONG_ARM + SHORT_ARM, BEAM_SECTION, BEAM_SECTION),
               location=place @ Vector(((LONG_ARM - SHORT_ARM) / 2, 0, 0)), rotation=rotation, mat=mats["wood"])
    rigid_body(beam, "ACTIVE", "BOX", mass=BEAM_MASS, friction=0.6, damping=(0.0, 0.02))
    weight = box("Counterweight", (COUNTERWEIGHT_SIZE,) * 3, location=place @ Vector((-SHORT_ARM, 0, 0)),
                 rotation=rotation, mat=mats["iron"])
    rigid_body(weight, "ACTIVE", "BOX", mass=COUNTERWEIGHT_MASS, friction=0.6, damping=(0.0, 0.02))
    # the cup: a plate on the leading face with cheeks either side and a lip at the end, so the rock
    # can neither roll off the narrow beam sideways nor slide off its end before the release
    cup_parts = [((CUP_LENGTH, CUP_WIDTH, PLATE), (LONG_ARM - CUP_LENGTH / 2, 0, -half - PLATE / 2), (0, 0, 0)),
                 ((0.06, CUP_WIDTH, 0.35), (LONG_ARM + 0.03, 0, -half - 0.175), (0, 0, 0))]
    for sign in (-1, 1):
        cup_parts.append(((CUP_LENGTH, PLATE, 0.18), (LONG_ARM - CUP_LENGTH / 2, sign * (CUP_WIDTH - PLATE) / 2,
                                                       -half - PLATE - 0.09), (0, 0, 0)))
    cup, _ = compound("Cup", [(size, place @ Vector(offset) - PIVOT, euler) for size, offset, euler in cup_parts],
                   location=PIVOT, mat=mats["wood"], mass=CUP_MASS, friction=0.6)
    constraint("CounterweightFixed", "FIXED", beam, weight, location=weight.location)
    constraint("CupFixed", "FIXED", beam, cup, location=cup.location)
    # The hinge axis is the empty's local Z, here world -Y. The limits are symmetric: the arm only
    # ever swings one way, and the stop then does not depend on which body's angle a simulator
    # measures (Blender measures object1 relative to object2, the opposite of the usual convention).
    swing = COCKED_ANGLE - RELEASE_ANGLE
    constraint("ArmHinge", "HINGE", bpy.data.objects["UprightR"], beam, location=PIVOT, rotation=(math.pi / 2, 0, 0),
               use_limit_ang_z=True, limit_ang_z_lower=-swing, limit_ang_z_upper=swing)
    rock_at = place @ Vector((LONG_ARM - ROCK_RADIUS - 0.02, 0, -half - PLATE - ROCK_RADIUS - 0.002))
    rock = sphere("Rock", ROCK_RADIUS, location=rock_at, mat=mats["rock"])
    rigid_body(rock, "ACTIVE", "SPHERE", mass=ROCK_MASS, friction=0.6, restitution=0.1)
    # Only the rock varies: a nudge as it sits in the cup changes where it flies, which is what the
    # paper got by varying the release time; the jointed arm gets no variation, since moving one of
    # its boxes alone would only fight the joints.
    variation(rock, location=(0.02, 0.02, 0.02), linear_velocity=(0.5, 0.1, 0.5), angular_velocity=(1.0, 1.0, 1.0))


# --- tower and bystanders -----------------------------------------------------------------------

def pinwheel_layer(mirrored):
    """16 blocks (centre x, y, rotated?) around a square ring, each side a run of BLOCKS_PER_SIDE
    blocks that covers one corner; `mirrored` turns the pinwheel the other way."""
    side = BLOCKS_PER_SIDE * BLOCK_LENGTH + BLOCK_DEPTH
    half = side / 2
    blocks = []
    for i in range(BLOCKS_PER_SIDE):
        t = -half + (i + 0.5) * BLOCK_LENGTH        # along a side, starting at its corner
        blocks += [(t, -half + BLOCK_DEPTH / 2, False),                 # south, from the west corner
                   (half - BLOCK_DEPTH / 2, t, True),                   # east, from the south corner
                   (-t, half - BLOCK_DEPTH / 2, False),                 # north, from the east corner
                   (-half + BLOCK_DEPTH / 2, -t, True)]                 # west, from the north corner
    if mirrored:
        blocks = [(-x, y, rotated) for x, y, rotated in blocks]
    return blocks


def build_tower(mats):
    """LAYERS x 16 = 192 blocks resting exactly on each other (no gaps, no overlaps), asleep, so
    the stack stands still until the rock arrives."""
    count = 0
    for layer in range(LAYERS):
        z = (layer + 0.5) * BLOCK_HEIGHT
        for x, y, rotated in pinwheel_layer(mirrored=layer % 2 == 1):
            count += 1
            size = (BLOCK_DEPTH, BLOCK_LENGTH, BLOCK_HEIGHT) if rotated else (BLOCK_LENGTH, BLOCK_DEPTH, BLOCK_HEIGHT)
            block = box(f"Block{count:03d}", size, location=TOWER_CENTRE + Vector((x, y, z)),
                        mat=mats["stone" if layer % 2 else "stone2"])
            # Each block is a cube as Blender adds it, left at the default shape (Convex Hull).
            rigid_body(block, "ACTIVE", "CONVEX_HULL", mass=BLOCK_MASS, friction=0.6, restitution=0.05)
            # As animators keep a stack from settling before it is hit: Bullet's Deactivation,
            # starting asleep. Both Blender and the engine then leave the tower alone until the
            # rock (or a falling block) reaches it, and neither spends time on it until then.
            block.rigid_body.use_deactivation = True
            block.rigid_body.use_start_deactivated = True


def build_bystanders(mats):
    """Passive figures near the tower: a query asks for worlds where no block touches them."""
    for i, (x, y) in enumerate(BYSTANDERS):
        person = capsule(f"Bystander{i + 1}", 0.25, 1.7, location=(x, y, 0.85), mat=mats["bystander"])
        rigid_body(person, "PASSIVE", "CAPSULE", friction=0.5)


def main():
    path = output_path()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.context.scene.name = "trebuchet_tower"
    scene_settings(FPS, FRAME_START, FRAME_END, SUBSTEPS, SOLVER_ITERATIONS, WORLD_COUNT, SEED)
    mats = {k: material(k, rgb) for k, rgb in {
        "ground": (0.3, 0.42, 0.25), "wood": (0.45, 0.3, 0.18), "rock": (0.3, 0.3, 0.32), "iron": (0.2, 0.2, 0.22),
        "stone": (0.75, 0.72, 0.65), "stone2": (0.68, 0.64, 0.58), "bystander": (0.9, 0.3, 0.2)}.items()}
    ground = box("Ground", (50, 30, 0.2), location=(8, 0, -0.1), mat=mats["ground"])
    rigid_body(ground, "PASSIVE", "BOX", friction=0.8)
    build_frame(mats)
    build_arm(mats)
    build_tower(mats)
    build_bystanders(mats)
    camera_and_lights(location=(6.0, -22.0, 7.5), target=(6.5, 0.0, 2.8), lens=30)
    bpy.context.preferences.filepaths.save_version = 0     # no .blend1 backup beside the committed file
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)


main()
