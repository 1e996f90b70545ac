#!/bin/sh
# The same world on every machine: the release engine samples a scene with every shape kind
# (box, trimesh, sphere, capsule, cylinder, cone, convex hull, compound), joints and perturbation
# on this host (Debian 12), in the Debian 11 chroot and in the Debian 13 chroot; the three
# libraries must be byte for byte the same. Then the host's own development build (another
# compiler, another glibc) refines a world sampled in the Debian 13 chroot.
# Needs root (chroot, mount); otherwise one "skipped: <reason>" line and exit $MWB_SKIP_STATUS.
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BULLSEYE=${MWB_BULLSEYE_ROOT:-/var/cache/mwb/bullseye}
TRIXIE=${MWB_TRIXIE_ROOT:-/var/cache/mwb/trixie}
ENGINE=$ROOT/build-release/dist/bin/mwb-engine
DEV_ENGINE=$ROOT/addon/many_worlds/bin/mwb-engine
SCENE=$ROOT/tests/scenes/all_shapes_and_joints.json
. "$ROOT/native/release/debian_chroot.sh"

[ "$(id -u)" -eq 0 ] || {
    echo "skipped: the cross-machine test needs root (chroot and mount)"
    exit "${MWB_SKIP_STATUS:-0}"
}
fail() {
    echo "cross-machine: FAILED: $*"
    exit 1
}
[ -x "$DEV_ENGINE" ] || {
    echo "cross-machine: $DEV_ENGINE is missing: build on the host first (tests/setup.sh)"
    exit 1
}
work_in_checkout "$ROOT" build-release cross
sh "$ROOT/native/release/build_release.sh" > "$WORK/build_release.log" 2>&1 || {
    cat "$WORK/build_release.log"
    fail "the release build"
}

# Two threads: worlds are stored in the order they finish, so compare after sorting by world
# (merge writes worlds in index order).
sample() {  # NAME [CHROOT]
    out=$WORK/$1.mwb
    if [ -n "${2:-}" ]; then
        in_chroot "$2" "$ENGINE" sample --scene "$SCENE" --worlds 0:24 --threads 2 --alpha 0.3 --out "$out.unsorted" > /dev/null
    else
        "$ENGINE" sample --scene "$SCENE" --worlds 0:24 --threads 2 --alpha 0.3 --out "$out.unsorted" > /dev/null
    fi
    "$ENGINE" merge "$out" "$out.unsorted" > /dev/null
}
sample debian12
for name in bullseye trixie; do
    chroot_dir=$BULLSEYE
    [ "$name" = bullseye ] || chroot_dir=$TRIXIE
    exec 9>"$chroot_dir.lock"
    flock 9
    ensure_chroot "$chroot_dir" "$name" ""
    mounted=$chroot_dir
    mount_checkout "$chroot_dir" "$ROOT"
    in_chroot "$chroot_dir" sh -c "echo \"cross-machine: $name, \$(ldd --version | head -n 1)\""
    sample "$name" "$chroot_dir"
    unmount_checkout "$chroot_dir" "$ROOT"
    mounted=""
    flock -u 9
    cmp "$WORK/debian12.mwb" "$WORK/$name.mwb" || fail "the library sampled in $name differs from the host's"
    echo "cross-machine: $name's library is byte for byte the host's ($(wc -c < "$WORK/$name.mwb") bytes, 24 worlds)"
done

# The development build refines what the release engine sampled in Debian 13.
"$DEV_ENGINE" refine --library "$WORK/trixie.mwb" --world 5 --bodies 2,3 --time 0.5 --count 3 \
    > "$WORK/refine.log" 2>&1 || { cat "$WORK/refine.log"; fail "a world sampled in Debian 13 does not refine on the host"; }
"$DEV_ENGINE" info "$WORK/trixie.mwb" > "$WORK/info.txt"
grep -q "trixie.mwb: 27 worlds" "$WORK/info.txt" || { cat "$WORK/info.txt"; fail "refining did not add 3 worlds"; }
grep "made by" "$WORK/info.txt"
echo "cross-machine: world 5 sampled in Debian 13 refined on the host into 3 children"
echo "cross-machine: OK"
