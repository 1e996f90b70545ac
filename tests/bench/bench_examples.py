"""Benchmark: sampling speed per bundled example, and Blender's own Bullet bake of the same scene
and frame range against our time per world when sampling many worlds on all cores, side by side.

blender -b blend_examples/NAME/NAME.blend --python tests/bench/bench_examples.py -- WORLDS
Prints a table and `BENCH sample_worlds_per_min_NAME`, `BENCH bullet_speedup_NAME`,
`BENCH sleep_speedup_NAME` (the same sampling with sleeping off, divided by on) and
`BENCH prefix_speedup_NAME` (with shared prefixes off, divided by on; they apply only to scenes
whose initial states do not vary).
Both sides simulate the whole frame range (the engine without stopping at rest).
"""
import os
import subprocess
import sys
import tempfile
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import many_worlds  # noqa: E402
from many_worlds.core import paths  # noqa: E402
from many_worlds.export import export_and_validate  # noqa: E402


def bullet_bake_seconds(scene):
    """One world with Blender's own rigid-body simulation: bake the point cache of the frame range."""
    cache = scene.rigidbody_world.point_cache
    with bpy.context.temp_override(scene=scene, point_cache=cache):
        bpy.ops.ptcache.free_bake()
        start = time.perf_counter()
        bpy.ops.ptcache.bake(bake=True)
        elapsed = time.perf_counter() - start
        if not cache.is_baked:
            raise SystemExit("Blender's rigid-body bake did not run")
        bpy.ops.ptcache.free_bake()
    return elapsed


def engine_seconds_per_world(scene_json, worlds, folder, sleep=True, share_prefix=True):
    library = os.path.join(folder, f"bench_{'sleep' if sleep else 'awake'}_{'shared' if share_prefix else 'alone'}.mwb")
    command = [paths.engine_path(), "sample", "--scene", scene_json, "--out", library, "--worlds", f"0:{worlds}",
               "--no-stop-at-rest", "--threads", str(os.cpu_count())] + ([] if sleep else ["--no-sleep"]) + (
               [] if share_prefix else ["--no-shared-prefix"])
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return (time.perf_counter() - start) / worlds


def measure(name, worlds):
    """Times Blender's bake of the open scene against our sampling of it (with and without
    sleeping, with and without shared prefixes) and prints the figures; shared with
    bench_fracture.py."""
    many_worlds.register()
    result, problems = export_and_validate(bpy.context)
    if result.scene is None or problems:
        raise SystemExit(f"{name}: cannot export: {problems or result.problems}")
    with tempfile.TemporaryDirectory() as folder:
        scene_json = os.path.join(folder, "scene.json")
        with open(scene_json, "w") as f:
            f.write(result.to_json())
        ours = engine_seconds_per_world(scene_json, worlds, folder)
        awake = engine_seconds_per_world(scene_json, worlds, folder, sleep=False)
        alone = engine_seconds_per_world(scene_json, worlds, folder, share_prefix=False)
        varies = any(body.get("variation") for body in result.scene["bodies"])
    bullet = bullet_bake_seconds(bpy.context.scene)
    frames = bpy.context.scene.frame_end - bpy.context.scene.frame_start + 1
    print(f"{name}: {frames} frames; Bullet bake {bullet:.3f} s per world (1 thread); "
          f"ours {ours:.3f} s per world sampling {worlds} worlds on {os.cpu_count()} cores "
          f"({awake:.3f} s without sleeping, {alone:.3f} s without shared prefixes, which "
          f"{'do not apply: initial states vary' if varies else 'apply: no initial state varies'})")
    print(f"BENCH sample_worlds_per_min_{name} {60.0 / ours:.6g}")
    print(f"BENCH bullet_speedup_{name} {bullet / ours:.6g}")
    print(f"BENCH sleep_speedup_{name} {awake / ours:.6g}")
    print(f"BENCH prefix_speedup_{name} {alone / ours:.6g}")


if __name__ == "__main__":
    measure(os.path.splitext(os.path.basename(bpy.data.filepath))[0],
            int(sys.argv[sys.argv.index("--") + 1]) if "--" in sys.argv else 16)
