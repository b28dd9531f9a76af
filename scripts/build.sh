#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Configures and builds Sightline in ./build (or $SIGHTLINE_BUILD_DIR) with Debian's python3.
# With --paraview first: the ParaView configuration (the modules against ParaView's own VTK:
# 5.11's 9.2 on Debian 12, 5.13's 9.3 on 13; and the plugin) in ./build-paraview (or $SIGHTLINE_BUILD_DIR), using the private ParaView
# prefix of scripts/paraview-prefix.sh. Further arguments go to cmake.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [ "${1:-}" = "--paraview" ]; then
  shift
  build="${SIGHTLINE_BUILD_DIR:-$root/build-paraview}"
  paraview_dir="$("$root/scripts/paraview-prefix.sh" "$build/paraview-prefix")"
  set -- -DSIGHTLINE_PARAVIEW=ON "-DParaView_DIR=$paraview_dir" \
    -DSIGHTLINE_BUILD_EXAMPLES=OFF -DSIGHTLINE_BUILD_BENCHMARKS=OFF "$@"
else
  build="${SIGHTLINE_BUILD_DIR:-$root/build}"
fi
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DPython3_EXECUTABLE=/usr/bin/python3 "$@"
cmake --build "$build" --parallel "$(nproc)"
