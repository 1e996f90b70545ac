#!/bin/sh
# Sets up (packages, configure, build) and runs every test: C++ unit tests, Python tests of the
# native module, tests inside Blender, and the corrupted-input replays of the fuzz targets.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
"$ROOT/tests/setup.sh"
ctest --test-dir "${MWB_BUILD_DIR:-$ROOT/build}" --output-on-failure -j2 "$@"
