#!/bin/sh
# The add-on on Blender 4.3: Debian 12 ships only Blender 3.4, Debian 13 ships 4.3 (Python 3.13),
# so this runs in a debootstrapped Debian 13 chroot cached in $MWB_TRIXIE_ROOT (default
# /var/cache/mwb/trixie); tests/shared/blender_in_chroot.sh has the steps.
#   tests/blender4/run.sh [chroot]      (chroot: only make the chroot ready)
[ "${1:-}" != chroot ] || export MWB_CHROOT_ONLY=1
MWB_CHROOT=${MWB_TRIXIE_ROOT:-/var/cache/mwb/trixie} exec sh "$(dirname "$0")/../shared/blender_in_chroot.sh" blender4 trixie
