#!/bin/sh
# Builds the release binaries in a Debian 11 chroot, so they run on any x86-64 Linux with glibc 2.31
# or newer (Debian 11, Ubuntu 20.04 and later):
#   build-release/dist/bin/mwb-engine                            needs only glibc
#   build-release/dist/modules/_native.cpython-311-...so, -313-, -314-  need only glibc and libgomp.so.1,
#   build-release/dist/modules/libgomp.so.1                      which ships beside them
# ODE and libccd are built from Debian's sources (native/ode), libstdc++, libgcc and zlib are linked
# in (MWB_SELF_CONTAINED). The chroot is cached ($MWB_BULLSEYE_ROOT, default
# /var/cache/mwb/bullseye). Needs root; otherwise prints "skipped: <reason>" and exits with
# $MWB_SKIP_STATUS (default 0).
#   native/release/build_release.sh
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
CHROOT=${MWB_BULLSEYE_ROOT:-/var/cache/mwb/bullseye}
BUILD=$ROOT/build-release
DIST=$BUILD/dist
. "$ROOT/native/release/debian_chroot.sh"

[ "$(id -u)" -eq 0 ] || {
    echo "skipped: the release build needs root (debootstrap, chroot and mount)"
    exit "${MWB_SKIP_STATUS:-0}"
}
mkdir -p "$(dirname "$CHROOT")" "$BUILD"
exec 9>"$CHROOT.lock"
flock 9
ensure_chroot "$CHROOT" bullseye "cmake g++ make patch pkg-config nlohmann-json3-dev zlib1g-dev"
sh "$ROOT/native/ode/fetch_ode_source.sh" "$BUILD/ode-source"
sh "$ROOT/native/release/fetch_python_headers.sh" "$BUILD/python-headers"

trap 'unmount_checkout "$CHROOT" "$ROOT"' EXIT
trap 'exit 130' INT TERM
mount_checkout "$CHROOT" "$ROOT"
# One build for the engine and every module: the core is compiled once. Under the build lock, as
# every build of this checkout, so two never share the machine's cores.
flock /tmp/mwb-build.lock chroot "$CHROOT" /usr/bin/env -i PATH=/usr/bin:/bin HOME=/root LANG=C.UTF-8 sh -c "
    set -e
    cmake -S '$ROOT' -B '$BUILD/build' -DCMAKE_BUILD_TYPE=Release -DMWB_SELF_CONTAINED=ON \
        -DMWB_BUILD_TESTS=OFF -DMWB_ADDON_ENGINE_DIR= -DMWB_MODULE_OUTPUT_DIR='$DIST/modules' \
        -DMWB_ODE_SOURCE_DIR='$BUILD/ode-source' -DMWB_PYTHON_HEADERS='$BUILD/python-headers' \
        -DMWB_PYTHON_VERSIONS='3.11;3.13;3.14' > '$BUILD/configure.log'
    cmake --build '$BUILD/build' -j\$(nproc) > '$BUILD/build.log' 2>&1 || { tail -n 30 '$BUILD/build.log'; exit 1; }
    mkdir -p '$DIST/bin'
    cp '$BUILD/build/native/mwb-engine' '$DIST/bin/mwb-engine'
    cp -L /usr/lib/x86_64-linux-gnu/libgomp.so.1 '$DIST/modules/libgomp.so.1'
    strip --strip-unneeded '$DIST/bin/mwb-engine' '$DIST/modules/'*.so '$DIST/modules/libgomp.so.1'"
echo "release binaries in $DIST:"
ls -l "$DIST/bin" "$DIST/modules" | sed -n 's/^-.* \([0-9][0-9]*\) [A-Z][a-z][a-z] .* \(.*\)$/  \2 \1 bytes/p'
