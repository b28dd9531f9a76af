#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Sightline on PyPI's VTK (vtk==9.5.0 wheel, PyVista 0.48), offscreen through EGL and through
# OSMesa with no X server: a compatibility check of this source tree, not the pip install
# (issue 37; see Documentation/python.md for what is missing for that).
#
# It recompiles, with the wheel's C++ ABI (-D_GLIBCXX_USE_CXX11_ABI=0), exactly what ninja
# compiles for the kernel and the VTK modules of BUILD (a Debian build with Python wrapping),
# with VTK 9.5.0's headers in place of Debian's; links the result with --no-undefined against
# the wheel's libraries; and runs the PyVista tests (and the self-contained sphere, spherical
# volume and tensor glyph tests) in a virtual environment holding only
# PyPI's VTK, with DISPLAY unset and VTK_DEFAULT_OPENGL_WINDOW set to vtkEGLRenderWindow and to
# vtkOSOpenGLRenderWindow (each test run asserts the window class and Mesa's llvmpipe).
#
# Where VTK 9.5.0's headers come from: PyPI carries the VTK 9.5.0 wheel SDK (vtk-sdk) for macOS
# only; its headers are VTK's own (the platform enters only through configured headers that
# Sightline does not include), so they are taken from it, pinned by hash. The Python wrappers
# are the ones BUILD generated with Debian's vtkWrapPython: VTK 9.3's (Debian 13) compile
# against 9.5; VTK 9.1's (Debian 12) do not (they still use Python 2's PyInt types), so this
# check runs on Debian 13 only.
# Usage: scripts/pypi-vtk-check.sh BUILD [WORK]    (WORK default BUILD/pypi-vtk, kept)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "$1" && pwd)"
work="${2:-$build/pypi-vtk}"
vtk_version=9.5.0
pyvista_version=0.48.0
sdk_wheel=vtk_sdk-9.5.0-cp310-cp310-macosx_11_0_arm64.whl
sdk_sha256=9f644e55eb13225062ed5ebcc28ddd8ad9e90b9a75836276bd613d9eeef3a2bb
start=$(date +%s)
mkdir -p "$work"

generator=$(ninja -C "$build" -t commands | grep -o '/[^ ]*vtkWrapPython-[0-9.]*' | head -n 1 || true)
case "$generator" in
  *-9.[3-9]|*-9.[1-9][0-9]) ;;
  *) echo "pypi-vtk-check: $build's wrappers come from '${generator:-no vtkWrapPython}';" \
       "VTK 9.3's or later are needed (Debian 13)" >&2; exit 1 ;;
esac

# 1. A virtual environment with PyPI's VTK and PyVista only (no system site packages).
venv="$work/venv"
if ! "$venv/bin/python" -c "import vtkmodules, pyvista, importlib.metadata as m
assert m.version('vtk') == '$vtk_version' and pyvista.__version__ == '$pyvista_version'" 2>/dev/null; then
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    "vtk==$vtk_version" "pyvista==$pyvista_version"
fi
wheel_libs=$("$venv/bin/python" -c "import os, vtkmodules; print(os.path.dirname(vtkmodules.__file__))")

