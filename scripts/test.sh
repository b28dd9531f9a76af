#!/usr/bin/env bash
# Sets up, builds and runs the whole test suite (kernel, rendering, Python, examples,
# install). Rendering tests open VTK windows, so ctest runs under a virtual X server.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SIGHTLINE_BUILD_DIR:-$root/build}"
"$root/scripts/install-dependencies.sh"
start=$(date +%s)
"$root/scripts/build.sh"
built=$(date +%s)
cd "$build"
xvfb-run -a -s "-screen 0 1920x1080x24" ctest --output-on-failure --timeout 600 "$@"
echo "build: $((built - start)) s, tests: $(($(date +%s) - built)) s"
