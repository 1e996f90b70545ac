#!/bin/sh
# The add-on's command line driving the Windows engine under wine64: `blender -b` (Blender 3.4)
# runs addon/many_worlds/cli.py on the quick-start example, once with the Linux engine and once
# with MWB_ENGINE_COMMAND="wine64 build-windows/native/mwb-engine.exe", the add-on's one seam for
# how the engine is started (core/paths.py):
#   - `sample` of 8 worlds, a refinement of world 3 (the command line has no refine: the add-on's
#     core/engine.py runs it, as the Refine button does) and a `seek` of at most 30 worlds; the
#     two libraries must hold the same worlds byte for byte (compare_libraries.py: all but the
#     engine build each file records);
#   - a `sample` of many worlds through wine interrupted with SIGINT once worlds arrive: the
#     command line cancels through the engine protocol and exits with EngineExit.CANCELLED (130),
#     and the library it leaves opens without a warning and holds only whole worlds, each the
#     Linux engine's world of the same index (compare_libraries.py --within).
# Needs build-windows/native/mwb-engine.exe (native/release/windows/build_windows.sh, or
# tests/windows/run.sh), wine64 and blender; otherwise prints "skipped: <reason>" and exits with
# $MWB_SKIP_STATUS (default 0). About 20 s on two cores.
#   tests/windows/cli_under_wine.sh [LINUX_ENGINE]      (default: the add-on's bin/mwb-engine)
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
LINUX_ENGINE=${1:-$ROOT/addon/many_worlds/bin/mwb-engine}
BUILD=${MWB_WINDOWS_BUILD:-$ROOT/build-windows}
WINDOWS_ENGINE=$BUILD/native/mwb-engine.exe
BLEND=$ROOT/blend_examples/quickstart/quickstart.blend
CLI=$ROOT/addon/many_worlds/cli.py
COMPARE=$ROOT/tests/windows/compare_libraries.py
CANCELLED=130  # EngineExit.CANCELLED
# Over the quick-start camera's view: the marble in the left bin, the cone in the middle one, the
# pill in the right one (tests/cli/test_cli.py's goal, rarely met in 30 worlds).
GOAL="--box 0.32,0.22,0.38,0.40 --objects Marble --time 3,4 --box 0.40,0.19,0.46,0.37 --objects Cone --time 3,4
      --box 0.50,0.15,0.557,0.33 --objects Pill --time 3,4"

skip() {
    echo "skipped: $*"
    exit "${MWB_SKIP_STATUS:-0}"
}

fail() {
    echo "FAIL: $*"
    exit 1
}

find_wine() {
    for wine in /usr/lib/wine/wine64 "$(command -v wine64 || true)" "$(command -v wine || true)"; do
        [ -n "$wine" ] && [ -x "$wine" ] && { echo "$wine"; return 0; }
    done
    return 1
}

[ -f "$WINDOWS_ENGINE" ] || skip "no Windows engine at $WINDOWS_ENGINE (native/release/windows/build_windows.sh builds it)"
WINE=$(find_wine) || skip "no wine64 (Debian package wine64)"
command -v blender > /dev/null || skip "no blender"
[ -x "$LINUX_ENGINE" ] || skip "no Linux engine at $LINUX_ENGINE to compare worlds with (build the host first)"

# A wine prefix of our own, kept with the build (run.sh makes it); wine's messages off.
export WINEPREFIX="$BUILD/wine-prefix" WINEDEBUG=-all
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"; "$(dirname "$WINE")/wineserver64" -k 2> /dev/null || wineserver -k 2> /dev/null || true' EXIT
cd "$WORK"

# The add-on's refinement (core/engine.py's RefineRequest, as the Refine button runs it): 3 children
# of world 3 of the library given re-simulating the marble and the die from 0.5 s.
cat > refine.py << 'EOF'
import json
import sys

from many_worlds import _native
from many_worlds.core import engine

library = sys.argv[1]
names = [body["name"] for body in json.loads(_native.Library(library).header.scene_json)["bodies"]]
run = engine.run_to_end(engine.RefineRequest(library, 3, (names.index("Marble"), names.index("Die")), 0.5, 3,
                                             threads=2))
if run.failure() is not None:
    sys.exit(f"refine: {run.failure().message}")
EOF
# "COUNT LAST": the worlds a library holds and the highest index ("0" before it exists); with
# "whole", a library with a warning (a torn or damaged record) fails.
cat > worlds.py << 'EOF'
import os
import sys

from many_worlds import _native

path = sys.argv[1]
if not os.path.exists(path):
    print(0)
    sys.exit()