# 2. VTK 9.5.0's headers.
sdk="$work/sdk"
if [ ! -f "$sdk/.complete" ]; then
  rm -rf "$sdk" && mkdir -p "$sdk"
  "$venv/bin/python" -m pip download --quiet --disable-pip-version-check --no-deps \
    --only-binary=:all: --platform macosx_11_0_arm64 --python-version 3.10 \
    "vtk-sdk==$vtk_version" -d "$sdk"
  echo "$sdk_sha256  $sdk/$sdk_wheel" | sha256sum --check --quiet
  (cd "$sdk" && python3 -c "import sys, zipfile
names = [n for n in zipfile.ZipFile(sys.argv[1]).namelist() if '/headers/vtk-9.5/' in n]
zipfile.ZipFile(sys.argv[1]).extractall('.', names)" "$sdk_wheel")
  rm -f "$sdk/$sdk_wheel"
  touch "$sdk/.complete"
fi
headers=$(find "$sdk" -type d -path '*/headers/vtk-9.5' | head -n 1)

# 3. What ninja compiles for the modules (not tests, benchmarks, examples or the kernel's
#    baselines and image files), with VTK 9.5's headers and the wheel's ABI.
objects="$work/objects"
rm -rf "$objects" && mkdir -p "$objects"
ninja -C "$build" -t commands | grep -E ' -c [^ ]*(Modules/(Kernel|Rendering|IO|Sources)/|/CMakeFiles/Sightline[A-Za-z]*Python(Python)?/)' |
  grep -vE '/(baselines|Testing|Benchmarks|Examples)/|ImageIO\.cpp' |
  sed -E "s#^([^ ]+) #\1 -D_GLIBCXX_USE_CXX11_ABI=0 #;
          s#-isystem /usr/include/vtk-9\.[0-9]+#-isystem $headers#;
          s# -MD -MT [^ ]+ -MF [^ ]+##;
          s#-o ([^ ]*/)?([^/ ]+\.o) #-o $objects/\2 #" > "$work/commands.sh"
[ -s "$work/commands.sh" ] || { echo "pypi-vtk-check: no module compile commands in $build" >&2; exit 1; }
echo "pypi-vtk-check: compiling $(wc -l < "$work/commands.sh") sources against VTK $vtk_version's headers"
xargs -P "$(nproc)" -d '\n' -I{} sh -c '{}' < "$work/commands.sh"

# 4. The modules' library (every symbol resolved: --no-undefined) and the three Python modules
#    (which leave Python's own symbols to the interpreter), linked against the wheel's VTK.
package="$work/python/sightline"
rm -rf "$work/python" && mkdir -p "$package"
vtk_libs=$(ls "$wheel_libs"/libvtk*.so | sed -E 's#.*/lib(vtk[^/]*)\.so#-l\1#')
link() { c++ -shared -o "$1" "${@:2}" -L"$wheel_libs" $vtk_libs -Wl,-rpath,"\$ORIGIN:$wheel_libs"; }
library=()
for object in "$objects"/*.o; do
  case "$(basename "$object")" in *Python*.o) ;; *) library+=("$object") ;; esac
done
link "$package/libSightlinePyPI.so" "${library[@]}" -lembree4 -ltbb -Wl,--no-undefined
for module in Rendering IO Sources; do
  wrappers=$(sed -nE "s#.* -o $objects/([^ ]+\.o) -c [^ ]*/CMakeFiles/Sightline${module}Python(Python)?/.*#\1#p" \
    "$work/commands.sh")
  link "$package/Sightline$module.so" $(printf "$objects/%s " $wrappers) -L"$package" -lSightlinePyPI
done
cp "$build"/lib/python3/dist-packages/sightline/*.py "$package/"

# 5. The tests, offscreen, with only PyPI's VTK in the process.
# PyVista's (every primitive, depth with PyVista meshes, translucent tubes, selection; the window
# class), and the self-contained ones of Python.Spheres, SphericalVolume and TensorGlyphs.
tests="test_pyvista test_spheres test_spherical_volume test_tensor_glyphs"
status=0
for window in vtkEGLRenderWindow vtkOSOpenGLRenderWindow; do
  echo "pypi-vtk-check: $tests through $window (DISPLAY unset)"
  (cd "$root/Testing/Python" &&
    env -u DISPLAY VTK_DEFAULT_OPENGL_WINDOW="$window" SIGHTLINE_EXPECT_WINDOW="$window" \
      PYTHONPATH="$work/python" SIGHTLINE_TEST_TEMP_DIR="$work" \
      "$venv/bin/python" -c "import vtkmodules, sys; sys.exit(0 if vtkmodules.__file__.startswith('$venv') else 'not the wheel VTK')" &&
    env -u DISPLAY VTK_DEFAULT_OPENGL_WINDOW="$window" SIGHTLINE_EXPECT_WINDOW="$window" \
      PYTHONPATH="$work/python" SIGHTLINE_TEST_TEMP_DIR="$work" \
      "$venv/bin/python" -m unittest -v $tests) || status=1
done
echo "pypi-vtk-check: VTK $vtk_version wheel, PyVista $pyvista_version: $(($(date +%s) - start)) s," \
  "$([ $status = 0 ] && echo passed || echo FAILED)"
exit $status
