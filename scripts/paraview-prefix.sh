#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Makes a private prefix of Debian's ParaView (5.11 on Debian 12, 5.13 on 13) in $1 (default
# build-paraview/paraview-prefix) and prints its CMake package folder (ParaView_DIR).
#
# Why a prefix: ParaView's Python (pvpython, its vtkmodules) is only in python3-paraview, and
# that package conflicts with python3-vtk9, so apt would remove Debian's VTK 9.1. ParaView's
# CMake package also names files of that package (VTKPython-targets.cmake points at its
# vtkCommonCore.so). So the .deb is unpacked here instead of installed, and the prefix is
# completed with links to every file of the installed paraview and paraview-dev packages.
# Nothing under /usr changes. See ../shared/notes/paraview.md.
# Debian 13's python3-paraview names its extension modules with the interpreter's ABI tag
# (vtkCommonCore.cpython-313-x86_64-linux-gnu.so) while paraview-dev's CMake files name them
# untagged (vtkCommonCore.so): each tagged module gets an untagged link beside it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
prefix="${1:-$root/build-paraview/paraview-prefix}"
stamp="$prefix/.complete"
if [ ! -f "$stamp" ]; then
  for p in paraview paraview-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || {
      echo "paraview-prefix: $p is not installed (scripts/install-dependencies.sh installs it)" >&2
      exit 1
    }
  done
  version="$(dpkg-query -W -f='${Version}' paraview)"
  rm -rf "$prefix"
  mkdir -p "$prefix/.download"
  # apt-get download writes into the current folder; as root it warns that _apt cannot. Its
  # messages go to stderr: stdout is only the ParaView_DIR line that build.sh reads.
  (cd "$prefix/.download" && apt-get download -q "python3-paraview=$version" 2>&1 | grep -v "unsandboxed" >&2 || true)
  deb="$(ls "$prefix"/.download/python3-paraview_*.deb 2>/dev/null | head -n1)"
  [ -n "$deb" ] || { echo "paraview-prefix: could not download python3-paraview=$version" >&2; exit 1; }
  dpkg -x "$deb" "$prefix"
  dpkg -L paraview paraview-dev | while read -r f; do
    if [ -f "$f" ] && [ ! -e "$prefix$f" ]; then
      mkdir -p "$prefix$(dirname "$f")"
      ln -s "$f" "$prefix$f"
    fi
  done
  find "$prefix/usr/lib" -name '*.cpython-*.so' -path '*-packages/*' | while read -r tagged; do
    untagged="${tagged%%.cpython-*}.so"
    [ -e "$untagged" ] || ln -s "$(basename "$tagged")" "$untagged"
  done
  rm -rf "$prefix/.download"
  touch "$stamp"
fi
found=("$prefix"/usr/lib/*/cmake/paraview-*)
[ ${#found[@]} -eq 1 ] && [ -d "${found[0]}" ] ||
  { echo "paraview-prefix: expected one cmake/paraview-* folder in $prefix, found: ${found[*]}" >&2; exit 1; }
echo "${found[0]}"
