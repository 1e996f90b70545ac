"""Benchmark: opening a library of 10,000 worlds in the add-on, until the first paths are drawn and
until the path index is complete.

blender -b --factory-startup --python tests/bench/bench_open_library.py -- BUILD_DIR
The library is the quick-start scene (tests/scenes/quickstart.json: 4 moving bodies, 4 s at
120 Hz) sampled by the engine itself into build/bench-results/open_library_10000.mwb; it is kept
there and sampled again only when this build cannot read it (about 1 to 3 minutes on 2 threads).

Each run starts from a fresh factory scene with the add-on registered, opens the library as the
Open Library button and a file load do (core.libraries.open_library), and then prepares the
viewport's paths as the overlay's timer does (draw.paths.OVERLAY.update: choosing, thinning, the
vertex and colour arrays handed to gpu.types.GPUBatch; background mode has no GPU, and handing
about 2,000,000 vertices to batch_for_shader adds 30-45 ms in the UI). "first paths" is the time
from the call until those arrays exist; "index complete" until the session's path index holds
every world (the main thread idles meanwhile, as the UI does between events). The phases below
time each step alone, once, on this library: what the open costs and where it goes.
Prints the tables and `BENCH open_library_s_10000 <s>`, `BENCH open_library_index_s_10000 <s>`
(medians of RUNS runs).
"""
import os
import statistics
import subprocess
import sys
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import many_worlds  # noqa: E402
from many_worlds import _native  # noqa: E402
from many_worlds.core.library_view import LibraryView  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from many_worlds.draw import paths  # noqa: E402
from many_worlds.core import libraries  # noqa: E402
from many_worlds.operators import browsing  # noqa: E402

WORLDS, RUNS = 10_000, 3
SCENE = os.path.join(ROOT, "tests", "scenes", "quickstart.json")
INDEX_TIMEOUT_S = 300


def build_dir():
    arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    return os.path.abspath(arguments[0] if arguments else os.path.join(ROOT, "build"))


def readable(path):
    """Whether this build reads all WORLDS worlds of `path` without a warning."""
    try:
        library = _native.Library(path, 0.0)
    except (IOError, ValueError):
        return False
    return len(library.world_indices) == WORLDS and not library.warnings


def library_path(build):
    """The cached library, sampled again by the engine when missing or unreadable."""
    results = os.path.join(build, "bench-results")
    os.makedirs(results, exist_ok=True)
    path = os.path.join(results, f"open_library_{WORLDS}.mwb")
    if os.path.isfile(path) and readable(path):
        return path, 0.0
    if os.path.exists(path):
        os.remove(path)
    engine = os.path.join(build, "native", "mwb-engine")
    start = time.perf_counter()
    subprocess.run([engine, "sample", "--scene", SCENE, "--out", path, "--worlds", f"0:{WORLDS}", "--threads", "2"],
                   check=True, stdout=subprocess.DEVNULL)
    return path, time.perf_counter() - start


def timed(function):
    start = time.perf_counter()
    value = function()
    return value, time.perf_counter() - start


def phases(path):
    """(phase, seconds) of each step of opening, timed alone on the main thread."""
    rows = []
    _, read_s = timed(lambda: _native.Library(path, 0.0))
    rows.append(("read the file (records, checksums, checkpoints)", read_s))
    library, open_s = timed(lambda: _native.Library(path))
    rows.append(("decode polylines (30 Hz) on open", max(0.0, open_s - read_s)))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    many_worlds.register()
    try:
        SESSION.view = LibraryView(_native, path)
        _, list_s = timed(lambda: browsing.sync_world_list(bpy.context.scene))
        rows.append(("world list (summaries of every world)", list_s))
        radii = _native.body_bounding_radii(_native.Scene.from_json(library.scene_json))
        for threads in (1, 0):
            index = _native.PathIndex(radii)
            _, index_s = timed(lambda: index.add_library(library, threads=threads))
            rows.append((f"build the path index ({threads or 'all'} thread{'s' if threads != 1 else ''})", index_s))
        paths.OVERLAY.clear()
        arrays, arrays_s = timed(lambda: (paths.OVERLAY.update(bpy.context), paths.OVERLAY.arrays)[1])
        rows.append((f"path arrays ({arrays.worlds_drawn:,} worlds, {arrays.vertex_count:,} vertices)", arrays_s))
    finally:
        SESSION.close()
        paths.OVERLAY.clear()
        many_worlds.unregister()
    return rows


def one_run(path):
    """(seconds to the first paths, seconds to a complete index, worlds drawn first)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    many_worlds.register()
    try:
        paths.OVERLAY.clear()
        start = time.perf_counter()
        assert libraries.open_library(path, bpy.context.scene)
        assert paths.OVERLAY.update(bpy.context) and paths.OVERLAY.arrays.vertex_count > 0
        first_s = time.perf_counter() - start
        drawn = paths.OVERLAY.arrays.worlds_drawn
        index = SESSION.query.index
        while index.world_count < len(SESSION.view.world_indices):
            assert time.perf_counter() - start < INDEX_TIMEOUT_S, "the index did not complete"
            time.sleep(0.005)
        return first_s, time.perf_counter() - start, drawn
    finally:
        SESSION.close()
        paths.OVERLAY.clear()
        many_worlds.unregister()


def main():
    path, sampled_s = library_path(build_dir())
    if sampled_s:
        print(f"sampled {WORLDS:,} worlds in {sampled_s:.0f} s -> {path}")
    print(f"{'phase (alone)':<52} {'s':>7}")
    for name, seconds in phases(path):
        print(f"{name:<52} {seconds:>7.3f}")
    runs = [one_run(path) for _ in range(RUNS)]
    print(f"\n{'run':>4} {'first paths s':>14} {'worlds drawn':>13} {'index complete s':>17}")
    for k, (first_s, index_s, drawn) in enumerate(runs):
        print(f"{k + 1:>4} {first_s:>14.3f} {drawn:>13,} {index_s:>17.3f}")
    print(f"BENCH open_library_s_{WORLDS} {statistics.median(r[0] for r in runs):.3f}")
    print(f"BENCH open_library_index_s_{WORLDS} {statistics.median(r[1] for r in runs):.3f}")


main()
