"""Benchmark: convex pieces passing through a passive mesh (tests/fidelity/tunnel.py).

blender -b --factory-startup --python tests/bench/bench_tunnel.py [-- WORLDS]
Prints `BENCH tunnel_worlds_per_1000` (target 0) and `tunnel_pieces`.
"""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.join(ROOT, "tests", "fidelity"))
sys.path.insert(0, os.path.join(ROOT, "tests", "shared"))

import tunnel  # noqa: E402
from factory_scene import factory_scene_with_addon  # noqa: E402


def report(name, value, unit, note=""):
    print(f"  {name:<36} {value:14.4f}  {unit:<12} {note}")
    print(f"BENCH {name} {value:.6g}", flush=True)


args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
worlds = int(args[0]) if args else 200
with factory_scene_with_addon():
    pieces, stored, tunnelled_worlds, tunnelled_pieces = tunnel.sample_fracture_wall_on_mesh(worlds)
print(f"Cell Fracture wall ({pieces} convex pieces) on a MESH plane, {stored} worlds")
report("tunnel_worlds_per_1000", 1000.0 * tunnelled_worlds / max(stored, 1), "worlds",
       "worlds where a piece ends below the mesh it started above (target 0)")
report("tunnel_pieces", tunnelled_pieces, "pieces", f"in all {stored} worlds")
