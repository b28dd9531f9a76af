#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Runs a command of this source tree (default: scripts/test.sh) on Debian 13 (trixie) from any
# Linux machine where we are root: in a Debian 13 root made with debootstrap, so that Debian 12
# machines (and CI on them) check the Debian 13 platform too: VTK 9.3, Embree 4, ParaView 5.13,
# GCC 14, the default clang.
#
# The root lives in $SIGHTLINE_DEBIAN13_ROOT (default build/debian13/root) and is kept between
# runs: made once (about a minute), its packages installed by the command itself
# (scripts/install-dependencies.sh, which sees Debian 13 there). Each run copies the working
# tree (tracked files and untracked ones git does not ignore) to /sightline/src inside it and
# builds in /sightline/build, /sightline/build-paraview and /sightline/build-asan, which stay
# there for the next run. The root gets /proc, /sys, /dev and a fresh /dev/shm (Open MPI) in a
# mount namespace of its own, so nothing stays mounted on the machine when the command ends,
# however it ends. $SIGHTLINE_DEBIAN_MIRROR overrides the mirror (default deb.debian.org).
# Usage: scripts/debian13.sh [COMMAND ARGS...]   (COMMAND relative to the source tree)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SIGHTLINE_BUILD_DIR:-$root/build}"
rootfs="${SIGHTLINE_DEBIAN13_ROOT:-$build/debian13/root}"
mirror="${SIGHTLINE_DEBIAN_MIRROR:-http://deb.debian.org/debian}"
[ $# -gt 0 ] || set -- scripts/test.sh

if [ "$(id -u)" -ne 0 ]; then
  echo "scripts/debian13.sh needs root (debootstrap, chroot, mounts); run it with sudo" >&2
  exit 1
fi
for tool in debootstrap unshare chroot; do
  command -v "$tool" >/dev/null || {
    echo "scripts/debian13.sh needs $tool (Debian: apt-get install debootstrap util-linux coreutils)" >&2
    exit 1
  }
done

if [ ! -f "$rootfs/.sightline-root-complete" ]; then
  echo "Making a Debian 13 root in $rootfs with debootstrap from $mirror"
  rm -rf "$rootfs"
  mkdir -p "$rootfs"
  debootstrap --variant=minbase trixie "$rootfs" "$mirror" >"$rootfs.debootstrap.log" 2>&1 || {
    tail -n 30 "$rootfs.debootstrap.log" >&2
    echo "debootstrap failed (whole log: $rootfs.debootstrap.log)" >&2
    exit 1
  }
  touch "$rootfs/.sightline-root-complete"
fi
# Name resolution for apt inside, as the machine has it now; and the machine's TLS trust (its
# certificate bundle may hold a local proxy's CA that Debian's does not), for pip inside
# (the TRX tests' trx-python from PyPI).
cp -L /etc/resolv.conf "$rootfs/etc/resolv.conf"
mkdir -p "$rootfs/sightline"
if [ -f /etc/ssl/certs/ca-certificates.crt ]; then
  cp -L /etc/ssl/certs/ca-certificates.crt "$rootfs/sightline/host-ca-certificates.crt"
fi

# The source tree as git sees it, with modification times kept so that builds stay incremental.
echo "Copying the working tree to $rootfs/sightline/src"
rm -rf "$rootfs/sightline/src"
mkdir -p "$rootfs/sightline/src"
(cd "$root" && git ls-files -z --cached --others --exclude-standard |
  xargs -0 -r sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' sh |
  tar --null -T - -cf -) | tar -xf - -C "$rootfs/sightline/src"

# Only what the command needs from outside: no host paths, the variables that steer the scripts.
env_inside=(PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin HOME=/root
  LANG=C.UTF-8 TERM=dumb
  SIGHTLINE_BUILD_DIR=/sightline/build
  SIGHTLINE_PARAVIEW_BUILD_DIR=/sightline/build-paraview
  SIGHTLINE_SANITIZE_BUILD_DIR=/sightline/build-asan)
if [ -f "$rootfs/sightline/host-ca-certificates.crt" ]; then
  env_inside+=(PIP_CERT=/sightline/host-ca-certificates.crt
    SSL_CERT_FILE=/sightline/host-ca-certificates.crt)
fi
for name in CI SIGHTLINE_PARAVIEW SIGHTLINE_SANITIZE; do
  [ -z "${!name+x}" ] || env_inside+=("$name=${!name}")
done

echo "Running $* on Debian 13 ($rootfs)"
# shellcheck disable=SC2016
exec unshare --mount --propagation private -- bash -c '
  set -e
  rootfs="$1"; shift
  mount -t proc proc "$rootfs/proc"
  mount -t sysfs sysfs "$rootfs/sys"
  mount --bind /dev "$rootfs/dev"
  mount -t devpts -o newinstance,ptmxmode=0666 devpts "$rootfs/dev/pts" 2>/dev/null ||
    mount --bind /dev/pts "$rootfs/dev/pts"
  mount -t tmpfs -o mode=1777 tmpfs "$rootfs/dev/shm"
  exec chroot "$rootfs" "$@"
' bash "$rootfs" /usr/bin/env -i "${env_inside[@]}" \
  bash -c 'cd /sightline/src && exec "$@"' bash "$@"
