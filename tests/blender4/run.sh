#!/bin/sh
# The add-on on Blender 4.3: Debian 12 ships only Blender 3.4, Debian 13 ships 4.3 (Python 3.13),
# so this runs in a debootstrapped Debian 13 chroot that is cached between runs
# ($MWB_TRIXIE_ROOT, default /var/cache/mwb/trixie). Steps, each timed:
#   1. create the chroot if missing, install the packages it lacks (both idempotent);
#   2. build the native module for Python 3.13 inside it (build-trixie/, under the build lock);
#   3. the same in-Blender test suite as on 3.4 (tests/blender), in Blender 4.3 headless;
#   4. the viewport tests under Xvfb (tests/viewport/run.sh);
#   5. the extension: build the zip, validate, install into a throwaway user folder, enable.
# Needs root (debootstrap, chroot, mount). Otherwise it prints one "skipped: <reason>" line and
# exits with $MWB_SKIP_STATUS (0 by default; CTest sets 77, its skip code).
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CHROOT=${MWB_TRIXIE_ROOT:-/var/cache/mwb/trixie}
SKIP_STATUS=${MWB_SKIP_STATUS:-0}
BUILD=$ROOT/build-trixie
PACKAGES="blender pybind11-dev python3-dev cmake g++ make patch pkg-config nlohmann-json3-dev
zlib1g-dev googletest libgtest-dev python3-pytest python3-numpy xvfb xauth"

skip() {
    echo "skipped: $*"
    exit "$SKIP_STATUS"
}

step_start=0
step() {
    step_start=$(date +%s)
    echo "== blender4: $*"
}
step_done() {
    echo "== blender4: $1 took $(( $(date +%s) - step_start )) s"
}

[ "$(id -u)" -eq 0 ] || skip "Blender 4.3 tests need root (debootstrap, chroot and mount)"

# The engine executable is the host's build (it runs in Debian 13 too); only the Python module
# must be rebuilt for Blender 4.3's Python.
[ -x "$ROOT/addon/many_worlds/bin/mwb-engine" ] || {
    echo "blender4: $ROOT/addon/many_worlds/bin/mwb-engine is missing: build on the host first (tests/setup.sh)"
    exit 1
}

# One run at a time per chroot: two runs would mount over each other and race apt.
mkdir -p "$(dirname "$CHROOT")"
exec 9>"$CHROOT.lock"
flock 9

. "$ROOT/native/release/debian_chroot.sh"
in_trixie() {
    in_chroot "$CHROOT" "$@"
}

# --- 1. the chroot (debootstrapped when missing, the packages it lacks installed) ---------------
step "the Debian 13 chroot in $CHROOT"
ensure_chroot "$CHROOT" trixie "$PACKAGES" || skip "the Debian 13 chroot could not be prepared"
step_done chroot

# --- mounts: /proc (Blender prints nothing useful without it) and this checkout at its own path,
# so paths are the same inside and out. Unmounted on any exit.
trap 'unmount_checkout "$CHROOT" "$ROOT"' EXIT
trap 'exit 130' INT TERM
mount_checkout "$CHROOT" "$ROOT"

# --- 2. the native module for Python 3.13 --------------------------------------------------------
# MWB_ADDON_ENGINE_DIR is empty so this build never replaces the host's engine in the add-on. ODE
# is built from the host's copy of the same Debian 12 sources (Debian 13 has a newer ODE), so the
# module makes the same worlds as the host's.
step "build the native module for Python 3.13"
flock /tmp/mwb-build.lock chroot "$CHROOT" /usr/bin/env -i PATH=/usr/bin:/bin HOME=/root LANG=C.UTF-8 sh -c "
    set -e
    cmake -S '$ROOT' -B '$BUILD' -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=/usr/bin/python3.13 \
        -DMWB_ADDON_ENGINE_DIR= -DMWB_BUILD_TESTS=OFF -DMWB_ODE_SOURCE_DIR='$ROOT/build/ode-source' > /dev/null
    cmake --build '$BUILD' --target _native -j2"
step_done build

status=0
# --- 3. the in-Blender suite ---------------------------------------------------------------------
step "tests/blender in Blender $(in_trixie blender --version 2>/dev/null | head -n 1)"
in_trixie sh -c "cd '$ROOT' && blender -b --factory-startup --python-exit-code 1 \
    --python tests/blender/run.py -- tests/blender" || {
    echo "== blender4: FAILED tests/blender"
    status=1
}
step_done "tests/blender"

# --- 4. the real UI under Xvfb -------------------------------------------------------------------
step "tests/viewport under Xvfb"
for test in "$ROOT"/tests/viewport/test_*.py; do
    in_trixie MWB_VIEWPORT_OUT="$BUILD/viewport" sh "$ROOT/tests/viewport/run.sh" "$(basename "$test")" || {
        echo "== blender4: FAILED tests/viewport/$(basename "$test")"
        status=1
    }
done
step_done "tests/viewport"

# --- 5. the extension ----------------------------------------------------------------------------
step "extension: build, validate, install, enable"
in_trixie sh "$ROOT/tests/blender4/extension_check.sh" "$BUILD/extension" || {
    echo "== blender4: FAILED extension check"
    status=1
}
step_done extension

exit $status
