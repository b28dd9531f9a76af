#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Makes a private ParaView 5.11 prefix in $1 (default build-paraview/paraview-prefix) and
# prints its CMake package folder (ParaView_DIR).
#
# Why a prefix: ParaView's Python (pvpython, its vtkmodules) is only in python3-paraview, and
# that package conflicts with python3-vtk9, so apt would remove Debian's VTK 9.1. ParaView's
# CMake package also names files of that package (VTKPython-targets.cmake points at its
# vtkCommonCore.so). So the .deb is unpacked here instead of installed, and the prefix is
# completed with links to every file of the installed paraview and paraview-dev packages.
# Nothing under /usr changes. See ../shared/notes/paraview.md.
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
  # progress goes to stderr: stdout is the ParaView_DIR that build.sh captures.
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
  rm -rf "$prefix/.download"
  touch "$stamp"
fi
echo "$prefix/usr/lib/x86_64-linux-gnu/cmake/paraview-5.11"
