#!/bin/sh
# The main loop with the installed extension alone, in this Blender: in DIR, sample the quick-start
# example with `blender -c many_worlds`, describe the library, bake a world and check that the
# baked file plays it from its keys (tests/release/check_baked.py). Each step's output is kept in
# DIR (sample.log, info.txt, bake.log, check.log). The extension must be installed in the user
# folder Blender uses ($BLENDER_USER_RESOURCES).
#   tests/shared/extension_main_loop.sh DIR
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$1"
cp "$ROOT/blend_examples/quickstart/quickstart.blend" quickstart.blend
blender -b -c many_worlds sample quickstart.blend --worlds 0:8 --out L.mwb > sample.log 2>&1
blender -b -c many_worlds info L.mwb > info.txt 2>&1
blender -b -c many_worlds bake L.mwb --blend quickstart.blend --world 3 --out baked.blend > bake.log 2>&1
blender -b baked.blend --python-exit-code 1 --python "$ROOT/tests/release/check_baked.py" > check.log 2>&1
