#!/bin/sh
# What the Windows modules are built against, from Debian's packages, into DIR:
#   DIR/python3.11, DIR/python3.13   CPython's headers (Include/ and the Windows pyconfig.h, from
#                                    the source packages python3.11 of Debian 12 and python3.13 of
#                                    13), python3XX.def (every name the headers declare) and the
#                                    import library libpython3XX.a made from it by dlltool
#   DIR/pybind11                     pybind11 2.13 (Debian 13's pybind11-dev; 3.13 needs 2.13)
# No Windows Python is needed, nor any host but the Debian mirror this machine already uses. A
# private apt configuration under DIR leaves the system's alone.
#   native/release/windows/fetch_windows_python.sh DIR
set -eu
DIR=$1
HERE=$(cd "$(dirname "$0")" && pwd)
[ -f "$DIR/python3.11/libpython311.a" ] && [ -f "$DIR/python3.13/libpython313.a" ] &&
    [ -f "$DIR/pybind11/pybind11/pybind11.h" ] && exit 0
. "$HERE/../debian_chroot.sh"

mirror=$(debian_mirror)
[ -n "$mirror" ] || { echo "fetch_windows_python: no Debian mirror in this machine's apt sources" >&2; exit 1; }
APT=$DIR/apt
private_apt_dir "$APT"
cat > "$APT/sources/debian.sources" <<SOURCES
Types: deb-src
URIs: $mirror
Suites: bookworm trixie
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: $mirror
Suites: trixie
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
# An index that fails to come only makes update warn; a package missing for it is named below.
apt_private "$APT" update || true
DOWNLOAD=$DIR/download
rm -rf "$DOWNLOAD"
mkdir -p "$DOWNLOAD"

for version in 3.11 3.13; do
    tag=$(echo "$version" | tr -d .)
    out=$DIR/python$version
    [ -f "$out/libpython$tag.a" ] && continue
    (cd "$DOWNLOAD" && apt_private "$APT" source --download-only "python$version") > /dev/null 2>&1 || true
    archive=$(ls "$DOWNLOAD"/python"$version"_*.orig.tar.* 2> /dev/null | head -n 1)
    [ -n "$archive" ] || { echo "fetch_windows_python: could not fetch Debian's source of python$version" >&2; exit 1; }
    top=$(tar tf "$archive" | head -n 1 | cut -d/ -f1)
    # 3.11 ships PC/pyconfig.h, 3.13 PC/pyconfig.h.in (the same file; only free-threaded builds edit it).
    tar xf "$archive" -C "$DOWNLOAD" "$top/Include" "$top/PC/pyconfig.h" 2> /dev/null ||
        tar xf "$archive" -C "$DOWNLOAD" "$top/Include" "$top/PC/pyconfig.h.in"
    rm -rf "$out"
    mv "$DOWNLOAD/$top/Include" "$out"
    if [ -f "$DOWNLOAD/$top/PC/pyconfig.h" ]; then
        mv "$DOWNLOAD/$top/PC/pyconfig.h" "$out/pyconfig.h"
    else
        mv "$DOWNLOAD/$top/PC/pyconfig.h.in" "$out/pyconfig.h"
    fi
    python3 "$HERE/python_def.py" "$out" "python$tag.dll" "$out/python$tag.def"
    x86_64-w64-mingw32-dlltool -d "$out/python$tag.def" -D "python$tag.dll" -l "$out/libpython$tag.a"
    rm -f "$archive"
done

if [ ! -f "$DIR/pybind11/pybind11/pybind11.h" ]; then
    (cd "$DOWNLOAD" && apt_private "$APT" download pybind11-dev/trixie) > /dev/null 2>&1 || true
    deb=$(ls "$DOWNLOAD"/pybind11-dev_2.1[3-9]*_all.deb 2> /dev/null | head -n 1)
    [ -n "$deb" ] || { echo "fetch_windows_python: could not fetch pybind11-dev 2.13 (Debian 13)" >&2; exit 1; }
    dpkg-deb -x "$deb" "$DOWNLOAD/pybind11-dev"
    rm -rf "$DIR/pybind11"
    mv "$DOWNLOAD/pybind11-dev/usr/include" "$DIR/pybind11"
fi
rm -rf "$DOWNLOAD"
