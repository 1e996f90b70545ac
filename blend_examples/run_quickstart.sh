#!/bin/sh
# The main job: set up, sample the quick-start scene with the engine, and summarize the library.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${MWB_BUILD_DIR:-$ROOT/build}
"$ROOT/tests/setup.sh"
OUT="$BUILD/quickstart"
mkdir -p "$OUT"
rm -f "$OUT/quickstart.mwb"
"$BUILD/native/mwb-engine" sample --scene "$ROOT/tests/scenes/quickstart.json" --out "$OUT/quickstart.mwb" \
    --seed 1 --worlds 0:200 --threads "$(nproc)"
"$BUILD/native/mwb-engine" info "$OUT/quickstart.mwb"
PYTHONPATH="$ROOT/addon" /usr/bin/python3 "$ROOT/blend_examples/summarize_library.py" "$OUT/quickstart.mwb"
echo "library: $OUT/quickstart.mwb"
