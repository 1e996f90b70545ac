"""Benchmark: baking 200 objects x 600 frames to keyframes with the add-on's bulk F-curve path.

blender -b --factory-startup --python tests/bench/bench_bake.py
Prints a small table and `BENCH bake_s_200x600 <seconds>` (best of 3, fresh objects each time).
"""
import os
import sys
import time

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

from many_worlds import bake  # noqa: E402

OBJECTS, FRAMES, RUNS = 200, 600, 3


def one_run(rng):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    objects = []
    for i in range(OBJECTS):
        ob = bpy.data.objects.new(f"Body{i:03d}", None)
        bpy.context.scene.collection.objects.link(ob)
        objects.append(ob)
    frames = np.arange(1, FRAMES + 1, dtype=np.float64)
    locations = rng.normal(size=(OBJECTS, FRAMES, 3))
    rotations = rng.normal(size=(OBJECTS, FRAMES, 4))
    rotations /= np.linalg.norm(rotations, axis=-1, keepdims=True)
    start = time.perf_counter()
    bake.bake_objects(objects, frames, locations, rotations)
    return time.perf_counter() - start


def main():
    rng = np.random.default_rng(0)
    times = [one_run(rng) for _ in range(RUNS)]
    print(f"{'objects':>8} {'frames':>7} {'channels':>9} {'best s':>8} {'worst s':>8}")
    print(f"{OBJECTS:>8} {FRAMES:>7} {7:>9} {min(times):>8.3f} {max(times):>8.3f}")
    print(f"BENCH bake_s_{OBJECTS}x{FRAMES} {min(times):.4f}")


main()
