#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Makes DIR a virtual environment of Debian's python3 (its system packages, VTK's bindings among
# them, stay visible) with what the tests take from PyPI (fixture PythonTestEnv.Setup):
# - trx-python, the TRX format's reference implementation (the TRX tests' independent reference);
# - PyVista (and scooby, its small pure-Python helper) for sightline.pyvista, installed without
#   dependencies so that pip never brings a second VTK: PyVista runs on Debian's. 0.44.1 is the
#   version Debian 13 packages (python3-pyvista), and it runs on Debian 12's VTK 9.1 too; later
#   PyVista needs VTK modules Debian's VTK does not build (vtkRenderingMatplotlib).
# Kept between runs.
# Usage: python-test-env.sh DIR
set -euo pipefail
dir="$1"
trx_version=0.6
pyvista_version=0.44.1
ready="import trx, pyvista, importlib.metadata as m
assert m.version('trx-python') == '$trx_version' and pyvista.__version__ == '$pyvista_version'"
if "$dir/bin/python" -c "$ready" 2>/dev/null; then
  echo "trx-python $trx_version and PyVista $pyvista_version are ready in $dir"
  exit 0
fi
rm -rf "$dir"
/usr/bin/python3 -m venv --system-site-packages "$dir"
pip=("$dir/bin/python" -m pip install --quiet --disable-pip-version-check)
"${pip[@]}" "trx-python==$trx_version"
"${pip[@]}" --no-deps "pyvista==$pyvista_version" "scooby==0.10.0"
"$dir/bin/python" -c "$ready
import vtkmodules, typing_extensions, matplotlib
assert vtkmodules.__file__.startswith('/usr/'), 'PyVista must run on Debian VTK, not a wheel'
print('trx-python $trx_version, PyVista $pyvista_version on VTK', pyvista.vtk_version_info, 'in', '$dir')"
