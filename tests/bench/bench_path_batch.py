"""Benchmark: preparing the viewport's path batches for 10,000 worlds x 200 bodies within the
drawing budget (2,000,000 vertices), on the CPU.

/usr/bin/python3 tests/bench/bench_path_batch.py
/usr/bin/python3 tests/bench/bench_path_batch.py LIBRARY.mwb   (also measures a real library)
Times core.path_budget.build_path_arrays: choosing the paths, thinning them, and the float32
vertex and colour arrays that draw.paths hands to gpu.types.GPUBatch (these machines have no GPU,
and Blender's gpu module does not work in background mode). Paths are 10 s at 30 Hz (301 points);
a world's paths are those of one of 16 synthetic random walks, gathered body by body as
Library.polylines gathers them. Each case builds from nothing, best of 5.
Prints a table and `BENCH path_batch_ms_10000x200 <ms>` (the first case) and one line per case.
Then the same cases thinned in screen space for a 1600 x 900 viewport looking at the paths: how
many more worlds fit the budget, and the time it costs; with a library, the same for its worlds
(all bodies, none selected or matching, a view of the whole scene).
"""
import json
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

sys.path.insert(0, os.path.join(ROOT, "tests", "shared"))

from camera_math import look_at, perspective  # noqa: E402
from many_worlds.core import palette, path_budget, screen_thinning  # noqa: E402

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


def gathered(pool):
    """Library.polylines over worlds whose paths are pool[world % DISTINCT]."""
    def polylines_of(worlds, bodies, stride):
        kept = path_budget.thinned_indices(pool.shape[2], stride)
        rows = (np.asarray(worlds, np.intp) % len(pool))[:, None, None]
        return pool[rows, np.asarray(bodies, np.intp)[None, :, None], kept[None, None, :]]
    return polylines_of


def screen_looking_at(lo, hi):
    """A 1600 x 900 viewport seeing the box lo..hi whole, from the front, above and to the side."""
    centre, size = (np.asarray(lo) + hi) / 2, float(np.linalg.norm(np.asarray(hi) - lo))
    eye = centre + size * np.array([0.9, -1.1, 0.6])
    matrix = perspective(0.8, 1600 / 900, 0.1, 100 * size) @ look_at(eye, centre)
    return screen_thinning.ScreenView(tuple(map(tuple, matrix)), 1600, 900)


def timed(build):
    """(the last result, best ms, worst ms) of RUNS calls of build()."""
    times = []
    for _ in range(RUNS):
        start = time.perf_counter()
        result = build()
        times.append((time.perf_counter() - start) * 1000)
    return result, min(times), max(times)


def main():
    rng = np.random.default_rng(0)
    pool = synthetic_polylines(rng)
    polylines_of = gathered(pool)
    screen = screen_looking_at(np.nanmin(pool, axis=(0, 1, 2)), np.nanmax(pool, axis=(0, 1, 2)))
    rows = []
    for name, choice in cases(rng):
        arrays, best, worst = timed(lambda: path_budget.build_path_arrays(choice, polylines_of))
        thinned, thinned_best, _ = timed(lambda: path_budget.build_path_arrays(choice, polylines_of, screen=screen))
        assert arrays.vertex_count <= path_budget.VERTEX_BUDGET >= thinned.vertex_count
        rows.append((name, arrays, best, worst, thinned, thinned_best))
    print(f"{'case':<46} {'vertices':>10} {'worlds':>7} {'stride':>7} {'best ms':>8} {'worst ms':>9}"
          f" | {'on screen: worlds':>17} {'best ms':>8}")
    for name, arrays, best, worst, thinned, thinned_best in rows:
        print(f"{name:<46} {arrays.vertex_count:>10,} {arrays.worlds_drawn:>7,} {arrays.coarsest_stride:>7} "
              f"{best:>8.1f} {worst:>9.1f} | {thinned.worlds_drawn:>17,} {thinned_best:>8.1f}")
    print(f"BENCH path_batch_ms_{WORLDS}x{BODIES} {rows[0][2]:.1f}")
    for name, _, best, _, thinned, thinned_best in rows[1:]:
        print(f"BENCH path_batch_ms_{WORLDS}x{BODIES} {name}: {best:.1f}")
    for name, arrays, best, _, thinned, thinned_best in rows:
        print(f"BENCH path_batch_screen_thinning {name}: worlds {arrays.worlds_drawn:,} -> {thinned.worlds_drawn:,}, "
              f"stride {arrays.coarsest_stride} -> {thinned.coarsest_stride}, {best:.1f} -> {thinned_best:.1f} ms")
    if len(sys.argv) > 1:
        library_case(sys.argv[1])


def library_case(path):
    """Worlds drawn within the budget with and without screen thinning, all bodies of a library: its
    own worlds, then WORLDS worlds made of its worlds over and over (a library bigger than the
    budget at the coarsest stride)."""
    from many_worlds import _native
    library = _native.Library(path)
    names = [b["name"] for b in json.loads(library.scene_json)["bodies"]]
    bodies = tuple(range(library.body_count))
    own = library.world_indices
    sample = library.polylines(own[:200], list(bodies), 1)
    screen = screen_looking_at(np.nanmin(sample, axis=(0, 1, 2)), np.nanmax(sample, axis=(0, 1, 2)))
    colours = palette.body_colours(names, list(bodies))

    def tiled(worlds, bodies, stride):
        return library.polylines([own[w % len(own)] for w in worlds], bodies, stride)

    for worlds, polylines_of in ((own, library.polylines), (list(range(WORLDS)), tiled)):
        choice = path_budget.PathChoice(worlds, np.zeros(len(worlds), bool), -1, bodies, (), colours)
        plain, best, _ = timed(lambda: path_budget.build_path_arrays(choice, polylines_of))
        thinned, thinned_best, _ = timed(lambda: path_budget.build_path_arrays(choice, polylines_of, screen=screen))
        repeated = "" if worlds is own else f" (its {len(own):,} over and over)"
        print(f"BENCH path_batch_screen_thinning {os.path.basename(path)} {len(worlds):,} worlds x {len(bodies)} "
              f"bodies{repeated}: worlds {plain.worlds_drawn:,} -> {thinned.worlds_drawn:,}, "
              f"stride {plain.coarsest_stride} -> {thinned.coarsest_stride}, vertices "
              f"{plain.vertex_count:,} -> {thinned.vertex_count:,}, {best:.1f} -> {thinned_best:.1f} ms")


main()
