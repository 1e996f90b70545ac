#!/bin/sh
# Installs what the build needs from Debian's packages (only what is missing), then configures
# and builds into build/. Safe to run again: it does only what is left to do.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${MWB_BUILD_DIR:-$ROOT/build}

PACKAGES="cmake g++ make patch pkg-config pybind11-dev nlohmann-json3-dev zlib1g-dev
googletest libgtest-dev python3-dev python3-pytest python3-numpy blender xvfb xauth
clang libclang-rt-14-dev slurm-wlm munge debootstrap
mingw-w64 g++-mingw-w64-x86-64-posix libz-mingw-w64-dev wine64"
# The Flamenco job type is tested with Node.js; use the machine's if it has one.
command -v node >/dev/null 2>&1 || PACKAGES="$PACKAGES nodejs"

missing=""
for p in $PACKAGES; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "setup: installing Debian packages:$missing"
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing
fi

# Blender runs Debian's Python 3.11; the module must be built for exactly that interpreter.
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=/usr/bin/python3.11 >/dev/null
cmake --build "$BUILD" -j"$(nproc)"
