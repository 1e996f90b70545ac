# Shell functions for Debian chroots made with debootstrap (sourced, not run):
#   debian_mirror                          the Debian mirror this machine already uses
#   ensure_chroot DIR SUITE "PACKAGES"     debootstrap DIR if missing, install the packages it lacks
#   in_chroot DIR CMD...                   run CMD in DIR with a clean environment
#   mount_checkout DIR ROOT                /proc and the checkout ROOT at its own path, in DIR
#   unmount_checkout DIR ROOT
#   work_in_checkout ROOT SUBDIR NAME      WORK: a new folder ROOT/SUBDIR/NAME.XXXXXX, which every
#                                          chroot sees at its own path; at exit it is removed (kept
#                                          with MWB_KEEP_WORK=1) and the chroot named in $mounted,
#                                          if any, unmounted. Call it from the script, not a
#                                          subshell (needs no root).
#   private_apt_dir APT                    make APT ready for apt_private (empty APT/sources)
#   apt_private APT ARGS...                apt-get with sources, lists and cache under APT only
# Needs root. Functions return non-zero with one line on stderr when something fails.

debian_mirror() {
    sed -n -e 's/^URIs:[[:space:]]*\([^[:space:]]*\/debian\)\/*$/\1/p' \
        -e 's/^deb[[:space:]]\{1,\}\(http[^[:space:]]*\/debian\)\/*[[:space:]].*/\1/p' \
        /etc/apt/sources.list.d/*.sources /etc/apt/sources.list.d/*.list /etc/apt/sources.list 2>/dev/null |
        head -n 1
}

in_chroot() {
    _dir=$1
    shift
    chroot "$_dir" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 \
        DEBIAN_FRONTEND=noninteractive "$@"
}

ensure_chroot() {
    _dir=$1 _suite=$2 _packages=$3
    # debootstrap writes into a side folder and renames it when done, so an interrupted run never
    # leaves a half-made chroot that the next run would take for a finished one.
    if [ ! -x "$_dir/usr/bin/apt-get" ] || [ -d "$_dir/debootstrap" ]; then
        command -v debootstrap >/dev/null 2>&1 || apt-get install -y -qq debootstrap >/dev/null 2>&1 || {
            echo "debootstrap is not installed and apt-get cannot install it" >&2
            return 1
        }
        _partial=$_dir.partial
        if grep -q " $_partial/" /proc/mounts; then
            echo "something is still mounted under $_partial" >&2
            return 1
        fi
        rm -rf "$_partial"
        # The machine's own Debian mirror; without one, debootstrap's default.
        _mirror=$(debian_mirror)
        debootstrap --variant=minbase "$_suite" "$_partial" ${_mirror:+"$_mirror"} \
            > "$_dir.debootstrap.log" 2>&1 || {
            echo "debootstrap $_suite failed (see $_dir.debootstrap.log)" >&2
            return 1
        }
        [ ! -e "$_dir" ] || rmdir "$_dir" 2>/dev/null || {
            echo "$_dir exists but is not a finished chroot; remove it" >&2
            return 1
        }
        mv "$_partial" "$_dir"
    fi
    _missing=""
    for _p in $_packages; do
        in_chroot "$_dir" dpkg-query -W -f='${db:Status-Abbrev}' "$_p" 2>/dev/null | grep -q '^ii' ||
            _missing="$_missing $_p"
    done
    [ -n "$_missing" ] || return 0
    cp /etc/resolv.conf "$_dir/etc/resolv.conf"
    # A frozen copy of a suite (sid, here) can be past its Release file's Valid-Until date.
    in_chroot "$_dir" apt-get -o Acquire::Check-Valid-Until=false update -qq &&
        in_chroot "$_dir" apt-get -o Acquire::Check-Valid-Until=false install -y -qq \
            --no-install-recommends $_missing > "$_dir.apt.log" 2>&1 || {
        tail -n 20 "$_dir.apt.log" >&2
        echo "apt-get install in $_dir failed:$_missing" >&2
        return 1
    }
}

private_apt_dir() {
    mkdir -p "$1/sources" "$1/lists/partial" "$1/cache/archives/partial"
    rm -f "$1"/sources/*
}

# The system's apt setup is left alone: no root needed, nothing installed, no lock taken.
apt_private() {
    _apt=$1
    shift
    apt-get -o Dir::Etc::SourceList=/dev/null -o Dir::Etc::SourceParts="$_apt/sources" \
        -o Dir::State::Lists="$_apt/lists" -o Dir::Cache="$_apt/cache" -o Dir::State::status=/dev/null \
        -o APT::Sandbox::User="$(id -un)" -o Debug::NoLocking=true -o Acquire::Check-Valid-Until=false \
        -qq "$@"
}

mount_checkout() {
    mkdir -p "$1$2"
    # A minbase chroot has no mount table; Blender 5 warns at every start without one.
    [ -e "$1/etc/mtab" ] || [ -L "$1/etc/mtab" ] || ln -s ../proc/self/mounts "$1/etc/mtab"
    mountpoint -q "$1/proc" || mount -t proc proc "$1/proc"
    mountpoint -q "$1$2" || mount --bind "$2" "$1$2"
}

unmount_checkout() {
    for _m in "$1$2" "$1/proc"; do
        if mountpoint -q "$_m"; then
            umount "$_m" || umount -l "$_m"
        fi
    done
}

work_in_checkout() {
    mkdir -p "$1/$2"
    WORK=$(mktemp -d "$1/$2/$3.XXXXXX")
    _work_root=$1
    # Only the chroot this run mounted, under its lock, is unmounted: another test may be using
    # another one.
    mounted=""
    trap '_leave_checkout_work' EXIT
    trap 'exit 130' INT TERM
}

_leave_checkout_work() {
    [ -z "$mounted" ] || unmount_checkout "$mounted" "$_work_root"
    [ -n "${MWB_KEEP_WORK:-}" ] || rm -rf "$WORK"
}
