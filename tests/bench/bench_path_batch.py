"""Benchmark: preparing the viewport's path batches for 10,000 worlds x 200 bodies within the
drawing budget (2,000,000 vertices), on the CPU.

/usr/bin/python3 tests/bench/bench_path_batch.py
Times core.path_budget.build_path_arrays: choosing the paths, thinning them, and the float32
vertex and colour arrays that draw.paths hands to gpu.types.GPUBatch (these machines have no GPU,
and Blender's gpu module does not work in background mode). Paths are 10 s at 30 Hz (301 points);
a world's polyline is a copy of one of 16 synthetic random walks, as the library copies a world's
polyline out on each read. Each case builds from nothing (no cached segments), best of 5.
Prints a table and `BENCH path_batch_ms_10000x200 <ms>` (the first case).
"""
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

from many_worlds.core import palette, path_budget  # noqa: E402

WORLDS, BODIES, POINTS, DISTINCT, RUNS = 10_000, 200, 301, 16, 5


def synthetic_polylines(rng):
    """DISTINCT worlds of float32 (BODIES, POINTS, 3) paths: random walks falling onto a floor."""
    start = rng.uniform(-1, 1, size=(DISTINCT, BODIES, 1, 3)) + np.array([0, 0, 2.0])
    steps = rng.normal(scale=0.01, size=(DISTINCT, BODIES, POINTS, 3)) - np.array([0, 0, 0.02])
    paths = start + np.cumsum(steps, axis=2)
    paths[..., 2] = np.maximum(paths[..., 2], 0.0)
    return paths.astype(np.float32)


def cases(rng):
    """(name, PathChoice) of the cases timed; the first one is the headline figure."""
    names = [f"Body{i:03d}" for i in range(BODIES)]
    colours = palette.body_colours(names, list(range(BODIES)))
    bodies = tuple(range(BODIES))
    some = np.zeros(WORLDS, bool)
    some[rng.choice(WORLDS, 1500, replace=False)] = True
    every = np.ones(WORLDS, bool)
    worlds = list(range(WORLDS))
    return [
        ("all bodies, 1,500 matching, 1 world selected", path_budget.PathChoice(worlds, some, 7, bodies, (), colours)),
        ("all bodies, all matching", path_budget.PathChoice(worlds, every, -1, bodies, (), colours)),
        ("3 objects selected, 1,500 matching", path_budget.PathChoice(worlds, some, 7, bodies, (3, 50, 120), colours)),
        ("3 objects selected, all matching", path_budget.PathChoice(worlds, every, 7, bodies, (3, 50, 120), colours)),
    ]


def main():
    rng = np.random.default_rng(0)
    pool = synthetic_polylines(rng)

    def polyline_of(world):
        return pool[world % DISTINCT].copy()

    def present_of(world, bodies):
        return bodies

    rows = []
    for name, choice in cases(rng):
        times = []
        for _ in range(RUNS):
            start = time.perf_counter()
            arrays = path_budget.build_path_arrays(choice, polyline_of, present_of)
            times.append((time.perf_counter() - start) * 1000)
        assert arrays.vertex_count <= path_budget.VERTEX_BUDGET
        rows.append((name, arrays, min(times), max(times)))
    print(f"{'case':<46} {'vertices':>10} {'worlds':>7} {'stride':>7} {'best ms':>8} {'worst ms':>9}")
    for name, arrays, best, worst in rows:
        print(f"{name:<46} {arrays.vertex_count:>10,} {arrays.worlds_drawn:>7,} {arrays.coarsest_stride:>7} "
              f"{best:>8.1f} {worst:>9.1f}")
    print(f"BENCH path_batch_ms_{WORLDS}x{BODIES} {rows[0][2]:.1f}")
    print(f"BENCH path_batch_ms_{WORLDS}x{BODIES}_3_selected_all_matching {rows[3][2]:.1f}")


main()
