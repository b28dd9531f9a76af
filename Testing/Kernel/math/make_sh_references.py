#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Reference tables for Testing/Kernel/TestSphericalHarmonics.cpp, from software nobody here wrote.

Usage: make_sh_references.py OUTPUT_DIR

Writes one plain-text case file per reference into OUTPUT_DIR (run by CTest as the fixture
setup test SphericalHarmonics.MakeReferences, into the build tree):

  mrtrix3_sh2amp_lmax{2,4,8,12,16}.txt
      MRtrix3's `sh2amp` (Debian package mrtrix3) evaluating coefficients in its own basis
      (DIPY calls it tournier07, legacy=False) along Cartesian directions.
  dipy_func_coef.txt
      DIPY's shipped pair func_coef.nii.gz / func_discrete.nii.gz on sphere_grad.txt, copied as
      they are. DIPY documents them (dipy.data.mrtrix_spherical_functions) as "coefficients
      associated with the mrtrix spherical harmonic basis of order 8 ... obtained by using the
      dwi2SH command of mrtrix" (MRtrix 0.2), and its test test_real_sym_sh_mrtrix checks them
      with real_sym_sh_mrtrix, i.e. real_sh_tournier(legacy=True): tournier07, legacy.
  dipy_{descoteaux07,tournier07}_{legacy,nonlegacy}_lmax{2..16}.txt
      dipy.reconst.shm.real_sh_descoteaux / real_sh_tournier (scipy's sph_harm underneath).

Every case holds F coefficient vectors (for generated cases: the unit vectors, so that each basis
function is checked on its own, then a few seeded random vectors), N directions, and the F x N
amplitudes. Format (lines starting with '#' are comments):

  source <free text>
  basis <descoteaux07|tournier07>
  legacy <0|1>
  order <even lmax>
  functions <F>
  directions <N>
  coefficients
  <F lines of (lmax+1)(lmax+2)/2 numbers>
  directions
  <N lines: x y z>
  amplitudes
  <F lines of N numbers>

The tolerances each reference supports are stated (and applied) in the C++ test.
"""
import os
import shutil
import subprocess
import sys
import tempfile
import warnings

import numpy as np

try:
    import nibabel as nib
    import dipy
    import dipy.data
    from dipy.reconst.shm import real_sh_descoteaux, real_sh_tournier
except ImportError as error:  # pragma: no cover - a missing reference is a failure, not a skip
    sys.exit(f"make_sh_references.py: {error} (install python3-dipy and python3-nibabel)")

# DIPY warns that the legacy bases are deprecated each time they are used; the point here is
# precisely to reproduce them.
warnings.simplefilter("ignore")

SH2AMP_ORDERS = (2, 4, 8, 12, 16)
DIPY_ORDERS = tuple(range(2, 17, 2))
RANDOM_FUNCTIONS = 4


def count(order):
    return (order + 1) * (order + 2) // 2


def test_directions(seed, n_random):
    """Special directions (poles, axes, equator, near-pole) then seeded random unit vectors."""
    special = np.array([
        [0, 0, 1], [0, 0, -1], [1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0],
        [1, 1, 0], [1, -1, 1], [-1, -2, -3], [1e-3, 2e-3, 1.0], [-1e-3, 1e-3, -1.0],
    ], dtype=np.float64)
    rng = np.random.default_rng(seed)
    directions = np.vstack([special, rng.standard_normal((n_random, 3))])
    return directions / np.linalg.norm(directions, axis=1)[:, None]


def test_coefficients(order, seed):
    rng = np.random.default_rng(seed)
    n = count(order)
    return np.vstack([np.eye(n), rng.standard_normal((RANDOM_FUNCTIONS, n))])


def write_case(path, source, basis, legacy, order, coefficients, directions, amplitudes,
               comments=()):
    coefficients = np.asarray(coefficients, dtype=np.float64)
    directions = np.asarray(directions, dtype=np.float64)
    amplitudes = np.asarray(amplitudes, dtype=np.float64)
    assert coefficients.shape[1] == count(order), (path, coefficients.shape)
    assert directions.shape[1] == 3
    assert amplitudes.shape == (coefficients.shape[0], directions.shape[0]), (path, amplitudes.shape)
    assert np.all(np.isfinite(amplitudes)) and np.all(np.isfinite(coefficients))
    with open(path, "w") as out:
        out.write("# written by Testing/Kernel/math/make_sh_references.py; do not edit\n")
        for line in comments:
            out.write(f"# {line}\n")
        out.write(f"source {source}\nbasis {basis}\nlegacy {int(legacy)}\norder {order}\n")
        out.write(f"functions {coefficients.shape[0]}\ndirections {directions.shape[0]}\n")
        out.write("coefficients\n")
        for row in coefficients:
            out.write(" ".join(f"{v:.17g}" for v in row) + "\n")
        out.write("directions\n")
        for row in directions:
            out.write(" ".join(f"{v:.17g}" for v in row) + "\n")
        out.write("amplitudes\n")
        for row in amplitudes:
            out.write(" ".join(f"{v:.17g}" for v in row) + "\n")


def sh2amp_cases(output_dir, work_dir):
    if shutil.which("sh2amp") is None:
        sys.exit("make_sh_references.py: sh2amp not found (install the Debian package mrtrix3)")
    version = subprocess.run(["sh2amp", "-version"], capture_output=True, text=True, check=True)
    version_line = version.stdout.strip().splitlines()[0] if version.stdout.strip() else "?"
    for order in SH2AMP_ORDERS:
        coefficients = test_coefficients(order, seed=1000 + order)
        directions = test_directions(seed=2000 + order, n_random=53)
        n_functions = coefficients.shape[0]
        # One voxel per function along x; coefficients along the 4th axis, as sh2amp expects.
        # Identity affine: image, scanner and direction axes coincide.
        image = nib.Nifti1Image(coefficients.reshape(n_functions, 1, 1, -1), np.eye(4))
        image.header.set_data_dtype(np.float64)
        coefficient_path = os.path.join(work_dir, f"coefficients_lmax{order}.nii")
        direction_path = os.path.join(work_dir, f"directions_lmax{order}.txt")
        amplitude_path = os.path.join(work_dir, f"amplitudes_lmax{order}.nii")
        nib.save(image, coefficient_path)
        # Three columns: Cartesian unit vectors (two would be azimuth/elevation).
        np.savetxt(direction_path, directions, fmt="%.17g")
        subprocess.run(["sh2amp", "-quiet", "-force", "-nthreads", "0", "-datatype", "float64",
                        coefficient_path, direction_path, amplitude_path], check=True)
        amplitudes = np.asarray(nib.load(amplitude_path).dataobj, dtype=np.float64)
        assert amplitudes.shape == (n_functions, 1, 1, directions.shape[0]), amplitudes.shape
        write_case(os.path.join(output_dir, f"mrtrix3_sh2amp_lmax{order}.txt"),
                   "mrtrix3 sh2amp", "tournier07", False, order, coefficients, directions,
                   amplitudes.reshape(n_functions, -1),
                   [f"sh2amp -version: {version_line}",
                    "sh2amp -datatype float64 coefficients.nii directions.txt amplitudes.nii"])


def dipy_func_coef_case(output_dir):
    files = os.path.join(os.path.dirname(dipy.data.__file__), "files")
    coef = np.asarray(nib.load(os.path.join(files, "func_coef.nii.gz")).dataobj, np.float64)
    discrete = np.asarray(nib.load(os.path.join(files, "func_discrete.nii.gz")).dataobj,
                          np.float64)
    gradients = np.loadtxt(os.path.join(files, "sphere_grad.txt"))
    assert coef.shape[-1] == count(8), coef.shape
    assert discrete.shape[:-1] == coef.shape[:-1] and discrete.shape[-1] == gradients.shape[0]
    # Volumes with b = 0 (the first one) carry no direction; the rest are the sphere.
    weighted = gradients[:, 3] > 0
    directions = gradients[weighted, :3]  # as stored (5 decimals, norms 1 +- 4e-6)
    write_case(os.path.join(output_dir, "dipy_func_coef.txt"),
               "dipy func_coef.nii.gz func_discrete.nii.gz sphere_grad.txt", "tournier07", True,
               8, coef.reshape(-1, coef.shape[-1]), directions,
               discrete.reshape(-1, discrete.shape[-1])[:, weighted],
               [f"dipy {dipy.__version__}: {files}",
                "voxels in C order; directions are rows of sphere_grad.txt with b > 0"])


def dipy_basis_cases(output_dir):
    functions = {"descoteaux07": real_sh_descoteaux, "tournier07": real_sh_tournier}
    for basis, function in functions.items():
        for legacy in (True, False):
            for order in DIPY_ORDERS:
                seed = 3000 + 100 * (basis == "tournier07") + 10 * legacy + order
                coefficients = test_coefficients(order, seed=seed)
                directions = test_directions(seed=seed + 7, n_random=53)
                theta = np.arccos(np.clip(directions[:, 2], -1.0, 1.0))  # polar
                phi = np.arctan2(directions[:, 1], directions[:, 0])     # azimuth
                matrix, _, _ = function(order, theta, phi, legacy=legacy)
                amplitudes = coefficients @ matrix.T
                name = f"dipy_{basis}_{'legacy' if legacy else 'nonlegacy'}_lmax{order}.txt"
                write_case(os.path.join(output_dir, name),
                           f"dipy.reconst.shm.real_sh_{basis[:-2]}", basis, legacy, order,
                           coefficients, directions, amplitudes,
                           [f"dipy {dipy.__version__}: real_sh_{basis[:-2]}({order}, theta, phi, "
                            f"legacy={legacy})"])


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    output_dir = sys.argv[1]
    os.makedirs(output_dir, exist_ok=True)
    # No stale tables: a case this run fails to write must be missing, not left from before.
    for name in os.listdir(output_dir):
        if name.endswith(".txt") and name.startswith(("mrtrix3_sh2amp_", "dipy_")):
            os.remove(os.path.join(output_dir, name))
    with tempfile.TemporaryDirectory(prefix="sh_references_") as work_dir:
        sh2amp_cases(output_dir, work_dir)
    dipy_func_coef_case(output_dir)
    dipy_basis_cases(output_dir)
    print(f"wrote SH reference tables to {output_dir}")


if __name__ == "__main__":
    main()
