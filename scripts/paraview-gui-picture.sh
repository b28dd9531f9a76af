#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Makes Data/Images/paraview-gui.png (or $1): the ParaView GUI's whole main window (pipeline
# browser, Properties panel, two render views) with DIPY's CST_R bundle as Sightline Tubes
# coloured by height and the SHData fixture's .mif as Sightline SH Glyphs.
#
# Needs the ParaView configuration built (scripts/build.sh --paraview, into build-paraview or
# $SIGHTLINE_BUILD_DIR) and Debian's xvfb, xdotool and Qt's SVG support (ParaView's toolbar icons
# are SVG; all in scripts/install-dependencies.sh). It starts its own Xvfb with a 1600x1000 screen,
# the `paraview` GUI with the plugin on PV_PLUGIN_PATH and scripts/paraview_gui_scene.py as its
# --script, and once the scene is up uses xdotool like a user: sizes the main window to the
# screen, widens the left dock, shortens the pipeline browser and collapses the filter's
# section of the Properties panel so that the Sightline Tubes group shows. Those pointer
# positions fit ParaView 5.11's default layout (--dr: no user settings) at 1600x1000.
# scripts/paraview_gui_capture.py then grabs the screen (Pillow's ImageGrab) into the PNG.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SIGHTLINE_BUILD_DIR:-$root/build-paraview}"
output="${1:-$root/Data/Images/paraview-gui.png}"
prefix="$build/paraview-prefix/usr"
# shellcheck source=platform.sh
. "$root/scripts/platform.sh"
plugin_dir="$(sightline_plugin_dir "$build")" && [ -f "$plugin_dir/Sightline.so" ] ||
  { echo "no plugin in $build: run scripts/build.sh --paraview" >&2; exit 1; }
for tool in Xvfb xdotool paraview; do
  command -v "$tool" >/dev/null || { echo "$tool is missing: run scripts/install-dependencies.sh" >&2; exit 1; }
done
sh_data="$build/Testing/Data/sh"
[ -f "$sh_data/small_64D_sh_tournier07.mif" ] || /usr/bin/python3 "$root/scripts/make_sh_data.py" "$sh_data" --tile 140

work="$(mktemp -d)"
xvfb_pid=""
paraview_pid=""
cleanup() {
  [ -z "$paraview_pid" ] || kill "$paraview_pid" 2>/dev/null || true
  [ -z "$xvfb_pid" ] || kill "$xvfb_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

Xvfb -displayfd 3 -noreset -screen 0 1600x1000x24 -nolisten tcp 3>"$work/display" 2>"$work/xvfb.log" &
xvfb_pid=$!
for _ in $(seq 50); do [ -s "$work/display" ] && break; sleep 0.1; done
export DISPLAY=":$(cat "$work/display")"

PYTHONPATH="$prefix/lib/python3/dist-packages:$(sightline_python_dir "$build")" \
LD_LIBRARY_PATH="$build/lib" PV_PLUGIN_PATH="$plugin_dir" XDG_RUNTIME_DIR="$work" XDG_CONFIG_HOME="$work" \
SIGHTLINE_GUI_MIF="$sh_data/small_64D_sh_tournier07.mif" SIGHTLINE_GUI_READY="$work/ready" \
  paraview --dr --script="$root/scripts/paraview_gui_scene.py" >"$work/paraview.log" 2>&1 &
paraview_pid=$!
for _ in $(seq 120); do [ -f "$work/ready" ] && break; sleep 0.5; done
[ -f "$work/ready" ] || { cat "$work/paraview.log" >&2; echo "the GUI did not set up the scene" >&2; exit 1; }

window="$(xdotool search --name '^ParaView [0-9]' | head -n1)"
xdotool windowmove "$window" 0 0 windowsize "$window" 1600 1000
sleep 2
# Widen the left dock (its edge at x=294), shorten the pipeline browser (its lower edge at
# y=436), collapse "Properties (Calculator1)" (its header at y=434 once the browser is shorter).
xdotool mousemove 294 700 mousedown 1 sleep 0.3 mousemove 350 700 sleep 0.3 mousemove 480 700 sleep 0.3 mouseup 1
sleep 0.5
xdotool mousemove 200 436 mousedown 1 sleep 0.3 mousemove 200 400 sleep 0.3 mousemove 200 300 sleep 0.3 mouseup 1
sleep 0.5
xdotool mousemove 26 434 click 1 sleep 0.3 mousemove 900 990
sleep 2
/usr/bin/python3 "$root/scripts/paraview_gui_capture.py" "$output" 1600 1000
echo "$output"
