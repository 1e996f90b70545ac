#!/bin/sh
# Cross-compiles ODE, libccd, the core, the engine and the native tests for 64-bit Windows with
# Debian's MinGW-w64 (native/release/windows/toolchain-mingw64.cmake), into build-windows/:
#   build-windows/native/mwb-engine.exe        needs only Windows' own DLLs
#   build-windows/modules/_native.cp3XX-win_amd64.pyd   the module for Python 3.11 and 3.13:
#                                              Windows' own DLLs and python3XX.dll only
#   build-windows/tests/mwb_*_tests.exe        the GoogleTest programs of the core
#   build-windows/dist/bin/mwb-engine.exe, dist/modules/_native.cp3XX-win_amd64.pyd
#                                              stripped copies of the engine and modules, as the
#                                              windows-x64 extension zip ships them
#                                              (tests/blender4/build_extension.py --platform windows-x64)
# The build folder is kept, so a second run only rebuilds what changed. Under the build lock, as
# every build of this checkout. Needs the packages mingw-w64, g++-mingw-w64-x86-64-posix and
# libz-mingw-w64-dev, and Debian's googletest and nlohmann-json3-dev sources.
#   native/release/windows/build_windows.sh [BUILD_DIR]
set -eu
ROOT=$(cd "$(dirname "$0")/../../.." && pwd)
BUILD=${1:-$ROOT/build-windows}
HERE=$ROOT/native/release/windows
ODE_SOURCE=${MWB_ODE_SOURCE_DIR:-$ROOT/build/ode-source}
mkdir -p "$BUILD"
[ -f "$ODE_SOURCE/ode_0.16.2.orig.tar.gz" ] || sh "$ROOT/native/ode/fetch_ode_source.sh" "$ODE_SOURCE"

sh "$HERE/fetch_windows_python.sh" "$BUILD/python-headers"

flock /tmp/mwb-build.lock cmake -S "$ROOT" -B "$BUILD" -DCMAKE_TOOLCHAIN_FILE="$HERE/toolchain-mingw64.cmake" \
    -DCMAKE_BUILD_TYPE=Release -DMWB_ADDON_ENGINE_DIR= \
    -Dnlohmann_json_DIR="$HERE/nlohmann_json" -DMWB_ODE_SOURCE_DIR="$ODE_SOURCE" \
    -DMWB_BUILD_PYTHON=ON -DMWB_PYTHON_HEADERS="$BUILD/python-headers" -DMWB_PYTHON_VERSIONS="3.11;3.13" \
    -DMWB_MODULE_OUTPUT_DIR="$BUILD/modules" \
    > "$BUILD/configure.log" 2>&1 || { tail -n 30 "$BUILD/configure.log"; exit 1; }
flock /tmp/mwb-build.lock cmake --build "$BUILD" -j"$(nproc)" --target mwb-engine _native_py311 _native_py313 \
    mwb_scene_tests mwb_codec_tests mwb_sim_tests mwb_library_tests mwb_query_tests \
    > "$BUILD/build.log" 2>&1 || { tail -n 40 "$BUILD/build.log"; exit 1; }
# The binaries as shipped, like the Linux release's dist/: stripped copies, each written beside its
# final name and renamed, so a reader never sees half a file. -p keeps the linker's PE timestamp
# (strip would write the current time), so the copies change only when the build does.
strip_into() {  # SOURCE TARGET
    x86_64-w64-mingw32-strip --strip-unneeded -p -o "$2.part" "$1"
    mv "$2.part" "$2"
}
mkdir -p "$BUILD/dist/bin" "$BUILD/dist/modules"
strip_into "$BUILD/native/mwb-engine.exe" "$BUILD/dist/bin/mwb-engine.exe"
for tag in 311 313; do
    strip_into "$BUILD/modules/_native.cp$tag-win_amd64.pyd" "$BUILD/dist/modules/_native.cp$tag-win_amd64.pyd"
done
echo "Windows binaries in $BUILD: native/mwb-engine.exe, modules/_native.cp311-win_amd64.pyd and" \
     "_native.cp313-win_amd64.pyd, tests/mwb_*_tests.exe; stripped for shipping in dist/"
