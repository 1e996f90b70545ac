#!/bin/sh
# Installs what the tests need from Debian's packages (only what is missing) on top of what the
# build needs (native/build.sh), then configures and builds into build/ with the C++ tests. Safe to
# run again: it does only what is left to do.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)

PACKAGES="googletest libgtest-dev python3-pytest xvfb xauth clang libclang-rt-dev slurm-wlm munge
debootstrap mingw-w64 g++-mingw-w64-x86-64-posix libz-mingw-w64-dev wine64"
# The Flamenco job type is tested with Node.js; use the machine's if it has one.
command -v node >/dev/null 2>&1 || PACKAGES="$PACKAGES nodejs"

# shellcheck disable=SC2086 # a list of package names
MWB_BUILD_TESTS=ON "$ROOT/native/build.sh" $PACKAGES
