#!/bin/sh
# The add-on on Blender 5.2 LTS, the Blender animators run today: Debian sid packages 5.2 (Python
# 3.14, CMake 4, gcc 16), so this runs in a debootstrapped sid chroot cached in $MWB_SID_ROOT
# (default /var/cache/mwb/sid); tests/shared/blender_in_chroot.sh has the steps, with the fidelity
# corpus against 5.2's own Bullet. Blender's own extension manager needs cattrs and requests, or
# it prints a traceback at every start.
#   tests/blender5/run.sh [chroot]      (chroot: only make the chroot ready)
[ "${1:-}" != chroot ] || export MWB_CHROOT_ONLY=1
MWB_CHROOT=${MWB_SID_ROOT:-/var/cache/mwb/sid} MWB_CHROOT_FIDELITY=1 \
    exec sh "$(dirname "$0")/../shared/blender_in_chroot.sh" blender5 sid python3-cattr python3-requests
