#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Makes DIR a virtual environment of Debian's python3 (its system packages, VTK's bindings among
# them, stay visible) with trx-python, the TRX format's reference implementation, from PyPI:
# the independent reference of the TRX tests (fixture TRXPython.Environment). Kept between runs.
# Usage: trx-python-env.sh DIR
set -euo pipefail
dir="$1"
version=0.6
if "$dir/bin/python" -c "import trx, importlib.metadata as m; assert m.version('trx-python') == '$version'" \
  2>/dev/null; then
  echo "trx-python $version is ready in $dir"
  exit 0
fi
rm -rf "$dir"
/usr/bin/python3 -m venv --system-site-packages "$dir"
"$dir/bin/python" -m pip install --quiet --disable-pip-version-check "trx-python==$version"
"$dir/bin/python" -c "import trx, nibabel, vtkmodules; print('trx-python', trx.__version__ if hasattr(trx, '__version__') else '$version', 'in', '$dir')"
