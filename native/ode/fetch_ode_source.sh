#!/bin/sh
# Fetches the sources of ODE 0.16.2 and libccd 2.1 (ode_0.16.2.orig.tar.gz, libccd_2.1.orig.tar.gz)
# from Debian's source packages into DIR.
#   native/ode/fetch_ode_source.sh DIR
# The machine's own Debian package sources get a deb-src twin in a private apt configuration under
# DIR, so the system's apt setup is left alone and no host is named here. apt checks each archive
# against the signed Release file, and the build checks its SHA-256.
set -eu
DIR=$1
[ -f "$DIR/ode_0.16.2.orig.tar.gz" ] && [ -f "$DIR/libccd_2.1.orig.tar.gz" ] && exit 0
. "$(dirname "$0")/../release/debian_chroot.sh"

APT=$DIR/apt
private_apt_dir "$APT"
mkdir -p "$DIR/download"
# deb822 files: every stanza becomes a deb-src stanza.
for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    sed -e 's/^Types:.*$/Types: deb-src/' "$f" > "$APT/sources/$(basename "$f")"
done
# One-line files: every "deb URI SUITE COMPONENTS" line gets a "deb-src" twin.
for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    sed -n -e 's/^[[:space:]]*deb[[:space:]]/deb-src /p' "$f" > "$APT/sources/$(basename "$f").list"
done

# Debian 13 and later package a newer ODE: the sources are Debian 12's, from the same mirror.
if ! grep -qs bookworm "$APT"/sources/*; then
    mirror=$(debian_mirror)
    [ -z "$mirror" ] || cat > "$APT/sources/bookworm-source.sources" <<EOF
Types: deb-src
URIs: $mirror
Suites: bookworm
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
fi

# A third-party source without deb-src entries only makes update warn; both come from Debian's.
apt_private "$APT" update || true

fetch() {  # PACKAGE VERSION ARCHIVE
    [ -f "$DIR/$3" ] && return 0
    (cd "$DIR/download" && apt_private "$APT" source --download-only "$1=$2") >/dev/null 2>&1 || true
    if [ ! -f "$DIR/download/$3" ]; then
        echo "fetch_ode_source: could not fetch $3 from Debian's source packages (is a Debian 12" \
             "mirror reachable? Or put it in $DIR yourself)" >&2
        exit 1
    fi
    mv "$DIR/download/$3" "$DIR/$3"
}
fetch ode 2:0.16.2-1 ode_0.16.2.orig.tar.gz
fetch libccd 2.1-2 libccd_2.1.orig.tar.gz
