#!/bin/sh
# Unpacks the headers the release modules are built against into DIR, from Debian's packages:
#   DIR/python3.11  (libpython3.11-dev of Debian 12: Blender 4.2-4.5 official builds, Debian's 3.4)
#   DIR/python3.13  (libpython3.13-dev of Debian 13: Debian's Blender 4.3, Blender 5.1 and later)
#   DIR/python3.14  (libpython3.14-dev of Debian sid: Debian's Blender 5.2)
#   DIR/pybind11    (pybind11-dev of Debian 13, for 3.11 and 3.13)
#   DIR/pybind11-3.14 (pybind11-dev of sid, 3.x: the first to support Python 3.14)
# A private apt configuration (under DIR) lists Debian 12, 13 and sid from the mirror this machine
# uses; the system's apt setup is left alone.
#   native/release/fetch_python_headers.sh DIR
set -eu
DIR=$1
[ -f "$DIR/python3.11/Python.h" ] && [ -f "$DIR/python3.13/Python.h" ] && [ -f "$DIR/python3.14/Python.h" ] &&
    [ -d "$DIR/pybind11/pybind11" ] && [ -d "$DIR/pybind11-3.14/pybind11" ] && exit 0
. "$(dirname "$0")/debian_chroot.sh"

APT=$DIR/apt
private_apt_dir "$APT"
mkdir -p "$DIR/debs" "$DIR/unpacked"
mirror=$(debian_mirror)
[ -n "$mirror" ] || {
    echo "fetch_python_headers: no Debian mirror in this machine's apt sources (/etc/apt)" >&2
    exit 1
}
cat > "$APT/sources/debian.sources" <<EOF
Types: deb
URIs: $mirror
Suites: bookworm trixie sid
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
apt_private "$APT" update
rm -rf "$DIR/debs" "$DIR/unpacked" "$DIR/debs-sid" "$DIR/unpacked-sid"
mkdir -p "$DIR/debs" "$DIR/unpacked" "$DIR/debs-sid" "$DIR/unpacked-sid"
(cd "$DIR/debs" && apt_private "$APT" download libpython3.11-dev/bookworm libpython3.13-dev/trixie \
    libpython3.14-dev/sid pybind11-dev/trixie)
(cd "$DIR/debs-sid" && apt_private "$APT" download pybind11-dev/sid)
for deb in "$DIR"/debs/*.deb; do
    dpkg-deb -x "$deb" "$DIR/unpacked"
done
dpkg-deb -x "$DIR"/debs-sid/*.deb "$DIR/unpacked-sid"
# pyconfig.h sits in the multiarch folder; Python.h includes it by name, so one folder holds both.
for v in 3.11 3.13 3.14; do
    rm -rf "$DIR/python$v"
    cp -r "$DIR/unpacked/usr/include/python$v" "$DIR/python$v"
    cp "$DIR/unpacked/usr/include/x86_64-linux-gnu/python$v/pyconfig.h" "$DIR/python$v/pyconfig.h"
done
rm -rf "$DIR/pybind11"
mkdir -p "$DIR/pybind11"
cp -r "$DIR/unpacked/usr/include/pybind11" "$DIR/pybind11/pybind11"
rm -rf "$DIR/pybind11-3.14"
mkdir -p "$DIR/pybind11-3.14"
cp -r "$DIR/unpacked-sid/usr/include/pybind11" "$DIR/pybind11-3.14/pybind11"
