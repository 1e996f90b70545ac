"""Benchmark: from pressing Sample to the first world in the browsing view, on the quick-start scene.

blender -b --factory-startup --python tests/bench/bench_first_world.py
Opens blend_examples/quickstart/quickstart.blend from a copy in a temporary folder (the library is
written next to it), invokes the Sample operator and calls the add-on's poller the way its
bpy.app.timers timer does, until the LibraryView holds a world. Two cadences:
- `timer`: every POLL_INTERVAL_S, as in the UI (what the user sees; includes up to one interval);
- `tight`: every 2 ms (the engine's and the reader's own latency).
Prints a table and `BENCH first_world_visible_s <seconds>` (median of the timer cadence).
"""
import os
import shutil
import statistics
import sys
import tempfile
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))

import many_worlds  # noqa: E402
from many_worlds.core.session import SESSION  # noqa: E402
from many_worlds.operators import run_poller  # noqa: E402

EXAMPLE = os.path.join(ROOT, "blend_examples", "quickstart", "quickstart.blend")
RUNS = 3
WORLDS = 200


def one_run(folder, interval_s):
    """Seconds from Sample to the first world in SESSION.view, polling every interval_s."""
    blend = os.path.join(folder, "quickstart.blend")
    shutil.copy(EXAMPLE, blend)
    bpy.ops.wm.open_mainfile(filepath=blend)
    settings = bpy.context.scene.mwb
    settings.library_path = "//quickstart_bench.mwb"
    settings.world_count = WORLDS
    start = time.perf_counter()
    assert bpy.ops.mwb.sample() == {"FINISHED"}, SESSION.status
    # The timer's first call comes one interval after Sample returns; then every interval.
    while True:
        time.sleep(interval_s)
        run_poller.poll_run()
        if SESSION.view is not None and SESSION.view.world_indices:
            seen = time.perf_counter() - start
            break
        assert SESSION.run is not None, f"sampling ended without a world: {SESSION.status}"
        assert time.perf_counter() - start < 60, "no world after 60 s"
    run_poller.stop_for_unregister()
    return seen


def main():
    if not os.path.isfile(EXAMPLE):
        sys.exit(f"bench_first_world: {EXAMPLE} is missing (run blend_examples/quickstart/build_quickstart.py)")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    many_worlds.register()
    cadences = (("timer", run_poller.POLL_INTERVAL_S), ("tight", 0.002))
    times = {name: [] for name, _ in cadences}
    try:
        for run in range(RUNS):
            for name, interval in cadences:
                with tempfile.TemporaryDirectory(prefix="mwb-bench-") as folder:
                    times[name].append(one_run(folder, interval))
    finally:
        many_worlds.unregister()
    print(f"{'cadence':>8} {'poll s':>7} {'runs':>5} {'median s':>9} {'best s':>7} {'worst s':>8}")
    for name, interval in cadences:
        values = times[name]
        print(f"{name:>8} {interval:>7.3f} {len(values):>5} {statistics.median(values):>9.3f} "
              f"{min(values):>7.3f} {max(values):>8.3f}")
    print(f"BENCH first_world_visible_s {statistics.median(times['timer']):.4f}")


main()
