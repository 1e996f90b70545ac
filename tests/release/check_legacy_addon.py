"""Inside Blender 3.x with a clean user folder: install the add-on zip as Preferences > Add-ons >
Install does, enable it, and check that its native module and engine are the zip's (not a
checkout's) and work.

    BLENDER_USER_SCRIPTS=WORK/scripts BLENDER_USER_CONFIG=WORK/config \\
        blender -b --python-exit-code 1 --python tests/release/check_legacy_addon.py -- ZIP WORK SCENE.json
"""
import os
import subprocess
import sys

import addon_utils
import bpy

zip_path, work, scene_path = sys.argv[sys.argv.index("--") + 1:][:3]
bpy.ops.preferences.addon_install(filepath=zip_path)
bpy.ops.preferences.addon_enable(module="many_worlds")
enabled, loaded = addon_utils.check("many_worlds")
assert enabled and loaded, (enabled, loaded)
assert hasattr(bpy.ops.mwb, "sample"), "the Sample operator is not registered"

package = sys.modules["many_worlds"]
installed = os.path.realpath(os.path.dirname(package.__file__))
assert installed.startswith(os.path.realpath(work)), f"the add-on loaded from {installed}, not the install"
from many_worlds import _native  # noqa: E402
assert os.path.realpath(_native.__file__).startswith(installed), _native.__file__
with open(scene_path) as f:
    scene = _native.Scene.from_json(f.read())
worlds = _native.sample(scene, _native.SimulationParameters(), 1, 0, 2, threads=2)
assert len(worlds) == 2

from many_worlds.core import paths  # noqa: E402
engine = paths.engine_path()
assert os.path.realpath(engine).startswith(installed), engine
library = os.path.join(work, "legacy.mwb")
result = subprocess.run([engine, "sample", "--scene", scene_path, "--worlds", "0:4", "--threads", "2",
                         "--out", library], capture_output=True, text=True)
assert result.returncode == 0, (result.returncode, result.stderr)
stored = len(_native.Library(library).world_indices)
assert stored == 4, f"the engine stored {stored} worlds, not 4"
print(f"release: add-on installed in {installed}, module {os.path.basename(_native.__file__)}, "
      f"engine sampled 4 worlds")
