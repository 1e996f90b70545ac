#!/bin/sh
# The README's first command on a fresh Debian 12 machine, packages included: a new minimal
# Debian 12 system (debootstrap, not timed) gets a fresh clone of this checkout's HEAD, then
# `./blend_examples/run_quickstart.sh` runs in it as root and is timed to its contact sheet,
# installing Blender and every other package it needs from the mirror this machine uses.
# Needs root; the system is made under build/bench-fresh and removed afterwards.
#   tests/bench/bench_fresh_machine.sh
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
. "$ROOT/native/release/debian_chroot.sh"
[ "$(id -u)" -eq 0 ] || { echo "bench fresh: skipped (needs root for debootstrap and chroot)"; exit 0; }
SYSTEM=${MWB_BUILD_DIR:-$ROOT/build}/bench-fresh
cleanup() {
    for m in dev/pts dev proc; do umount "$SYSTEM/$m" 2> /dev/null || true; done
    rm -rf "$SYSTEM"
}
trap cleanup EXIT
trap 'exit 130' INT TERM
cleanup
ensure_chroot "$SYSTEM" bookworm "" || exit 1
mount -t proc proc "$SYSTEM/proc"
mount --bind /dev "$SYSTEM/dev"
cp /etc/resolv.conf "$SYSTEM/etc/resolv.conf"
git clone -q "$ROOT" "$SYSTEM/root/many-worlds"
start=$(date +%s)
in_chroot "$SYSTEM" sh -c 'cd /root/many-worlds && ./blend_examples/run_quickstart.sh' > "$SYSTEM.log" 2>&1 || {
    tail -n 30 "$SYSTEM.log"
    echo "bench fresh: the first command failed on a fresh Debian 12 (log: $SYSTEM.log)"
    exit 1
}
seconds=$(($(date +%s) - start))
[ -f "$SYSTEM/root/many-worlds/build/quickstart/contact_sheet.png" ] ||
    { echo "bench fresh: no contact sheet"; exit 1; }
split=$(sed -n 's/^setup: packages \([0-9]*\) s, build \([0-9]*\) s.*/packages \1 s, build \2 s/p' "$SYSTEM.log")
printf '  %-40s %10d  s   %s\n' fresh_first_command_s "$seconds" \
    "$(nproc) cores, Debian 12 from debootstrap: $split, then the job (target < 180 s)"
echo "BENCH fresh_first_command_s $seconds"
