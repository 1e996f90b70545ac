"""Builds every fidelity scene (scenes.py) and saves it as DIR/<scene>.blend, for a Blender that
lacks a tool the scenes are built with (Cell Fracture is bundled up to 4.1) to open, as an
animator opens an older file: compare.py reads them from $MWB_FIDELITY_SCENES.

    blender -b --factory-startup --python-exit-code 1 --python tests/fidelity/save_scenes.py -- DIR [SCENE ...]
"""
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(HERE)), "addon"))
sys.path.insert(0, HERE)
import scenes  # noqa: E402

# Scenes the other fidelity tests build beside the corpus's.
EXTRA = {"fracture_wall_on_mesh": lambda: scenes.fracture_wall(ground_shape="MESH")}

args = sys.argv[sys.argv.index("--") + 1:]
out = os.path.abspath(args[0])
builders = {**{name: build for name, (build, _) in scenes.SCENES.items()}, **EXTRA}
names = args[1:] or list(builders)
os.makedirs(out, exist_ok=True)
for name in names:
    build = builders[name]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build()
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out, f"{name}.blend"))
print(f"fidelity: saved {len(names)} scenes in {out}")
