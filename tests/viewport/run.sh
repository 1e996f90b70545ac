#!/bin/sh
# Viewport test under Xvfb with the real Blender UI. Makes a throwaway Blender config, a .blend
# with a sampled library, then checks the path overlay in screenshots. Keeps the screenshots in
# $MWB_VIEWPORT_OUT (default: a temporary folder, printed).
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
WORK=$(mktemp -d)
OUT=${MWB_VIEWPORT_OUT:-$WORK/out}
mkdir -p "$OUT" "$WORK/tmp" "$WORK/config" "$WORK/scripts/addons"
ln -s "$ROOT/addon/many_worlds" "$WORK/scripts/addons/many_worlds"
export TMPDIR="$WORK/tmp" BLENDER_USER_CONFIG="$WORK/config" BLENDER_USER_SCRIPTS="$WORK/scripts"
blender -b --factory-startup --python-exit-code 1 --python "$ROOT/tests/viewport/make_fixture.py" -- "$OUT" \
    > "$WORK/fixture.log" 2>&1 || { cat "$WORK/fixture.log"; exit 1; }
status=0
timeout 300 xvfb-run -a -s "-screen 0 1600x1000x24" \
    blender --factory-startup --addons many_worlds "$OUT/paths.blend" \
    --python "$ROOT/tests/viewport/test_paths_drawn.py" -- "$OUT" > "$OUT/blender.log" 2>&1 || status=$?
cat "$OUT/blender.log"
# A Python error while drawing a panel or the overlay is only printed, never raised: fail on it.
if grep -q "Traceback" "$OUT/blender.log"; then status=1; fi
echo "viewport screenshots in $OUT"
exit $status
