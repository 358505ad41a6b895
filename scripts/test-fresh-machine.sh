#!/usr/bin/env bash
# The test command on a fresh Debian 12, timed: a minimal bookworm (debootstrap
# --variant=minbase: no compiler, no CMake, no Python) in a folder, this checkout's HEAD
# cloned into it, and .ci/run run inside it, so that every package it needs is installed and
# every cache (the compiler's, MeshLab's builds) starts empty. The time printed at the end
# counts from .ci/run's start: installing the packages, building and every test.
# Needs root. The folder is removed afterwards unless --keep is given.
#
#   test-fresh-machine.sh [--keep] [FOLDER]
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)

keep=no
if [ "${1:-}" = --keep ]; then keep=yes; shift; fi
dir=${1:-$(mktemp -d /tmp/geofilter-fresh.XXXXXX)}
mkdir -p "$dir"
root=$dir/root
[ "$(id -u)" -eq 0 ] || { echo "test-fresh-machine: needs root (debootstrap, chroot)" >&2; exit 1; }
if ! command -v debootstrap >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends debootstrap
fi
[ ! -e "$root" ] || { echo "test-fresh-machine: $root exists; give an empty folder" >&2; exit 1; }

mounted=()
cleanup() {
    for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount "${mounted[i]}" || umount -l "${mounted[i]}" || true; done
    # Never remove through a mount that is still there: it is the machine's /dev, /proc or /sys.
    if grep -q " $root/" /proc/mounts; then
        echo "test-fresh-machine: $root still has mounts; left in place" >&2
    elif [ "$keep" = no ]; then
        rm -rf "$dir"
    fi
}
trap cleanup EXIT

echo "== test-fresh-machine: a minimal Debian 12 in $root"
debootstrap --variant=minbase bookworm "$root" >"$dir/debootstrap.log" 2>&1 ||
    { tail -n 20 "$dir/debootstrap.log" >&2; exit 1; }
# What any machine has and a bare folder lacks: its own host name in /etc/hosts (without it
# Open MPI's three-rank runs wait: mpi.errors took 69 s instead of 11), a resolver, and this machine's way to
# Debian's archive (its apt sources and settings, as a new machine of its kind gets them).
cp /etc/hosts /etc/resolv.conf "$root/etc/"
cp -r /etc/apt/sources.list* /etc/apt/apt.conf.d "$root/etc/apt/" 2>/dev/null || true
for d in proc sys dev dev/pts dev/shm; do
    mount --bind "/$d" "$root/$d"
    mounted+=("$root/$d")
done
git clone -q "$top" "$root/root/geofilter"

start=$(date +%s)
env -i HOME=/root TERM=dumb PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    chroot "$root" bash -c 'cd /root/geofilter && .ci/run'
echo "test-fresh-machine: .ci/run passed in $(( $(date +%s) - start )) s on a fresh Debian 12" \
     "($(git -C "$top" rev-parse --short HEAD), $(nproc) cores), packages and empty caches included"
