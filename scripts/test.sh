#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Sets up, builds and runs the whole test suite (kernel, rendering, Python, examples,
# install), then the sanitizer job: the kernel, the readers and the mappers built with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer in $SIGHTLINE_SANITIZE_BUILD_DIR (default
# build-asan), their C++ tests run there (kernel, IO, rendering; not the Python ones, whose
# interpreter is not instrumented; leak checking for all but the window tests), and a few
# seconds of each reader's fuzz target.
# SIGHTLINE_SANITIZE=0 skips the sanitizer job. Extra arguments go to the first ctest.
#
# Platforms: Debian 12 and 13 (scripts/platform.sh). On Debian 12 the same command then runs
# again on Debian 13, in a Debian 13 root made with debootstrap under the build folder
# (scripts/debian13.sh; kept between runs): one source tree, both platforms' suites.
# SIGHTLINE_DEBIAN13=0 skips that second run. There the modules are also checked on PyPI's
# VTK wheel through EGL and OSMesa with no X server (scripts/pypi-vtk-check.sh), and the
# sanitizer job is left out unless SIGHTLINE_DEBIAN13_SANITIZE=1: it checks the same code as
# here, and would add about 16 of CI's 90 minutes on 2 cores (on Debian 13 itself test.sh runs
# it, with the default clang).
#
# Rendering tests open VTK windows, so ctest runs with a virtual X server of our own, started
# with -noreset: by default an X server resets itself whenever its last client disconnects,
# and a window opened during that reset has its connection dropped (ECONNRESET), which VTK
# reports as "bad X server connection" and aborts on. Tests that close one window and open the
# next did so 25 times in 40 under load; with -noreset, 0 in 40. It is also started with
# -displayfd: Xvfb itself takes the first free display and reports it once it accepts
# connections (`xvfb-run -a` guesses one from the lock files, which races with other jobs).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${SIGHTLINE_BUILD_DIR:-$root/build}"
asan_build="${SIGHTLINE_SANITIZE_BUILD_DIR:-$root/build-asan}"
pv_build="${SIGHTLINE_PARAVIEW_BUILD_DIR:-$root/build-paraview}"
# shellcheck source=platform.sh
. "$root/scripts/platform.sh"
"$root/scripts/install-dependencies.sh"
suite_start=$(date +%s)

xvfb_pid=""
xvfb_dir="$(mktemp -d)"
cleanup() {
  [ -z "$xvfb_pid" ] || kill "$xvfb_pid" 2>/dev/null || true
  rm -rf "$xvfb_dir"
}
trap cleanup EXIT
start_xvfb() {
  Xvfb -displayfd 3 -noreset -screen 0 1920x1080x24 -nolisten tcp 3>"$xvfb_dir/display" \
    >"$xvfb_dir/log" 2>&1 &
  xvfb_pid=$!
  for _ in $(seq 300); do
    if [ -s "$xvfb_dir/display" ]; then
      export DISPLAY=":$(head -n1 "$xvfb_dir/display")"
      echo "Xvfb (pid $xvfb_pid) serves DISPLAY=$DISPLAY"
      return 0
    fi
    kill -0 "$xvfb_pid" 2>/dev/null || break
    sleep 0.1
  done
  echo "Xvfb did not start:" >&2
  cat "$xvfb_dir/log" >&2
  return 1
}

# Tests run as many at a time as there are cores: serially they took 44 of CI's 90 minutes on
# 2 cores. Tests that must run alone (the MPI ones, the install test) say so (RUN_SERIAL).
jobs="$(nproc)"

start=$(date +%s)
"$root/scripts/build.sh"
built=$(date +%s)
start_xvfb
status=0
(cd "$build" && ctest --output-on-failure --timeout 600 -j "$jobs" "$@") || status=$?
tested=$(date +%s)
echo "build: $((built - start)) s, tests: $((tested - built)) s"

# PyPI's VTK (9.5.0 wheel, PyVista 0.48) offscreen through EGL and OSMesa with no X server:
# this build's modules and wrappers recompiled against the wheel (scripts/pypi-vtk-check.sh).
# Debian 13 only (its VTK 9.3 wrapper generator); SIGHTLINE_PYPI_VTK=0 skips it.
if [ "$SIGHTLINE_DEBIAN" = 13 ] && [ "${SIGHTLINE_PYPI_VTK:-1}" != 0 ]; then
  "$root/scripts/pypi-vtk-check.sh" "$build" || status=$?
fi

# The ParaView configuration: the same modules against ParaView's own VTK (5.11's 9.2 on Debian
# 12, 5.13's 9.3 on 13), the plugin, and its pvbatch tests (label paraview).
# SIGHTLINE_PARAVIEW=0 skips it.
if [ "${SIGHTLINE_PARAVIEW:-1}" != 0 ]; then
  pv_start=$(date +%s)
  SIGHTLINE_BUILD_DIR="$pv_build" "$root/scripts/build.sh" --paraview
  pv_built=$(date +%s)
  (cd "$pv_build" && ctest --output-on-failure --timeout 600 -j "$jobs") || status=$?
  tested=$(date +%s)
  echo "ParaView configuration: build $((pv_built - pv_start)) s, tests $((tested - pv_built)) s"
fi

if [ "${SIGHTLINE_SANITIZE:-1}" != 0 ]; then
  CC="$SIGHTLINE_CC" CXX="$SIGHTLINE_CXX" cmake -S "$root" -B "$asan_build" -G Ninja \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPython3_EXECUTABLE=/usr/bin/python3 \
    -DSIGHTLINE_WRAP_PYTHON=OFF -DSIGHTLINE_BUILD_EXAMPLES=OFF \
    -DSIGHTLINE_BUILD_BENCHMARKS=OFF -DSIGHTLINE_FUZZ=ON
  cmake --build "$asan_build" --parallel "$(nproc)"
  asan_built=$(date +%s)
  # Any report fails its test: UBSan halts on the first finding, ASan and LeakSanitizer
  # always do. The window tests run without LeakSanitizer: Mesa's driver, loaded and unloaded
  # by VTK, leaves small allocations that cannot even be attributed (its module is gone by
  # then); ASan and UBSan still check them.
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  (cd "$asan_build" &&
    ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:check_initialization_order=1 \
    ctest --output-on-failure --timeout 900 -j "$jobs" -L 'kernel|io|fuzz' -LE 'python|install|display') ||
    status=$?
  (cd "$asan_build" &&
    ASAN_OPTIONS=detect_leaks=0:strict_string_checks=1:check_initialization_order=1 \
    ctest --output-on-failure --timeout 900 -j "$jobs" -L rendering -LE 'python|install') ||
    status=$?
  echo "sanitizer build: $((asan_built - tested)) s, sanitizer tests: $(($(date +%s) - asan_built)) s"
fi
echo "Debian $SIGHTLINE_DEBIAN: whole suite $(($(date +%s) - suite_start)) s"

if [ "$SIGHTLINE_DEBIAN" = 12 ] && [ "${SIGHTLINE_DEBIAN13:-1}" != 0 ]; then
  # Our X server goes first: the root's own shares the machine's abstract socket names.
  cleanup
  xvfb_pid=""
  d13_start=$(date +%s)
  SIGHTLINE_SANITIZE="${SIGHTLINE_DEBIAN13_SANITIZE:-0}" "$root/scripts/debian13.sh" scripts/test.sh ||
    status=$?
  echo "Debian 13 root (made or refreshed, packages, the same suite): $(($(date +%s) - d13_start)) s"
fi
exit $status
