#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Installs everything Sightline needs from Debian's packages, on Debian 12 (bookworm) or 13
# (trixie): /etc/os-release says which. Both have the same package names but for the
# sanitizer's clang (clang-14 on 12, the default clang on 13, which has no clang-14) and the
# ParaView GUI's SVG icons (Qt 5 on 12, Qt 6 on 13).
# ParaView (the plugin's configuration) comes without its recommends: python3-paraview would
# replace Debian's VTK (scripts/paraview-prefix.sh unpacks it privately instead).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=platform.sh
. "$root/scripts/platform.sh"

packages=(
  cmake ninja-build g++ pkg-config
  libvtk9-dev python3-vtk9            # VTK (9.1 on 12, 9.3 on 13) and its Python bindings
  libembree-dev libglm-dev libtbb-dev libopenimageio-dev openimageio-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  xvfb xauth libgl1-mesa-dri          # offscreen OpenGL for VTK's X-only build
  libegl1 libegl-mesa0 libosmesa6     # EGL and OSMesa for PyPI's VTK (scripts/pypi-vtk-check.sh)
  python3-numpy python3-matplotlib    # Python tests and benchmark plots
  python3-dipy python3-nibabel        # real data: DIPY's tractography, NIfTI/TrackVis readers
  python3-netcdf4 libnetcdf-dev       # CF netCDF Earth models: the tests write them; VTK's netcdf
  python3-venv                        # trx-python, PyVista from PyPI for tests (python-test-env.sh)
  python3-typing-extensions           # PyVista (sightline.pyvista) runs on Debian's VTK with it
  mrtrix3                             # sh2amp: an independent reference for the MRtrix3 SH basis
  paraview paraview-dev               # ParaView (5.11 on 12, 5.13 on 13) and its own VTK
  mpi-default-bin                     # mpirun (Open MPI) for the plugin's MPI tests
  xdotool python3-pil                 # scripts/paraview-gui-picture.sh
)
case "$SIGHTLINE_DEBIAN" in
  12) packages+=(clang-14 libclang-rt-14-dev  # sanitizer build and libFuzzer targets
                 libqt5svg5                   # ParaView 5.11's SVG toolbar icons (Qt 5)
                 debootstrap) ;;              # the Debian 13 root of test.sh (scripts/debian13.sh)
  13) packages+=(clang libclang-rt-dev        # the default clang (19): trixie has no clang-14
                 qt6-svg-plugins) ;;          # ParaView 5.13's SVG toolbar icons (Qt 6)
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "All Debian $SIGHTLINE_DEBIAN packages Sightline needs are installed."
  exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
echo "Installing from Debian $SIGHTLINE_DEBIAN's packages: ${missing[*]}"
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
