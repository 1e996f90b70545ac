"""Builds the viewport test's .blend and its library: a ground and three boxes dropped with some
spread, sampled through the add-on's Sample operator (the real engine child process).

blender -b --factory-startup --python tests/viewport/make_fixture.py -- OUT_DIR
Writes OUT_DIR/paths.blend and OUT_DIR/paths.mwb (the default library next to the .blend).
"""
import os
import sys
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.join(ROOT, "tests", "blender"))

import many_worlds  # noqa: E402
from conftest import drop_scene  # noqa: E402
from many_worlds.operators import run_poller  # noqa: E402

WORLDS = 24


def main(out_dir):
    bpy.ops.wm.read_factory_settings(use_empty=False)
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob)
    many_worlds.register()
    drop_scene(bodies=3)
    os.makedirs(out_dir, exist_ok=True)
    # Start a new library: Sample would otherwise add worlds to one left by an earlier run (or to
    # the libraries a changed run started beside it).
    for name in os.listdir(out_dir):
        if name.startswith("paths") and name.endswith((".blend", ".mwb", ".scene.json")):
            os.remove(os.path.join(out_dir, name))
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, "paths.blend"))
    bpy.context.scene.mwb.world_count = WORLDS
    assert bpy.ops.mwb.sample() == {"FINISHED"}
    deadline = time.monotonic() + 120
    while run_poller.poll_run() is not None:
        assert time.monotonic() < deadline, "sampling did not finish"
        time.sleep(0.05)
    for ob in bpy.data.objects:
        ob.select_set(False)
    bpy.ops.wm.save_mainfile()
    many_worlds.unregister()


main(sys.argv[sys.argv.index("--") + 1])
