#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Sets up, builds, and runs Sightline's main job on data shipped with Debian: a slice of exact
# SH glyphs from DIPY's small_64D diffusion data with soft shadows, DIPY's tractography bundles
# as exact spheres (in a VTK window and without OpenGL), and higher-order tensor glyphs (a copper
# polycrystal's stiffness tensors; small_64D fitted as 4th-order tensors), and the bundles again
# as exact generalized tubes, opaque and translucent. Images go to ./output.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SIGHTLINE_BUILD_DIR:-$root/build}"
# shellcheck source=platform.sh
. "$root/scripts/platform.sh"
"$root/scripts/install-dependencies.sh"
"$root/scripts/build.sh"
cd "$root"
export PYTHONPATH="$build/lib/python3/dist-packages" LD_LIBRARY_PATH="$build/lib"
# Debian's VTK is built for X only: the windows render under a virtual X server.
# 1. Exact SH glyphs (fibre ODFs) of DIPY's small_64D, fitted with CSD, over its FA slice, with
#    soft shadows: output/sh_glyphs_axial_4.png.
xvfb-run -a -s "-noreset -screen 0 1920x1080x24" \
  /usr/bin/python3 Examples/Python/render_sh_glyphs.py --output "$root/output" --size 1600 1000
# 2. DIPY's tractography bundles as exact spheres, in a window and without OpenGL.
xvfb-run -a -s "-noreset -screen 0 1920x1080x24" \
  /usr/bin/python3 Examples/Python/render_tractography.py --output "$root/output" "$@"
# 3. Higher-order tensor glyphs: copper's 4th-order stiffness tensor in 16 random crystal
#    orientations, coloured by the longitudinal modulus (output/tensor_glyphs_copper_polycrystal_
#    exact.png), and DIPY's small_64D fitted as 4th-order generalised-DTI tensors
#    (output/tensor_glyphs_small_64D_gdti4_exact.png).
/usr/bin/python3 scripts/make_tensor_data.py "$root/output/tensor_data"
xvfb-run -a -s "-noreset -screen 0 1920x1080x24" \
  /usr/bin/python3 Examples/Python/render_tensor_glyphs.py --output "$root/output" --size 1600 1200
xvfb-run -a -s "-noreset -screen 0 1920x1080x24" \
  /usr/bin/python3 Examples/Python/render_tensor_glyphs.py --output "$root/output" --size 1200 1200 \
  --tensor "$root/output/tensor_data/small_64D_gdti4.nii.gz" --layout unique
# 4. DIPY's bundles as exact generalized tubes (Sightline's TrackVis reader), opaque and with
#    two bundles translucent around an opaque one, in a window and without OpenGL
#    (output/tubes_opaque_window.png, output/tubes_translucent_window.png, ..._gl_free.png).
xvfb-run -a -s "-noreset -screen 0 1920x1080x24" \
  /usr/bin/python3 Examples/Python/render_tubes.py --output "$root/output" --size 1600 1000
# 5. A layered Earth (PREM density with a degree-2 mantle perturbation) ray-cast natively on its
#    spherical grid, a quarter cut away, around an opaque inner core and under OpenGL graticule
#    lines (output/earth_window.png, output/earth_gl_free.png).
xvfb-run -a -s "-noreset -screen 0 1920x1080x24" \
  /usr/bin/python3 Examples/Python/render_earth.py --output "$root/output" --size 1200 1000
# 6. A user's own file in one command: DIPY's shipped SH file (it has only an sform) through the
#    installed-style viewer, without a window (output/sightline_view_func_coef.png).
"$build/bin/sightline-view" /usr/lib/python3/dist-packages/dipy/data/files/func_coef.nii.gz \
  --basis dipy --legacy --output "$root/output/sightline_view_func_coef.png" --size 1200 900
# 7. The same kind of scene through ParaView: the plugin built against ParaView's own VTK (5.11's
#    9.2 on Debian 12, 5.13's 9.3 on 13; scripts/build.sh --paraview), DIPY's bundle as Sightline Tubes coloured through a ParaView
#    colour map beside PREM as a Sightline Spherical Volume, with ParaView's outline, axes grid
#    and scalar bar, rendered by pvbatch (output/paraview_sightline.png).
pv_build="${SIGHTLINE_PARAVIEW_BUILD_DIR:-$root/build-paraview}"
SIGHTLINE_BUILD_DIR="$pv_build" "$root/scripts/build.sh" --paraview
pv_prefix="$pv_build/paraview-prefix/usr"
PYTHONPATH="$pv_prefix/lib/python3/dist-packages:$(sightline_python_dir "$pv_build")" \
  LD_LIBRARY_PATH="$pv_build/lib" xvfb-run -a -s "-noreset -screen 0 1920x1080x24" \
  "$pv_prefix/bin/pvbatch" --force-offscreen-rendering Examples/ParaView/render_paraview.py \
  --plugin "$(sightline_plugin_dir "$pv_build")/Sightline.so" --output "$root/output"
