#!/bin/sh
# Viewport test under Xvfb with the real Blender UI. Makes a throwaway Blender config and a .blend
# with a sampled library (for the Seek test: a fresh copy of the quick-start example, which the
# test samples itself), then runs one test script (default: test_paths_drawn.py) that checks the
# overlays in screenshots. Keeps the screenshots in $MWB_VIEWPORT_OUT/<test name> (default: a
# temporary folder, printed).
#   tests/viewport/run.sh [test_box_tool.py]
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
TEST=${1:-test_paths_drawn.py}
WORK=$(mktemp -d)
OUT=${MWB_VIEWPORT_OUT:-$WORK/out}/${TEST%.py}
mkdir -p "$OUT" "$WORK/tmp" "$WORK/config" "$WORK/scripts/addons"
ln -s "$ROOT/addon/many_worlds" "$WORK/scripts/addons/many_worlds"
export TMPDIR="$WORK/tmp" BLENDER_USER_CONFIG="$WORK/config" BLENDER_USER_SCRIPTS="$WORK/scripts"
case $TEST in
test_seek.py)
    # A bundled example as a user would start from it: no library beside it yet.
    rm -f "$OUT"/quickstart*
    cp "$ROOT/blend_examples/quickstart/quickstart.blend" "$OUT/quickstart.blend"
    BLEND=$OUT/quickstart.blend ;;
*)
    blender -b --factory-startup --python-exit-code 1 --python "$ROOT/tests/viewport/make_fixture.py" -- "$OUT" \
        > "$WORK/fixture.log" 2>&1 || { cat "$WORK/fixture.log"; exit 1; }
    BLEND=$OUT/paths.blend ;;
esac
status=0
# --enable-event-simulate: the box tool test drives the mouse with window.event_simulate (real
# input is ignored then, which also keeps the other test independent of the X server's pointer).
# --python-exit-code: a test script that fails as it starts (an import error) ends Blender at once
# instead of leaving the UI open until the timeout.
timeout 300 xvfb-run -a -s "-screen 0 1600x1000x24" \
    blender --factory-startup --enable-event-simulate --addons many_worlds "$BLEND" \
    --python-exit-code 1 --python "$ROOT/tests/viewport/$TEST" -- "$OUT" > "$OUT/blender.log" 2>&1 || status=$?
cat "$OUT/blender.log"
# A Python error while drawing a panel or the overlay is only printed, never raised: fail on it.
if grep -q "Traceback" "$OUT/blender.log"; then status=1; fi
echo "viewport screenshots in $OUT"
exit $status
