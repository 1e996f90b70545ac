#!/bin/sh
# The release, as a user gets it, on systems without our build tools or ODE:
#   1. build the release binaries in the Debian 11 chroot (native/release/build_release.sh) and
#      check them, as built and as shipped in both zips: no glibc symbol newer than 2.31, no
#      library outside glibc but those beside them;
#   2. in the Debian 11 chroot (the oldest glibc we promise): the engine samples and reports
#      (tests/release/cross_machine.sh compares the worlds across machines);
#   3. in the Debian 13 chroot with ODE and libccd removed: install the extension zip with
#      `blender -c extension install-file`, then `blender -c many_worlds sample FILE.blend`,
#      `info` and `bake` (Debian's Blender itself depends on libgomp1, so that one stays); the
#      installed extension's Slurm plan runs its tasks and merge with the release engine;
#      the same install, sample, info and bake in Debian sid's Blender 5.2 (Python 3.14);
#   4. the add-on zip in Debian 12's Blender 3.4 with a clean user folder: Install, enable, sample.
# Needs root (debootstrap, chroot, mount); otherwise one "skipped: <reason>" line and exit
# $MWB_SKIP_STATUS (0 by default; CTest sets 77, its skip code).
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BULLSEYE=${MWB_BULLSEYE_ROOT:-/var/cache/mwb/bullseye}
TRIXIE=${MWB_TRIXIE_ROOT:-/var/cache/mwb/trixie}
SID=${MWB_SID_ROOT:-/var/cache/mwb/sid}
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
work_in_checkout "$ROOT" build-release test

# In CHROOT's Blender, with a throwaway user folder in DIR: install the extension zip as a user
# does, then run the main loop with it (tests/shared/extension_main_loop.sh: DIR/*.log, DIR/info.txt).
use_extension() {  # CHROOT DIR
    in_chroot "$1" env BLENDER_USER_RESOURCES="$2/user" TMPDIR="$2" sh -c "
        set -e
        cd '$2'
        blender -b -c extension install-file -r user_default -e '$ext_zip' > install.log 2>&1
        sh '$ROOT/tests/shared/extension_main_loop.sh' '$2'"
}

