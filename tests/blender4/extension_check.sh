#!/bin/sh
# The add-on as a Blender 4.2+ extension: build the linux-x64 zip, `extension validate` it, install
# it into a throwaway user folder with `extension install-file` (enabling it, as a user would),
# then check in a fresh Blender that it is enabled, registered, imports its native module from its
# wheel and runs the engine, that `blender -c many_worlds` reaches the add-on's command line, and
# that it samples a bundled example and bakes a world that plays from its keys.
# Needs a Blender >= 4.2 on PATH (run.sh runs this inside the Debian 13 and sid chroots).
#   tests/blender4/extension_check.sh [OUT_DIR]      (the zip is left in OUT_DIR)
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
OUT=${1:-$ROOT/build/extension}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

# Everything Blender writes (preferences, the installed extension, its unpacked wheels) stays here.
export BLENDER_USER_RESOURCES="$WORK/user" TMPDIR="$WORK"
mkdir -p "$BLENDER_USER_RESOURCES"

zip=$(python3 "$ROOT/tests/blender4/build_extension.py" --out "$OUT")
echo "extension: built $zip"
blender -b --factory-startup -c extension validate "$zip"
# A wrong argument still exits 0 from some `extension` subcommands; the checks below catch that.
blender -b -c extension install-file -r user_default -e "$zip"

blender -b --python-exit-code 1 --python "$ROOT/tests/blender4/check_installed_extension.py" -- "$ROOT" "$WORK"

# `-c` commands come from add-ons enabled in the preferences, which is the installed extension.
"$ROOT/addon/many_worlds/bin/mwb-engine" sample --scene "$ROOT/tests/scenes/quickstart.json" \
    --out "$WORK/q.mwb" --worlds 0:3 --threads 2 > /dev/null
blender -b -c many_worlds info "$WORK/q.mwb" > "$WORK/info.txt" 2>&1 || {
    cat "$WORK/info.txt"
    echo "extension: 'blender -c many_worlds info' failed"
    exit 1
}
grep -qi "worlds" "$WORK/info.txt" || {
    cat "$WORK/info.txt"
    echo "extension: 'blender -c many_worlds info' printed no world count"
    exit 1
}
echo "extension: 'blender -c many_worlds info' works"

# The main loop with the installed extension alone.
sh "$ROOT/tests/shared/extension_main_loop.sh" "$WORK" || {
    tail -n 20 "$WORK"/sample.log "$WORK"/bake.log "$WORK"/check.log 2>/dev/null
    echo "extension: sampling and baking with the installed extension failed"
    exit 1
}
grep "^release: baked" "$WORK/check.log"
echo "extension: OK"
