#!/usr/bin/env bash
# Build (once) and cache a Debian root with QGIS, for running the QGIS suite on another QGIS.
#   .ci/debian_root.sh SUITE          build /var/cache/easyidp-roots/SUITE if it is not there
#   .ci/debian_root.sh SUITE run CMD  run CMD in that root, with the clone's parent folder
#                                     (the clone and ../shared) bound at the same path
# SUITE: trixie (QGIS 3.40 LTR) or sid (QGIS 3.44). Needs root (debootstrap, mount, chroot).
set -euo pipefail
suite=$1; shift || true
cache=${EASYIDP_ROOTS:-/var/cache/easyidp-roots}
root=$cache/$suite
here=$(cd "$(dirname "$0")/.." && pwd)
parent=$(dirname "$here")
# the Makefile's list (what make env installs on a host), make itself, and git (the clone is a
# checkout: make package and its test list the files git tracks)
PACKAGES="$(make -s -f "$here/Makefile" apt-packages) make ca-certificates git"

in_root() {  # in_root CMD...: a private mount namespace, /proc /dev and the work folder bound
    unshare -m --propagation private bash -c '
        set -e; r=$1; p=$2; shift 2
        mount -t proc proc "$r/proc"; mount --rbind /dev "$r/dev"; mount -t tmpfs tmpfs "$r/tmp"
        mkdir -p "$r$p"; mount --rbind "$p" "$r$p"
        cp /etc/resolv.conf "$r/etc/resolv.conf" 2>/dev/null || true
        exec chroot "$r" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
            LANG=C.UTF-8 CI="${CI:-}" bash -c "$*"' _ "$root" "$parent" "$@"
}

if [ ! -f "$root/.easyidp-done" ]; then
    command -v debootstrap >/dev/null || { apt-get update -qq; DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap >/dev/null; }
    echo "== building a Debian $suite root with QGIS in $root (a few minutes, once; cached)"
    rm -rf "$root.part"; mkdir -p "$cache"
    debootstrap --variant=minbase "$suite" "$root.part" http://deb.debian.org/debian >"$cache/$suite.log" 2>&1 \
        || { tail -20 "$cache/$suite.log"; exit 1; }
    cp /etc/ssl/certs/ca-certificates.crt "$root.part/etc/ssl/certs/ca-certificates.crt" 2>/dev/null || true
    [ -f /etc/pip.conf ] && cp /etc/pip.conf "$root.part/etc/pip.conf"
    # the registry may serve a dated snapshot of sid, whose Release file has expired
    echo 'Acquire::Check-Valid-Until "false";' >"$root.part/etc/apt/apt.conf.d/99easyidp-snapshot"
    root_final=$root; root=$root.part
    in_root "apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $PACKAGES >/dev/null" \
        >>"$cache/$suite.log" 2>&1 || { tail -20 "$cache/$suite.log"; exit 1; }
    # the host's certificate bundle again (ca-certificates rewrites it) for pip behind this network
    cp /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/certs/ca-certificates.crt" 2>/dev/null || true
    touch "$root/.easyidp-done"; mv "$root" "$root_final"; root=$root_final
fi
# a cached root from an older package list gets what is missing
in_root "dpkg -s $PACKAGES >/dev/null 2>&1 || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
    apt-get install -y -qq --no-install-recommends $PACKAGES >/dev/null; }" >>"$cache/$suite.log" 2>&1 \
    || { tail -20 "$cache/$suite.log"; exit 1; }
if [ "${1:-}" = run ]; then shift; in_root "cd '$here' && $*"; fi