library = _native.Library(path)
if library.warnings and sys.argv[2:] == ["whole"]:
    sys.exit(f"{path}: {library.warnings[0]}")
print(len(library.world_indices), max(library.world_indices, default=-1))
EOF
worlds() {
    PYTHONPATH="$ROOT/addon" python3 worlds.py "$@"
}

# with_engine SIDE COMMAND...: COMMAND with the engine of SIDE (linux or windows) for the add-on.
with_engine() {
    side=$1
    shift
    if [ "$side" = windows ]; then
        MWB_ENGINE_COMMAND="'$WINE' '$WINDOWS_ENGINE'" "$@"
    else
        (unset MWB_ENGINE_COMMAND; MWB_ENGINE="$LINUX_ENGINE" "$@")
    fi
}

# cli SIDE COMMAND [options]: the add-on's command line; its output in SIDE-COMMAND.log.
cli() {
    side=$1
    shift
    status=0
    with_engine "$side" blender -b --factory-startup "$BLEND" --python-exit-code 1 --python "$CLI" -- "$@" \
        > "$side-$1.log" 2>&1 || status=$?
    [ "$status" -eq 0 ] || { tail -n 20 "$side-$1.log"; fail "$side: many_worlds $1 exited with $status"; }
}

for side in linux windows; do
    cli "$side" sample --worlds 0:8 --threads 2 --out "$WORK/$side.mwb"
    with_engine "$side" env PYTHONPATH="$ROOT/addon" python3 refine.py "$WORK/$side.mwb" > "$side-refine.log" 2>&1 ||
        { tail -n 20 "$side-refine.log"; fail "$side: the refinement failed"; }
    # shellcheck disable=SC2086
    cli "$side" seek "$WORK/$side.mwb" $GOAL --want 1 --budget 30 --seed 7 --threads 2 --json
done
# The Linux engine's merge writes each file's worlds in index order, so the two compare.
"$LINUX_ENGINE" merge linux-merged.mwb linux.mwb > /dev/null
"$LINUX_ENGINE" merge windows-merged.mwb windows.mwb > /dev/null
python3 "$COMPARE" windows-merged.mwb linux-merged.mwb > compare.log ||
    { cat compare.log; fail "the worlds the command line made with mwb-engine.exe differ from the Linux engine's"; }
made=$(worlds linux.mwb whole)

# Ctrl-C to the command line (Blender itself, started here) once 20 worlds are stored.
MWB_ENGINE_COMMAND="'$WINE' '$WINDOWS_ENGINE'" blender -b --factory-startup "$BLEND" --python-exit-code 1 \
    --python "$CLI" -- sample --worlds 0:100000 --threads 2 --out "$WORK/cancelled.mwb" > windows-cancel.log 2>&1 &
sampler=$!
waited=0
until [ "$(worlds cancelled.mwb | cut -d' ' -f1)" -ge 20 ]; do
    kill -0 "$sampler" 2> /dev/null || { tail -n 20 windows-cancel.log; fail "the sample under wine ended before Ctrl-C"; }
    [ "$waited" -lt 240 ] || { kill -KILL "$sampler"; fail "no 20 worlds stored under wine in 2 minutes"; }
    sleep 0.5
    waited=$((waited + 1))
done
kill -INT "$sampler"
waited=0
while kill -0 "$sampler" 2> /dev/null && [ "$waited" -lt 120 ]; do
    sleep 0.5
    waited=$((waited + 1))
done
kill -0 "$sampler" 2> /dev/null && { kill -KILL "$sampler"; fail "the command line did not stop within a minute of Ctrl-C"; }
status=0
wait "$sampler" || status=$?
[ "$status" -eq "$CANCELLED" ] ||
    { tail -n 20 windows-cancel.log; fail "after Ctrl-C the command line exited with $status, not $CANCELLED (cancelled)"; }
kept=$(worlds cancelled.mwb whole) || fail "the library left after Ctrl-C does not open without a warning"
cli linux sample --worlds "0:$((${kept#* } + 1))" --threads 2 --out "$WORK/cancel-linux.mwb"
python3 "$COMPARE" --within cancelled.mwb cancel-linux.mwb > compare-cancel.log ||
    { cat compare-cancel.log; fail "the worlds kept after Ctrl-C under wine differ from the Linux engine's"; }
echo "cli-under-wine: many_worlds sample, refine and seek made the same ${made%% *} worlds with mwb-engine.exe" \
     "under wine as with the Linux engine; after Ctrl-C it exited cancelled and kept ${kept%% *} whole worlds," \
     "each the Linux engine's"
