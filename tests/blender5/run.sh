#!/bin/sh
# The add-on on Blender 5.2 LTS, the Blender animators run today: Debian sid packages 5.2 (Python
# 3.14, CMake 4, gcc 16), so this runs in a debootstrapped sid chroot cached in
# /var/cache/mwb/sid (tests/shared/blender_in_chroot.sh has the steps). Blender's own extension
# manager needs cattrs and requests, or it prints a traceback at every start.
MWB_CHROOT=${MWB_SID_ROOT:-/var/cache/mwb/sid} exec sh "$(dirname "$0")/../shared/blender_in_chroot.sh" blender5 sid python3-cattr python3-requests
