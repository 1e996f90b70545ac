#!/bin/sh
# The add-on's native build for the Blender on this machine: installs the Debian packages it lacks
# (Blender among them), asks Blender which Python it runs, then configures and builds the engine
# and the module for exactly that Python into build/. Safe to run again: it does only what is left.
#   native/build.sh [MORE DEBIAN PACKAGES...]
# MWB_BUILD_DIR    the build folder (default build/)
# MWB_BUILD_TESTS  ON also builds the C++ tests; unset keeps what the build folder has (OFF when new)
# MWB_CMAKE_ARGS   more arguments for the configure step
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${MWB_BUILD_DIR:-$ROOT/build}

PACKAGES="cmake g++ make patch pkg-config pybind11-dev nlohmann-json3-dev zlib1g-dev python3-dev
python3-numpy blender $*"

started=$(date +%s)
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
missing=""
for p in $PACKAGES; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "setup: installing Debian packages:$missing"
    # A frozen copy of a suite (sid) can be past its Release file's Valid-Until date.
    $SUDO apt-get -o Acquire::Check-Valid-Until=false update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get -o Acquire::Check-Valid-Until=false install -y -qq \
        --no-install-recommends $missing
fi

packages_done=$(date +%s)

# The module must be built for the minor version of the Python that Blender itself runs (Debian's
# Blender runs the system's: 3.11 in Debian 12, 3.13 in 13, 3.14 in sid).
version=$(blender -b --factory-startup --python-expr \
    'import sys; print("blender-python %d.%d" % sys.version_info[:2])' 2>/dev/null |
    sed -n 's/^blender-python \([0-9]*\.[0-9]*\)$/\1/p')
[ -n "$version" ] || {
    echo "setup: 'blender' did not say which Python it runs (is it installed and working?)" >&2
    exit 1
}
PYTHON=/usr/bin/python$version
if [ ! -x "$PYTHON" ] || [ ! -f "/usr/include/python$version/Python.h" ]; then
    echo "setup: Blender runs Python $version; installing its headers (python$version-dev)"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "python$version-dev" || {
        echo "setup: Blender runs Python $version, which this Debian does not package (python$version-dev)" >&2
        exit 1
    }
fi

tests=""
if [ -n "${MWB_BUILD_TESTS:-}" ]; then
    tests="-DMWB_BUILD_TESTS=$MWB_BUILD_TESTS"
elif [ ! -f "$BUILD/CMakeCache.txt" ]; then
    tests="-DMWB_BUILD_TESTS=OFF"
fi
# shellcheck disable=SC2086 # MWB_CMAKE_ARGS is a list of arguments
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE="$PYTHON" $tests \
    ${MWB_CMAKE_ARGS:-} >/dev/null
cmake --build "$BUILD" -j"$(nproc)"
echo "setup: packages $((packages_done - started)) s, build $(($(date +%s) - packages_done)) s (Python $version)"
