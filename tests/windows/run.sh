#!/bin/sh
# The Windows cross test (CTest label windows-cross): ODE, the core, the engine, the module for
# Python 3.11 and 3.13 and the native tests cross-compiled for 64-bit Windows with MinGW-w64
# (native/release/windows/build_windows.sh, cached in build-windows/); the modules' import and
# export tables checked (check_module_imports.py); the windows-x64 extension zip built from the
# stripped copies in build-windows/dist, checked and validated by Blender 4.3 (extension_zip.sh,
# in the Debian 13 chroot when root); then under wine64:
#   - the GoogleTest programs of the core (every test but those named in WINDOWS_EXCLUDED below);
#   - `mwb-engine.exe sample` (resumed once) and `refine` on a scene with every shape kind and
#     joints, in supervised worker processes, and again with faults injected into some worlds, whose library must hold byte for byte the worlds the Linux engine makes with the same
#     seeds (compare_libraries.py: all but the engine build each file records), and which the
#     Linux engine reads and merges.
# Installs mingw-w64, g++-mingw-w64-x86-64-posix, libz-mingw-w64-dev and wine64 when root and
# missing; otherwise prints "skipped: <reason>" and exits with $MWB_SKIP_STATUS (default 0).
#   tests/windows/run.sh [LINUX_ENGINE]      (default: the add-on's bin/mwb-engine)
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
LINUX_ENGINE=${1:-$ROOT/addon/many_worlds/bin/mwb-engine}
BUILD=${MWB_WINDOWS_BUILD:-$ROOT/build-windows}
SCENE=$ROOT/tests/scenes/all_shapes_and_joints.json

skip() {
    echo "skipped: $*"
    exit "${MWB_SKIP_STATUS:-0}"
}

find_wine() {
    for wine in /usr/lib/wine/wine64 "$(command -v wine64 || true)" "$(command -v wine || true)"; do
        [ -n "$wine" ] && [ -x "$wine" ] && { echo "$wine"; return 0; }
    done
    return 1
}

missing=""
command -v x86_64-w64-mingw32-g++-posix > /dev/null || missing="$missing mingw-w64 g++-mingw-w64-x86-64-posix"
[ -f /usr/x86_64-w64-mingw32/lib/libz.a ] || missing="$missing libz-mingw-w64-dev"
find_wine > /dev/null || missing="$missing wine64"
[ -f /usr/src/googletest/CMakeLists.txt ] || missing="$missing googletest"
[ -f /usr/include/nlohmann/json.hpp ] || missing="$missing nlohmann-json3-dev"
if [ -n "$missing" ]; then
    [ "$(id -u)" -eq 0 ] || skip "the Windows cross build needs the Debian packages$missing (run as root to install them)"
    mkdir -p "$BUILD"
    apt-get update -qq > "$BUILD/apt.log" 2>&1 || true
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $missing >> "$BUILD/apt.log" 2>&1 ||
        skip "could not install$missing (see $BUILD/apt.log)"
fi
[ -x "$LINUX_ENGINE" ] || skip "no Linux engine at $LINUX_ENGINE to compare worlds with (build the host first)"
WINE=$(find_wine)

sh "$ROOT/native/release/windows/build_windows.sh" "$BUILD"

# The modules, read from their import and export tables (no Windows Python can be run here): each
# exports PyInit__native and takes from python3XX.dll only what that version's headers declare.
# The check must also tell the versions apart: 3.13's module needs names 3.11 does not have.
for tag in 311 313; do
    python3 "$ROOT/tests/windows/check_module_imports.py" "$BUILD/modules/_native.cp$tag-win_amd64.pyd" \
        "$BUILD/python-headers/python3.${tag#3}/python$tag.def" || exit 1
done
if python3 "$ROOT/tests/windows/check_module_imports.py" "$BUILD/modules/_native.cp313-win_amd64.pyd" \
    "$BUILD/python-headers/python3.11/python311.def" > /dev/null; then
    echo "FAIL: the import check takes the 3.13 module for one 3.11 could load"
    exit 1
fi
# The windows-x64 extension zip from the stripped binaries in $BUILD/dist: reproducible, what it
# holds, and Blender 4.3's `extension validate` in the Debian 13 chroot.
MWB_WINDOWS_BUILD=$BUILD sh "$ROOT/tests/windows/extension_zip.sh"

# A wine prefix of our own, kept with the build (making one takes seconds); wine's messages off.
export WINEPREFIX="$BUILD/wine-prefix" WINEDEBUG=-all
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"; "$(dirname "$WINE")/wineserver64" -k 2> /dev/null || wineserver -k 2> /dev/null || true' EXIT
cd "$WORK"

