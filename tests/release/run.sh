#!/bin/sh
# The release, as a user gets it, on systems without our build tools or ODE:
#   1. build the release binaries in the Debian 11 chroot (native/release/build_release.sh) and
#      check them: no glibc symbol newer than 2.31, no library outside glibc but those beside them;
#   2. in the Debian 11 chroot (the oldest glibc we promise): the engine samples and reports
#      (tests/release/cross_machine.sh compares the worlds across machines);
#   3. in the Debian 13 chroot with ODE and libccd removed: install the extension zip with
#      `blender -c extension install-file`, then `blender -c many_worlds sample FILE.blend`,
#      `info` and `bake` (Debian's Blender itself depends on libgomp1, so that one stays);
#   4. the add-on zip in Debian 12's Blender 3.4 with a clean user folder: Install, enable, sample.
# Needs root (debootstrap, chroot, mount); otherwise one "skipped: <reason>" line and exit
# $MWB_SKIP_STATUS (0 by default; CTest sets 77, its skip code).
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BULLSEYE=${MWB_BULLSEYE_ROOT:-/var/cache/mwb/bullseye}
TRIXIE=${MWB_TRIXIE_ROOT:-/var/cache/mwb/trixie}
HOST_ENGINE=$ROOT/addon/many_worlds/bin/mwb-engine
DIST=$ROOT/build-release/dist
ZIPS=$ROOT/build-release/zips
. "$ROOT/native/release/debian_chroot.sh"

[ "$(id -u)" -eq 0 ] || {
    echo "skipped: the release tests need root (debootstrap, chroot and mount)"
    exit "${MWB_SKIP_STATUS:-0}"
}
[ -x "$HOST_ENGINE" ] || {
    echo "release: $HOST_ENGINE is missing: build on the host first (tests/setup.sh)"
    exit 1
}
fail() {
    echo "release: FAILED: $*"
    exit 1
}
# Work folders live in the checkout, which every chroot sees at the same path.
mkdir -p "$ROOT/build-release"
WORK=$(mktemp -d "$ROOT/build-release/test.XXXXXX")
cleanup() {
    unmount_checkout "$BULLSEYE" "$ROOT"
    unmount_checkout "$TRIXIE" "$ROOT"
    [ -n "${MWB_KEEP_WORK:-}" ] || rm -rf "$WORK"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "== release: 1. build and check the binaries"
sh "$ROOT/native/release/build_release.sh"
python3 "$ROOT/tests/release/check_binaries.py" "$DIST/bin/mwb-engine" "$DIST"/modules/* ||
    fail "a shipped binary needs more than glibc 2.31"
ext_zip=$(python3 "$ROOT/tests/blender4/build_extension.py" --binaries "$DIST" --out "$ZIPS" 2>/dev/null)
addon_zip=$(python3 "$ROOT/tests/blender4/build_extension.py" --binaries "$DIST" --out "$ZIPS" --legacy)

echo "== release: 2. the engine in Debian 11"
exec 9>"$BULLSEYE.lock"
flock 9
mount_checkout "$BULLSEYE" "$ROOT"
in_chroot "$BULLSEYE" sh -c "ldd --version | head -n 1"
in_chroot "$BULLSEYE" "$DIST/bin/mwb-engine" sample --scene "$ROOT/tests/scenes/quickstart.json" \
    --worlds 0:16 --threads 2 --out "$WORK/bullseye.mwb" | tail -n 1
in_chroot "$BULLSEYE" "$DIST/bin/mwb-engine" info "$WORK/bullseye.mwb" > "$WORK/bullseye.txt"
grep -q "bullseye.mwb: 16 worlds" "$WORK/bullseye.txt" || { cat "$WORK/bullseye.txt"; fail "the engine in Debian 11 did not store 16 worlds"; }
unmount_checkout "$BULLSEYE" "$ROOT"
flock -u 9

echo "== release: 3. the extension in Debian 13 without ODE"
exec 8>"$TRIXIE.lock"
flock 8
ensure_chroot "$TRIXIE" trixie "blender"
in_chroot "$TRIXIE" dpkg --purge --force-depends libode-dev libode8t64 libccd-dev libccd2 > /dev/null 2>&1 || true
in_chroot "$TRIXIE" sh -c "ldconfig -p | grep -E 'libode|libccd'" && fail "ODE or libccd is still installed in $TRIXIE"
mount_checkout "$TRIXIE" "$ROOT"
cp "$ROOT/blend_examples/quickstart/quickstart.blend" "$WORK/quickstart.blend"
in_chroot "$TRIXIE" env BLENDER_USER_RESOURCES="$WORK/user" TMPDIR="$WORK" sh -c "
    set -e
    cd '$WORK'
    blender -b -c extension install-file -r user_default -e '$ext_zip' > install.log 2>&1
    blender -b -c many_worlds sample quickstart.blend --worlds 0:8 --out L.mwb > sample.log 2>&1
    blender -b -c many_worlds info L.mwb > info.txt 2>&1
    blender -b -c many_worlds bake L.mwb --blend quickstart.blend --world 3 --out baked.blend > bake.log 2>&1
    blender -b baked.blend --python-exit-code 1 --python '$ROOT/tests/release/check_baked.py' > check.log 2>&1
" || {
    tail -n 20 "$WORK"/*.log "$WORK/info.txt" 2>/dev/null
    fail "install, sample, info or bake in Debian 13"
}
grep -q "L.mwb: 8 worlds" "$WORK/info.txt" || { cat "$WORK/info.txt"; fail "info does not report the 8 sampled worlds"; }
grep "L.mwb: 8 worlds" "$WORK/info.txt"
grep "^release:" "$WORK/check.log"
unmount_checkout "$TRIXIE" "$ROOT"
flock -u 8

echo "== release: 4. the add-on zip in Blender 3.4"
mkdir -p "$WORK/b34/config" "$WORK/b34/scripts"
BLENDER_USER_CONFIG="$WORK/b34/config" BLENDER_USER_SCRIPTS="$WORK/b34/scripts" TMPDIR="$WORK" \
    blender -b --python-exit-code 1 --python "$ROOT/tests/release/check_legacy_addon.py" -- \
    "$addon_zip" "$WORK/b34" "$ROOT/tests/scenes/quickstart.json" > "$WORK/b34.log" 2>&1 || {
    tail -n 30 "$WORK/b34.log"
    fail "the add-on zip in Blender 3.4"
}
grep "^release:" "$WORK/b34.log"
echo "release: OK"
