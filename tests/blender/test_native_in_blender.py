"""The native module inside Blender's own Python: it imports, samples, and ODE's random calls
reach the engine's per-world generator (symbol lookup in a module loaded by Blender)."""
import os

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def test_module_samples_deterministically_inside_blender():
    from many_worlds import _native
    with open(os.path.join(ROOT, "tests", "scenes", "quickstart.json")) as f:
        scene = _native.Scene.from_json(f.read())
    before = _native.ode_random_calls_on_this_thread()
    one = [w.hash for w in _native.sample(scene, _native.SimulationParameters(), 2, 0, 3, threads=1)]
    assert _native.ode_random_calls_on_this_thread() - before > 1000
    two = [w.hash for w in _native.sample(scene, _native.SimulationParameters(), 2, 0, 3, threads=2)]
    assert one == two
    assert bpy.app.version >= (3, 4, 0)
