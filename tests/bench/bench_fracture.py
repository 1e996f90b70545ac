"""Benchmark: a Cell Fracture wall of 60 pieces, built here with Blender's own tools as an animator
builds one (Cell Fracture from a grid of points, Calculate Mass, Deactivation with Start
Deactivated so the wall stands until hit) and knocked by a thrown ball: Blender's Bullet bake per
world against our sampling (bench_examples.measure).

blender -b --factory-startup --python tests/bench/bench_fracture.py [-- WORLDS]
Prints `BENCH bullet_speedup_fracture`, `sleep_speedup_fracture` and `fracture_pieces`.
"""
import math
import os
import random
import sys

import addon_utils
import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "fidelity"))

import bench_examples  # noqa: E402
import scenes  # noqa: E402


def fracture_wall(pieces_x=12, pieces_z=5):
    """A 4 m × 0.25 m × 2 m wall cut at a grid of points (pieces_x × pieces_z pieces)."""
    addon_utils.enable("object_fracture_cell", default_set=False)
    scenes.ground("BOX", size=30)
    wall = scenes.add_mesh("cube", "Wall", size=1.0, location=(0, 0, 1.0), scale=(4.0, 0.25, 2.0))
    grid = scenes.add_mesh("grid", "Cuts", x_subdivisions=pieces_x - 1, y_subdivisions=pieces_z - 1, size=1.0,
                           location=(0, 0, 1.0), rotation=(math.radians(90), 0, 0), scale=(1.8, 0.9, 1.0))
    grid.parent = wall
    grid.matrix_parent_inverse = wall.matrix_world.inverted()
    scenes.select([wall])
    random.seed(11)  # Cell Fracture jitters cell points with Python's random
    bpy.ops.object.add_fracture_cell_objects(source={"VERT_CHILD"}, source_limit=0, use_debug_redraw=False,
                                             use_recenter=True, use_remove_original=True)
    pieces = sorted(bpy.context.selected_objects, key=lambda ob: ob.name)
    scenes.select([grid])
    bpy.ops.object.delete()
    scenes.add_rigid(pieces)
    bpy.ops.rigidbody.mass_calculate(material="Brick (Common)")
    for piece in pieces:
        piece.rigid_body.use_deactivation = True
        piece.rigid_body.use_start_deactivated = True
    ball = scenes.add_mesh("uv_sphere", "Ball", radius=0.3, location=(-0.5, -4.0, 1.2))
    scenes.add_rigid([ball], shape="SPHERE")
    ball.rigid_body.mass = 40.0
    scenes.key_throw(ball, (0.0, 9.0, 0.5), release_frame=5)
    scenes.frames(120)
    return pieces


def main():
    worlds = int(sys.argv[sys.argv.index("--") + 1]) if "--" in sys.argv else 16
    bpy.ops.wm.read_factory_settings(use_empty=True)
    pieces = fracture_wall()
    print(f"fracture: Cell Fracture wall of {len(pieces)} pieces, Start Deactivated, hit by a 40 kg ball")
    print(f"BENCH fracture_pieces {len(pieces)}")
    bench_examples.measure("fracture", worlds)


main()
