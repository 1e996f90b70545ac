"""Checks, inside a Blender that loaded the preferences, the extension that extension_check.sh
installed: enabled, registered, its native module imported from its wheel (not from a checkout),
and its engine executable runnable (zip extraction drops permission bits).

blender -b --python-exit-code 1 --python tests/blender4/check_installed_extension.py -- ROOT WORK
"""
import os
import subprocess
import sys

import addon_utils
import bpy

MODULE = "bl_ext.user_default.many_worlds"


def check(root, work):
    assert MODULE in bpy.context.preferences.addons, sorted(bpy.context.preferences.addons.keys())
    enabled, loaded = addon_utils.check(MODULE)
    assert enabled and loaded, (enabled, loaded)
    assert hasattr(bpy.types.Scene, "mwb"), "the add-on's scene settings are not registered"
    assert hasattr(bpy.ops.mwb, "sample"), "the Sample operator is not registered"

    package = sys.modules[MODULE]
    assert os.path.realpath(package.__file__).startswith(os.path.realpath(work)), package.__file__
    from bl_ext.user_default.many_worlds import _native
    tag = f"cpython-{sys.version_info.major}{sys.version_info.minor}"
    assert tag in _native.__file__ and os.sep + "site-packages" + os.sep in _native.__file__, _native.__file__
    with open(os.path.join(root, "tests", "scenes", "quickstart.json")) as f:
        scene = _native.Scene.from_json(f.read())
    worlds = _native.sample(scene, _native.SimulationParameters(), 1, 0, 2, threads=1)
    assert len(worlds) == 2

    from bl_ext.user_default.many_worlds.core import paths
    engine = paths.engine_path()
    assert os.path.realpath(engine).startswith(os.path.realpath(work)), engine
    result = subprocess.run([engine, "validate", os.path.join(root, "tests", "scenes", "quickstart.json")],
                            capture_output=True, text=True)
    assert result.returncode == 0, (result.returncode, result.stderr)
    print(f"extension: enabled as {MODULE}, native module {os.path.basename(_native.__file__)}, engine runs")


check(*sys.argv[sys.argv.index("--") + 1:][:2])