echo "== release: 1. build and check the binaries"
sh "$ROOT/native/release/build_release.sh"
python3 "$ROOT/tests/release/check_binaries.py" "$DIST/bin/mwb-engine" "$DIST"/modules/* ||
    fail "a shipped binary needs more than glibc 2.31"
ext_zip=$(python3 "$ROOT/tests/blender4/build_extension.py" --binaries "$DIST" --out "$ZIPS" 2>/dev/null)
addon_zip=$(python3 "$ROOT/tests/blender4/build_extension.py" --binaries "$DIST" --out "$ZIPS" --legacy)
# The binaries as shipped: the engine and the wheels' modules in the extension zip, the engine and
# the modules in the add-on zip.
mkdir -p "$WORK/shipped/ext" "$WORK/shipped/addon"
python3 -m zipfile -e "$ext_zip" "$WORK/shipped/ext"
python3 -m zipfile -e "$addon_zip" "$WORK/shipped/addon"
for wheel in "$WORK"/shipped/ext/wheels/*.whl; do
    python3 -m zipfile -e "$wheel" "$WORK/shipped/$(basename "$wheel" .whl)"
done
shipped=$(find "$WORK/shipped" -type f \( -name mwb-engine -o -name '*.so' -o -name '*.so.*' \) | sort)
[ "$(echo "$shipped" | wc -l)" -eq 12 ] || { echo "$shipped"; fail "the zips should hold 12 binaries: 2 engines, 6 modules (Python 3.11, 3.13, 3.14 in each) and 4 copies of libgomp (one per wheel, one in the add-on zip)"; }
python3 "$ROOT/tests/release/check_binaries.py" $shipped > "$WORK/shipped.txt" || {
    cat "$WORK/shipped.txt"
    fail "a binary in the zips needs more than glibc 2.31"
}
echo "release: $(echo "$shipped" | wc -l) binaries in the zips need nothing newer than GLIBC_2.31 and nothing outside glibc but libgomp.so.1 beside them"

echo "== release: 2. the engine in Debian 11"
exec 9>"$BULLSEYE.lock"
flock 9
mounted=$BULLSEYE
mount_checkout "$BULLSEYE" "$ROOT"
in_chroot "$BULLSEYE" sh -c "ldd --version | head -n 1"
in_chroot "$BULLSEYE" "$DIST/bin/mwb-engine" sample --scene "$ROOT/tests/scenes/quickstart.json" \
    --worlds 0:16 --threads 2 --out "$WORK/bullseye.mwb" | tail -n 1
in_chroot "$BULLSEYE" "$DIST/bin/mwb-engine" info "$WORK/bullseye.mwb" > "$WORK/bullseye.txt"
grep -q "bullseye.mwb: 16 worlds" "$WORK/bullseye.txt" || { cat "$WORK/bullseye.txt"; fail "the engine in Debian 11 did not store 16 worlds"; }
unmount_checkout "$BULLSEYE" "$ROOT"
mounted=""
flock -u 9

echo "== release: 3. the extension in Debian 13 without ODE"
exec 8>"$TRIXIE.lock"
flock 8
# Debian's Blender, unlike Blender's own builds, leaves numpy to python3-numpy, which it does not
# depend on: an animator on Debian installs both (README, Install). Named here, so a fresh chroot
# does not rely on the blender4 test having installed it.
ensure_chroot "$TRIXIE" trixie "blender python3-numpy"
in_chroot "$TRIXIE" dpkg --purge --force-depends libode-dev libode8t64 libccd-dev libccd2 > /dev/null 2>&1 || true
in_chroot "$TRIXIE" sh -c "ldconfig -p | grep -E 'libode|libccd'" && fail "ODE or libccd is still installed in $TRIXIE"
mounted=$TRIXIE
mount_checkout "$TRIXIE" "$ROOT"
use_extension "$TRIXIE" "$WORK" && in_chroot "$TRIXIE" env BLENDER_USER_RESOURCES="$WORK/user" TMPDIR="$WORK" sh -c "
    set -e
    cd '$WORK'
    # The installed extension's Slurm plan, its tasks run as Slurm runs them (one per chunk), then
    # its merge: every task calls the extension's cli.py and so the engine beside it.
    ext=\$(pwd)/user/extensions/user_default
    blender -b --factory-startup --python-exit-code 1 --python-expr \"
import sys
sys.path.insert(0, '\$ext')
from many_worlds.farm import slurm
array, merge, tasks = slurm.job_scripts('$WORK/quickstart.blend', 0, 8, 4, '$WORK/farm')
assert tasks == 2 and '\$ext/many_worlds/cli.py' in array and '\$ext/many_worlds/cli.py' in merge
open('farm_array.sh', 'w').write(array)
open('farm_merge.sh', 'w').write(merge)
\" > farm_plan.log 2>&1
    mkdir -p farm
    SLURM_ARRAY_TASK_ID=0 sh farm_array.sh > farm_task0.log 2>&1
    SLURM_ARRAY_TASK_ID=1 sh farm_array.sh > farm_task1.log 2>&1
    sh farm_merge.sh > farm_merge.log 2>&1
    blender -b -c many_worlds info farm/merged.mwb > farm_info.txt 2>&1
" || {
    tail -n 20 "$WORK"/*.log "$WORK/info.txt" 2>/dev/null
    fail "install, sample, info, bake or the Slurm plan in Debian 13"
}
grep -q "L.mwb: 8 worlds" "$WORK/info.txt" || { cat "$WORK/info.txt"; fail "info does not report the 8 sampled worlds"; }
grep "L.mwb: 8 worlds" "$WORK/info.txt"
grep "^release:" "$WORK/check.log"
grep -q "merged.mwb: 8 worlds" "$WORK/farm_info.txt" || { cat "$WORK/farm_info.txt"; fail "the Slurm plan's tasks and merge did not make 8 worlds"; }
release_build=$(grep "made by" "$WORK/bullseye.txt")
[ "$(grep "made by" "$WORK/farm_info.txt")" = "$release_build" ] || {
    echo "release engine:$release_build"
    cat "$WORK/farm_info.txt"
    fail "the Slurm plan's shards were not made by the release engine"
}
echo "release: the installed extension's Slurm plan sampled 2 chunks and merged them with the release engine"
unmount_checkout "$TRIXIE" "$ROOT"
mounted=""
flock -u 8

echo "== release: 3b. the extension in Debian sid's Blender 5.2 (Python 3.14) without ODE"
exec 7>"$SID.lock"
flock 7
ensure_chroot "$SID" sid "blender python3-numpy python3-cattr python3-requests"
in_chroot "$SID" dpkg --purge --force-depends libode-dev libode8t64 libccd-dev libccd2 > /dev/null 2>&1 || true
mounted=$SID
mount_checkout "$SID" "$ROOT"
mkdir -p "$WORK/sid"
use_extension "$SID" "$WORK/sid" || {
    tail -n 20 "$WORK"/sid/*.log "$WORK/sid/info.txt" 2>/dev/null
    fail "install, sample, info or bake in Debian sid's Blender 5.2"
}
grep -q "L.mwb: 8 worlds" "$WORK/sid/info.txt" || { cat "$WORK/sid/info.txt"; fail "info on 5.2 does not report the 8 sampled worlds"; }
grep "^release:" "$WORK/sid/check.log"
echo "release: the extension zip installs, samples and bakes in Blender $(in_chroot "$SID" blender --version 2>/dev/null | head -n 1 | cut -d ' ' -f 2-)"
unmount_checkout "$SID" "$ROOT"
mounted=""
flock -u 7

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
