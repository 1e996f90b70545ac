#!/bin/sh
# The main job on the quick-start example, headless: set up, sample 200 worlds, keep those where
# the marble ends in the left bin, rank them by how soon the marble settles, bake the best one to
# a .blend and draw a contact sheet of the top six.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=${MWB_BUILD_DIR:-$ROOT/build}
"$ROOT/native/build.sh"
OUT="$BUILD/quickstart"
LIB="$OUT/quickstart.mwb"
mkdir -p "$OUT"
rm -f "$LIB" "$LIB.scene.json"
# One command of the add-on's command line; its own output goes to $OUT/<command>.txt, without
# Blender's banner and log lines (from 5.0 on, "00:00.160  blend | Read blend: ..."). A failing
# command stops the job with what it printed.
cli() {
    log="$OUT/$1.log"
    status=0
    blender -b "$ROOT/blend_examples/quickstart/quickstart.blend" --python-exit-code 1 \
        --python "$ROOT/addon/many_worlds/cli.py" -- "$@" > "$log" 2>&1 || status=$?
    grep -v -e '^Blender ' -e '^Read blend' -e '^$' -e '^[0-9][0-9]:[0-9][0-9]\.[0-9][0-9]*  ' \
        "$log" > "$OUT/$1.txt" || true
    if [ "$status" -ne 0 ]; then
        cat "$OUT/$1.txt"
        echo "quickstart: '$1' failed (exit $status; Blender's whole output: $log)" >&2
        exit "$status"
    fi
}
# The left (green) bin seen from the scene camera, in view fractions; the marble over the last second.
LEFT_BIN="--box 0.318,0.217,0.38,0.40 --objects Marble --time 3,4"

echo "== sample"
cli sample --worlds 0:200 --out "$LIB"
tail -n 1 "$OUT/sample.txt"
echo "== info"
cli info "$LIB"
cat "$OUT/info.txt"
echo "== query: the marble ends in the left bin"
cli query "$LIB" $LEFT_BIN
grep -m 1 " worlds match$" "$OUT/query.txt"
echo "== rank: those worlds by how soon the marble rests"
cli rank "$LIB" --metric time_to_rest_s --objects Marble $LEFT_BIN --limit 6
# "WORLD VALUE" lines only, whatever else Blender printed.
grep -E '^[0-9]+ [-+.0-9e]+$' "$OUT/rank.txt" > "$OUT/ranking.txt" || {
    cat "$OUT/rank.txt"
    echo "quickstart: no world ends in the left bin" >&2
    exit 1
}
cat "$OUT/ranking.txt"
BEST=$(head -n 1 "$OUT/ranking.txt" | cut -d ' ' -f 1)
TOP=$(cut -d ' ' -f 1 "$OUT/ranking.txt" | paste -s -d ,)
echo "== bake world $BEST"
cli bake "$LIB" --world "$BEST" --out "$OUT/best_world.blend"
tail -n 1 "$OUT/bake.txt"
echo "== contact sheet"
cli preview "$LIB" --worlds "$TOP" --out "$OUT/contact_sheet.png"
tail -n 1 "$OUT/preview.txt"
echo
echo "library:       $LIB"
echo "ranking:       $OUT/ranking.txt"
echo "baked world:   $OUT/best_world.blend"
echo "contact sheet: $OUT/contact_sheet.png"
