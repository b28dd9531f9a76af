# SPDX-License-Identifier: BSD-3-Clause
# Sourced by the scripts: what differs between the supported platforms, said once.
#   SIGHTLINE_DEBIAN         12 (bookworm) or 13 (trixie), from /etc/os-release
#   SIGHTLINE_CC/_CXX        the sanitizer job's clang: clang-14 on 12, the default clang on 13
#   sightline_python_dir B   the folder of build B that holds the Python package `sightline`
#   sightline_plugin_dir B   the folder of build B that holds the ParaView plugin
# Anything else is refused with a message that says what is supported.
if [ -r /etc/os-release ]; then
  # shellcheck disable=SC1091
  SIGHTLINE_OS_ID="$(. /etc/os-release && echo "${ID:-}")"
  SIGHTLINE_OS_VERSION="$(. /etc/os-release && echo "${VERSION_ID:-}")"
  SIGHTLINE_OS_NAME="$(. /etc/os-release && echo "${PRETTY_NAME:-$ID}")"
else
  SIGHTLINE_OS_ID="" SIGHTLINE_OS_VERSION="" SIGHTLINE_OS_NAME="a system without /etc/os-release"
fi
case "$SIGHTLINE_OS_ID:$SIGHTLINE_OS_VERSION" in
  debian:12) SIGHTLINE_DEBIAN=12 SIGHTLINE_CC=clang-14 SIGHTLINE_CXX=clang++-14 ;;
  debian:13) SIGHTLINE_DEBIAN=13 SIGHTLINE_CC=clang SIGHTLINE_CXX=clang++ ;;
  *)
    echo "Sightline's scripts support Debian 12 (bookworm) and Debian 13 (trixie); this is" \
      "$SIGHTLINE_OS_NAME. Elsewhere, install VTK >= 9.1, Embree 3.13 or 4.x, TBB, GLM," \
      "OpenImageIO and GoogleTest yourself and configure with CMake (Documentation/dependencies.md)." >&2
    exit 1 ;;
esac
export SIGHTLINE_DEBIAN SIGHTLINE_CC SIGHTLINE_CXX

# The one folder matching a glob, or an error naming what is missing.
sightline_one_dir() {
  local what="$1" found
  shift
  found=("$@")
  if [ ! -d "${found[0]}" ] || [ ${#found[@]} -ne 1 ]; then
    echo "expected one $what, found: ${found[*]}" >&2
    return 1
  fi
  echo "${found[0]}"
}
sightline_python_dir() {
  local package
  package="$(sightline_one_dir "Python package sightline in $1" "$1"/lib/python3*/*-packages/sightline)" &&
    dirname "$package"
}
sightline_plugin_dir() {
  sightline_one_dir "ParaView plugin folder in $1" "$1"/lib/paraview-*/plugins/Sightline
}
