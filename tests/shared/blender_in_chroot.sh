#!/bin/sh
# The add-on on a Debian's own Blender, in a debootstrapped chroot of that Debian cached between
# runs (/var/cache/mwb/SUITE). Steps, each timed:
#   1. create the chroot if missing, install the packages it lacks (both idempotent);
#   2. the build there: native/build.sh, as a user runs it, with that Debian's compiler and CMake,
#      for the Python its Blender runs (into build-SUITE/, under the build lock);
#   3. the README's quick-start command, run there, to its contact sheet; the baked world moves
#      its objects by its keys alone;
#   4. the in-Blender test suite (tests/blender);
#   5. the viewport tests under Xvfb (tests/viewport/run.sh);
#   6. the extension: build the zip, validate, install into a throwaway user folder, enable,
#      sample and bake with it;
#   7. with MWB_CHROOT_FIDELITY=1, the fidelity corpus against this Blender's own Bullet: the
#      scenes are built by the host's Blender 3.4 (some need its bundled Cell Fracture) and opened
#      here, as an animator opens an older file.
# With MWB_CHROOT_ONLY=1 it stops after step 1 (CTest prepares the chroots that way while other
# tests run: debootstrap and apt wait on the network more than on the cores).
# Needs root (debootstrap, chroot, mount). Otherwise it prints one "skipped: <reason>" line and
# exits with $MWB_SKIP_STATUS (0 by default; CTest sets 77, its skip code).
#   tests/shared/blender_in_chroot.sh NAME SUITE [MORE PACKAGES...]
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
NAME=$1
SUITE=$2
shift 2
CHROOT=${MWB_CHROOT:-/var/cache/mwb/$SUITE}
SKIP_STATUS=${MWB_SKIP_STATUS:-0}
BUILD=$ROOT/build-$SUITE
# What native/build.sh installs, and what the tests run with.
PACKAGES="blender pybind11-dev python3-dev cmake g++ make patch pkg-config nlohmann-json3-dev
zlib1g-dev python3-pytest python3-numpy xvfb xauth $*"

skip() {
    echo "skipped: $*"
    exit "$SKIP_STATUS"
}

step_start=0
step() {
    step_start=$(date +%s)
    echo "== $NAME: $*"
}
step_done() {
    echo "== $NAME: $1 took $(( $(date +%s) - step_start )) s"
}

[ "$(id -u)" -eq 0 ] || skip "the $NAME tests need root (debootstrap, chroot and mount)"

# The engine executable is the host's build (it runs in every newer Debian); the add-on uses it
# there too, so worlds are the host's.
[ -x "$ROOT/addon/many_worlds/bin/mwb-engine" ] || {
    echo "$NAME: $ROOT/addon/many_worlds/bin/mwb-engine is missing: build on the host first (tests/setup.sh)"
    exit 1
}

# One run at a time per chroot: two runs would mount over each other and race apt.
mkdir -p "$(dirname "$CHROOT")"
exec 9>"$CHROOT.lock"
flock 9

. "$ROOT/native/release/debian_chroot.sh"
in_suite() {
    in_chroot "$CHROOT" "$@"
}

# --- 1. the chroot -------------------------------------------------------------------------------
step "the Debian $SUITE chroot in $CHROOT"
# shellcheck disable=SC2086 # a list of package names
ensure_chroot "$CHROOT" "$SUITE" "$(echo $PACKAGES)" || skip "the Debian $SUITE chroot could not be prepared"
step_done chroot
[ -z "${MWB_CHROOT_ONLY:-}" ] || exit 0

# --- mounts: /proc (Blender prints nothing useful without it) and this checkout at its own path,
# so paths are the same inside and out. Unmounted on any exit.
trap 'unmount_checkout "$CHROOT" "$ROOT"' EXIT
trap 'exit 130' INT TERM
mount_checkout "$CHROOT" "$ROOT"

# --- 2. the build --------------------------------------------------------------------------------
# MWB_ADDON_ENGINE_DIR is empty so this build never replaces the host's engine in the add-on. ODE
# is built from the host's copy of the same Debian 12 sources, so the module makes the host's worlds.
step "build with $(in_suite cmake --version | head -n 1) and $(in_suite g++ --version | head -n 1)"
mkdir -p "$BUILD"
flock /tmp/mwb-build.lock chroot "$CHROOT" /usr/bin/env -i PATH=/usr/bin:/bin HOME=/root LANG=C.UTF-8 \
    MWB_BUILD_DIR="$BUILD" MWB_BUILD_TESTS=OFF \
    MWB_CMAKE_ARGS="-DMWB_ADDON_ENGINE_DIR= -DMWB_ODE_SOURCE_DIR=$ROOT/build/ode-source" \
    sh "$ROOT/native/build.sh" > "$BUILD/build.log" 2>&1 || {
    tail -n 30 "$BUILD/build.log"
    echo "== $NAME: FAILED the build (log: $BUILD/build.log)"
    exit 1
}
step_done build