# Left out on Windows, and why:
#   PortableMath.SinAndCosStayWithinTwoUlpsOfTheCLibraryOverManyTurns measures our sin and cos
#   against the C library's, which on Windows (msvcrt) is itself hundreds of ulps off for large
#   arguments: the reference, not our code, differs. Our functions are the same code on every
#   system, so the Linux run of this test covers them.
WINDOWS_EXCLUDED=PortableMath.SinAndCosStayWithinTwoUlpsOfTheCLibraryOverManyTurns
passed=0
failed=0
for suite in scene codec sim library query; do
    exe=$BUILD/tests/mwb_${suite}_tests.exe
    if "$WINE" "$exe" --gtest_brief=1 --gtest_filter="-$WINDOWS_EXCLUDED" > "$suite.log" 2>&1; then
        count=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) tests\{0,1\}\..*/\1/p' "$suite.log")
        echo "mwb_${suite}_tests.exe under wine: ${count:-?} tests passed"
        passed=$((passed + ${count:-0}))
    else
        echo "mwb_${suite}_tests.exe under wine FAILED:"
        tail -n 30 "$suite.log"
        failed=$((failed + 1))
    fi
done
# On Windows two threads, a run resumed in the same file and a refinement; on Linux one run of
# each. The Linux engine's merge writes each file's worlds in index order, so the two compare.
# The engine is the one the zip ships (stripped, in dist/).
win() { "$WINE" "$BUILD/dist/bin/mwb-engine.exe" "$@"; }
win sample --scene "$SCENE" --worlds 0:6 --threads 2 --out windows.mwb
win sample --scene "$SCENE" --worlds 0:12 --threads 2 --out windows.mwb
win refine --library windows.mwb --world 3 --bodies 2,3 --time 0.5 --count 3 --threads 2
"$LINUX_ENGINE" sample --scene "$SCENE" --worlds 0:12 --threads 1 --out linux.mwb > /dev/null
"$LINUX_ENGINE" refine --library linux.mwb --world 3 --bodies 2,3 --time 0.5 --count 3 --threads 1 > /dev/null
"$LINUX_ENGINE" info windows.mwb
"$LINUX_ENGINE" merge windows-merged.mwb windows.mwb > /dev/null
"$LINUX_ENGINE" merge linux-merged.mwb linux.mwb > /dev/null
python3 "$ROOT/tests/windows/compare_libraries.py" windows-merged.mwb linux-merged.mwb ||
    { echo "FAIL: the worlds sampled on Windows differ from Linux's (are both engines built from the same sources?)"; exit 1; }

# Worlds that abort, fault, print where ODE prints, or hang, each in its own worker: on Windows as
# on Linux each is a rejection naming the fault, and the library is the same file.
FAULTS="3:abort,5:segv,7:print,9:hang,14:segv"
MWB_ENGINE_TEST_FAULTS=$FAULTS win sample --scene "$SCENE" --worlds 0:12 --threads 2 --world-time-limit 5 \
    --out windows-faults.mwb > windows-faults.log 2>&1
MWB_ENGINE_TEST_FAULTS=$FAULTS win refine --library windows-faults.mwb --world 2 --bodies 2,3 --time 0.5 --count 4 \
    --threads 2 >> windows-faults.log 2>&1
MWB_ENGINE_TEST_FAULTS=$FAULTS "$LINUX_ENGINE" sample --scene "$SCENE" --worlds 0:12 --threads 1 --world-time-limit 5 \
    --out linux-faults.mwb > /dev/null 2>&1
MWB_ENGINE_TEST_FAULTS=$FAULTS "$LINUX_ENGINE" refine --library linux-faults.mwb --world 2 --bodies 2,3 --time 0.5 \
    --count 4 --threads 1 > /dev/null 2>&1
grep -q "Polygon 0 is not defined counterclockwise" windows-faults.log ||
    { echo "FAIL: a worker's print did not reach the log"; cat windows-faults.log; exit 1; }
# The hang is the third rejection; its words are checked by the comparison with Linux's file below.
for reason in "signal 6, Aborted" "signal 11, Segmentation fault" "3 rejected"; do
    grep -q "$reason" windows-faults.log ||
        { echo "FAIL: no world rejected for \"$reason\" under wine:"; cat windows-faults.log; exit 1; }
done
"$LINUX_ENGINE" merge windows-faults-merged.mwb windows-faults.mwb > /dev/null
"$LINUX_ENGINE" merge linux-faults-merged.mwb linux-faults.mwb > /dev/null
python3 "$ROOT/tests/windows/compare_libraries.py" windows-faults-merged.mwb linux-faults-merged.mwb ||
    { echo "FAIL: the supervised run with faults differs between Windows and Linux"; exit 1; }
[ "$failed" -eq 0 ] || { echo "FAIL: $failed of 5 Windows test programs failed (above)"; exit 1; }
# The add-on's command line driving the Windows engine over the typed protocol, cancel included.
MWB_WINDOWS_BUILD=$BUILD sh "$ROOT/tests/windows/cli_under_wine.sh" "$LINUX_ENGINE"
echo "windows-cross: $passed native tests passed under wine; mwb-engine.exe sampled and refined 15 worlds," \
     "and 16 with aborts, faults, prints and a hang in its workers, the same bytes as on Linux"
