"""Benchmark: sampling that survives faults. Worlds run in supervised worker processes; this
measures what that costs against sampling in the engine's own process (the same engine, side by
side, alternating), and checks that a run with crashing and hanging worlds loses nothing else.

/usr/bin/python3 tests/bench/bench_faults.py BUILD_DIR
Prints a table and `BENCH supervised_throughput_ratio`, `worlds_per_min_50body_engine`,
`fault_worlds_lost`, `supervised_seek_ratio` (a goal search's wall time in its own threads /
with every world in a worker process: each worker re-simulates the parents it did not make) and
the same for refinement and search on a scene of Blender's default shapes (convex hulls),
`supervised_hull_refine_ratio` and `supervised_hull_seek_ratio`.
"""
import json
import shutil
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

from many_worlds import _native  # noqa: E402

BUILD = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
ENGINE = os.path.join(BUILD, "native", "mwb-engine")
PILE = os.path.join(ROOT, "tests", "bench", "pile50.json")
QUICKSTART = os.path.join(ROOT, "tests", "scenes", "quickstart.json")
DEFAULTS = os.path.join(ROOT, "tests", "scenes", "blender_defaults.json")


def report(name, value, unit, note=""):
    print(f"  {name:<36} {value:14.4f}  {unit:<12} {note}")
    print(f"BENCH {name} {value:.6g}", flush=True)


def timed_sample(folder, scene, worlds, *extra, env=None):
    out = os.path.join(folder, f"run{time.monotonic_ns()}.mwb")
    start = time.perf_counter()
    subprocess.run([ENGINE, "sample", "--scene", scene, "--out", out, "--worlds", f"0:{worlds}", "--threads", "2",
                    *extra], check=True, capture_output=True, env=env)
    return time.perf_counter() - start, out


def main():
    print("Supervised sampling (worker processes) against in-process, 50-box pile, 2 threads")
    with tempfile.TemporaryDirectory() as folder:
        worlds = 32
        ratios, supervised_s = [], []
        for _ in range(3):
            inside, _ = timed_sample(folder, PILE, worlds, "--in-process")
            outside, _ = timed_sample(folder, PILE, worlds)
            ratios.append(inside / outside)
            supervised_s.append(outside)
        report("supervised_throughput_ratio", statistics.median(ratios), "x",
               "worlds/s supervised / in-process, median of 3 pairs (target >= 0.97)")
        report("worlds_per_min_50body_engine", 60 * worlds / statistics.median(supervised_s), "worlds/min",
               "the engine as the add-on runs it, 5 s worlds")

        faults = {5: "abort", 17: "segv", 33: "hang", 48: "abort"}
        env = dict(os.environ, MWB_ENGINE_TEST_FAULTS=",".join(f"{w}:{f}" for w, f in faults.items()))
        _, faulty = timed_sample(folder, QUICKSTART, 60, "--world-time-limit", "5", env=env)
        _, clean = timed_sample(folder, QUICKSTART, 60, "--in-process")
        got, want = _native.Library(faulty), _native.Library(clean)
        lost = 0
        for w in set(range(60)) - set(faults):
            same = w in got.world_indices and (got.positions(w) == want.positions(w)).all()
            lost += not same
        report("fault_worlds_lost", lost, "worlds", f"beyond the {len(faults)} faulty ones of 60 (target 0)")

        # A goal search of a fixed budget in worlds makes the same worlds either way.
        _, base = timed_sample(folder, QUICKSTART, 8)
        upright = {"within_deg": 8, "time_window": [3.0, 4.0]}
        goal = write_goal(folder, "upright", [dict(upright, objects=[o]) for o in ("Die", "Can", "Cone")])
        report("supervised_seek_ratio", in_process_over_supervised(folder, base, "seek", "--goal", goal,
                                                                   "--budget-worlds", "400", "--seed", "1"),
               "x", "seek wall time in-process / supervised, 400 quick-start worlds, median of 3 pairs")

        # Blender's default shapes: every refined child has ghosts grown from hulls.
        _, base = timed_sample(folder, DEFAULTS, 8)
        with open(DEFAULTS) as f:
            names = [b["name"] for b in json.load(f)["bodies"]]
        bodies = f"{names.index('Sphere')},{names.index('Bottle.000')}"
        report("supervised_hull_refine_ratio",
               in_process_over_supervised(folder, base, "refine", "--world", "3", "--bodies", bodies, "--time", "0.8",
                                          "--count", "32"),
               "x", "refine wall time in-process / supervised, 32 children of two hulls, median of 3 pairs")
        standing = {"within_deg": 10, "time_window": [2.0, 3.0]}
        goal = write_goal(folder, "standing", [dict(standing, objects=["Bottle.000", "Bottle.002"])])
        report("supervised_hull_seek_ratio",
               in_process_over_supervised(folder, base, "seek", "--goal", goal, "--budget-worlds", "300", "--seed", "1"),
               "x", "seek wall time in-process / supervised, 300 worlds of default-shape hulls, median of 3 pairs")


def write_goal(folder, name, orientations):
    goal = os.path.join(folder, f"{name}.goal.json")
    with open(goal, "w") as f:
        json.dump({"boxes": [], "orientations": orientations}, f)
    return goal


def in_process_over_supervised(folder, base, command, *args):
    """Wall time of `command` on a copy of library `base` in the engine's threads / in its worker
    processes, 2 threads, median of 3 pairs run alternately (the worlds are the same either way)."""
    ratios = []
    for _ in range(3):
        times = {}
        for mode, extra in (("inside", ["--in-process"]), ("outside", [])):
            library = os.path.join(folder, f"{command}_{mode}.mwb")
            shutil.copy(base, library)
            start = time.perf_counter()
            subprocess.run([ENGINE, command, "--library", library, *args, "--threads", "2", *extra], check=True,
                           capture_output=True)
            times[mode] = time.perf_counter() - start
        ratios.append(times["inside"] / times["outside"])
    return statistics.median(ratios)


if __name__ == "__main__":
    main()
