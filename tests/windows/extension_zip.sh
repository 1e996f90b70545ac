#!/bin/sh
# The windows-x64 extension zip, part of windows-cross: tests/blender4/build_extension.py
# --platform windows-x64 from the cross build's dist folder (native/release/windows/build_windows.sh)
#   - built twice, the same bytes;
#   - its contents (check_extension_zip.py): the manifest lists windows-x64 alone, bin/mwb-engine.exe
#     and a wheel per module are the dist's stripped files, no Linux binary; the shipped modules'
#     import and export tables (check_module_imports.py);
#   - `blender -c extension validate` in Debian 13's Blender 4.3, in the chroot the release and
#     blender4 tests share ($MWB_TRIXIE_ROOT, /var/cache/mwb/trixie; native/release/debian_chroot.sh),
#     held under its lock while the checkout is mounted there. Needs root; without it the
#     validation alone is reported skipped.
# The zip is left in $BUILD/zips.
#   tests/windows/extension_zip.sh      (MWB_WINDOWS_BUILD: the cross build, default build-windows/)
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=${MWB_WINDOWS_BUILD:-$ROOT/build-windows}
TRIXIE=${MWB_TRIXIE_ROOT:-/var/cache/mwb/trixie}
. "$ROOT/native/release/debian_chroot.sh"

fail() {
    echo "FAIL: $*"
    exit 1
}
build_zip() {  # OUT_DIR
    python3 "$ROOT/tests/blender4/build_extension.py" --platform windows-x64 --binaries "$BUILD/dist" \
        --out "$1" 2> /dev/null
}
# The second copy lives in the checkout, which the chroot sees at the same path.
work_in_checkout "$ROOT" build-windows zip-check

zip=$(build_zip "$BUILD/zips")
again=$(build_zip "$WORK")
cmp -s "$zip" "$again" || fail "building the windows-x64 zip twice gave different bytes"
python3 "$ROOT/tests/windows/check_extension_zip.py" "$zip" "$BUILD/dist" || exit 1
for tag in 311 313; do
    python3 "$ROOT/tests/windows/check_module_imports.py" "$BUILD/dist/modules/_native.cp$tag-win_amd64.pyd" \
        "$BUILD/python-headers/python3.${tag#3}/python$tag.def" > /dev/null ||
        fail "the shipped (stripped) _native.cp$tag-win_amd64.pyd no longer passes check_module_imports.py"
done

if [ "$(id -u)" -ne 0 ]; then
    echo "$(basename "$zip"): reproducible; extension validate skipped: the Debian 13 chroot needs root"
    exit 0
fi
# Run on its own, before any test that makes the chroot, its folder may not exist yet.
mkdir -p "$(dirname "$TRIXIE")"
exec 8> "$TRIXIE.lock"
flock 8
ensure_chroot "$TRIXIE" trixie "blender python3-numpy" || fail "the Debian 13 chroot at $TRIXIE"
mounted=$TRIXIE
mount_checkout "$TRIXIE" "$ROOT"
in_chroot "$TRIXIE" blender -b --factory-startup -c extension validate "$again" > "$WORK/validate.log" 2>&1 ||
    { cat "$WORK/validate.log"; fail "Blender 4.3's extension validate refused $(basename "$zip")"; }
grep -v "^Blender [0-9]" "$WORK/validate.log"
echo "$(basename "$zip"): reproducible, and valid for $(grep -m 1 "^Blender [0-9]" "$WORK/validate.log")"
