#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs everything Sightline needs from Debian bookworm's packages.
# ParaView (the plugin's configuration) comes without its recommends: python3-paraview would
# replace Debian's VTK 9.1 (scripts/paraview-prefix.sh unpacks it privately instead).
set -euo pipefail
packages=(
  cmake ninja-build g++ pkg-config
  libvtk9-dev python3-vtk9            # VTK 9.1 and its Python bindings (for /usr/bin/python3)
  libembree-dev libglm-dev libtbb-dev libopenimageio-dev openimageio-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  xvfb xauth libgl1-mesa-dri          # offscreen OpenGL for VTK's X-only build
  python3-numpy python3-matplotlib    # Python tests and benchmark plots
  python3-dipy python3-nibabel        # real data: DIPY's tractography, NIfTI/TrackVis readers
  mrtrix3                             # sh2amp: an independent reference for the MRtrix3 SH basis
  clang-14 libclang-rt-14-dev         # sanitizer build and libFuzzer targets (scripts/test.sh)
  paraview paraview-dev               # ParaView 5.11 and its VTK 9.2: the plugin's configuration
  libqt5svg5 xdotool python3-pil     # the GUI's SVG icons, and scripts/paraview-gui-picture.sh
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "All Debian packages Sightline needs are installed."
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
