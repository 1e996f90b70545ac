"""Benchmark: sampling that survives faults. Worlds run in supervised worker processes; this
measures what that costs against sampling in the engine's own process (the same engine, side by
side, alternating), and checks that a run with crashing and hanging worlds loses nothing else.

/usr/bin/python3 tests/bench/bench_faults.py BUILD_DIR
Prints a table and `BENCH supervised_throughput_ratio`, `worlds_per_min_50body_engine`,
`fault_worlds_lost` and `supervised_seek_ratio` (a goal search's wall time in its own threads /
with every world in a worker process: each worker re-simulates the parents it did not make).
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
        goal = os.path.join(folder, "upright.goal.json")
        with open(goal, "w") as f:
            upright = {"within_deg": 8, "time_window": [3.0, 4.0]}
            json.dump({"boxes": [], "orientations": [dict(upright, objects=[o]) for o in ("Die", "Can", "Cone")]}, f)
        seek_ratios = []
        for _ in range(3):
            times = {}
            for mode, extra in (("inside", ["--in-process"]), ("outside", [])):
                library = os.path.join(folder, f"seek_{mode}.mwb")
                shutil.copy(base, library)
                start = time.perf_counter()
                subprocess.run([ENGINE, "seek", "--library", library, "--goal", goal, "--budget-worlds", "400",
                                "--seed", "1", "--threads", "2", *extra], check=True, capture_output=True)
                times[mode] = time.perf_counter() - start
            seek_ratios.append(times["inside"] / times["outside"])
        report("supervised_seek_ratio", statistics.median(seek_ratios), "x",
               "seek wall time in-process / supervised, 400 quick-start worlds, median of 3 pairs")


if __name__ == "__main__":
    main()
