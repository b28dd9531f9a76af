#!/usr/bin/env bash
# Sets up, builds, and runs Sightline's main job: DIPY's tractography bundles as exact
# ray-traced spheres, rendered in a VTK window and without OpenGL. Images go to ./output.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SIGHTLINE_BUILD_DIR:-$root/build}"
"$root/scripts/install-dependencies.sh"
"$root/scripts/build.sh"
cd "$root"
# Debian's VTK is built for X only: the window renders under a virtual X server.
PYTHONPATH="$build/lib/python3/dist-packages" LD_LIBRARY_PATH="$build/lib" \
  xvfb-run -a -s "-screen 0 1920x1080x24" \
  /usr/bin/python3 Examples/Python/render_tractography.py --output "$root/output" "$@"