status=0
# --- 3. the quick start --------------------------------------------------------------------------
step "the quick-start command"
rm -f "$BUILD/quickstart/contact_sheet.png"
if in_suite env MWB_BUILD_DIR="$BUILD" sh "$ROOT/blend_examples/run_quickstart.sh" > "$BUILD/quickstart.log" 2>&1 &&
    [ -s "$BUILD/quickstart/contact_sheet.png" ] &&
    in_suite blender -b "$BUILD/quickstart/best_world.blend" --python-exit-code 1 \
        --python "$ROOT/tests/release/check_baked.py" >> "$BUILD/quickstart.log" 2>&1; then
    grep "^release: baked" "$BUILD/quickstart.log"
else
    tail -n 30 "$BUILD/quickstart.log"
    echo "== $NAME: FAILED the quick-start command (log: $BUILD/quickstart.log)"
    status=1
fi
step_done "quick start"

# --- 4. the in-Blender suite ---------------------------------------------------------------------
step "tests/blender in $(in_suite blender --version 2>/dev/null | head -n 1)"
in_suite sh -c "cd '$ROOT' && blender -b --factory-startup --python-exit-code 1 \
    --python tests/blender/run.py -- tests/blender" > "$BUILD/blender-suite.log" 2>&1 || {
    echo "== $NAME: FAILED tests/blender"
    status=1
}
cat "$BUILD/blender-suite.log"
step_done "tests/blender"

# --- 5. the real UI under Xvfb -------------------------------------------------------------------
step "tests/viewport under Xvfb"
rm -rf "$BUILD/viewport"
for test in "$ROOT"/tests/viewport/test_*.py; do
    in_suite MWB_VIEWPORT_OUT="$BUILD/viewport" sh "$ROOT/tests/viewport/run.sh" "$(basename "$test")" || {
        echo "== $NAME: FAILED tests/viewport/$(basename "$test")"
        status=1
    }
done
step_done "tests/viewport"

# What this Blender says of the add-on's own code (a deprecated call, a property it no longer
# takes as it was given) is a failure too: Blender only prints it.
if grep -h -E "many_worlds/[^ ]*\.py:[0-9]+: [A-Za-z]*Warning" "$BUILD/blender-suite.log" "$BUILD"/viewport/*/blender.log \
    > "$BUILD/addon-warnings.txt"; then
    sort -u "$BUILD/addon-warnings.txt"
    echo "== $NAME: FAILED: Blender warns about the add-on's code (above)"
    status=1
fi

# --- 6. the extension ----------------------------------------------------------------------------
step "extension: build, validate, install, enable, sample, bake"
in_suite sh "$ROOT/tests/blender4/extension_check.sh" "$BUILD/extension" || {
    echo "== $NAME: FAILED extension check"
    status=1
}
step_done extension

# --- 7. fidelity ---------------------------------------------------------------------------------
if [ -n "${MWB_CHROOT_FIDELITY:-}" ]; then
    step "the fidelity corpus against the Bullet of $(in_suite blender --version 2>/dev/null | head -n 1)"
    scenes=$BUILD/fidelity-scenes
    # The host's Blender (3.4) builds and saves them.
    blender -b --factory-startup --python-exit-code 1 --python "$ROOT/tests/fidelity/save_scenes.py" -- "$scenes" \
        > "$BUILD/fidelity-scenes.log" 2>&1 || {
        tail -n 20 "$BUILD/fidelity-scenes.log"
        echo "== $NAME: FAILED saving the fidelity scenes with the host's Blender"
        status=1
    }
    rm -rf "$BUILD/fidelity"
    in_suite env MWB_FIDELITY_SCENES="$scenes" MWB_FIDELITY_OUT="$BUILD/fidelity" sh -c "cd '$ROOT' && \
        blender -b --factory-startup --python-exit-code 1 --python tests/blender/run.py -- tests/fidelity" || {
        echo "== $NAME: FAILED tests/fidelity"
        status=1
    }
    python3 "$ROOT/tests/fidelity/report.py" "$BUILD/fidelity" || true
    step_done fidelity
fi

exit $status
