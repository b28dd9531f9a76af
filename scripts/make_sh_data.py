#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Real spherical-harmonics (SH) test and showcase data from DIPY's shipped `small_64D` DWI.

Usage: make_sh_data.py OUTPUT_DIR [--tile N] [--check]

Run with Debian's /usr/bin/python3 (python3-dipy, python3-nibabel, python3-vtk9; MRtrix3's
mrconvert and sh2amp from the Debian package mrtrix3). Everything goes into OUTPUT_DIR, never
into the repository. Deterministic (fixed seeds, no multi-threaded reductions that change with
the machine) and fast (a few seconds). CTest runs it as the fixture setup test SHData.Generate.

Input: dipy.data.get_fnames('small_64D'): 10x10x10x65 int16, one b=0 and 64 directions at
b=1000, 2 mm voxels, an affine that permutes the axes and rotates them (qfac = -1).

Fit: constrained spherical deconvolution (DIPY's ConstrainedSphericalDeconvModel, lmax = 8,
single-shell single-tissue response from auto_response_ssst). It is fast enough here (well under
a second per fit), so the CSA/Q-ball fallback is not used.

Files written (all float32 unless stated, all with the DWI's affine as qform and sform, code 1):
  small_64D_sh_descoteaux07.nii.gz   (10,10,10,45) CSD fODF, DIPY's default basis
                                     (descoteaux07, legacy=True); all-zero outside the mask.
  small_64D_sh_tournier07.nii.gz     the same functions in MRtrix3's basis (tournier07,
                                     legacy=False): an exact change of basis (least squares on a
                                     724-point sphere; both bases span the same space).
  small_64D_sh_tournier07.mif        mrconvert of the tournier07 NIfTI, axes kept as they are
                                     (-config RealignTransform false), layout +0,+1,+2,+3.
  small_64D_sh_tournier07.mif.gz     the same, gzipped, stored with strides -2,3,-4,1 (layout
                                     -1,+2,-3,+0: coefficients contiguous, two axes reversed on
                                     disk), so that a reader's reordering is exercised.
  small_64D_sh_tournier07_realigned.mif  mrconvert with MRtrix's default RealignTransform: the
                                     header permutes and flips the image axes to lie near the
                                     scanner axes (same bytes on disk, layout -1,-0,+2,+3).
  small_64D_sh_uncertainty_descoteaux07.nii.gz  residual-bootstrap uncertainty glyph (below).
  small_64D_b0.nii.gz, small_64D_fa.nii.gz      mean b=0 image and DTI FA (anatomical underlay).
  small_64D_mask.nii.gz (uint8)     the mask (below).
  small_64D_sh_tiled{N}.nii.gz       with --tile N: the axial slice (image axis 2, which the
                                     affine maps mostly to scanner z) with the most mask voxels,
                                     tiled periodically to N x N x 1 x 45, 2 mm identity affine.

Mask: the 10^3 crop lies entirely inside the brain (every b0 is well above noise), so a brain
mask (median_otsu) would keep everything, and Otsu's threshold of the b0 in fact separates CSF
(bright b0) from tissue. The mask is therefore the *tissue* mask: b0 at or below Otsu's
threshold of the b0. CSF voxels, whose fODFs are noise, become the all-zero "background".

Uncertainty: a residual bootstrap (20 resamples, seed 20230701). A linear SH fit of each voxel's
DWI signal (lmax 8, Laplace-Beltrami lambda 0.006) gives fitted signals and leverage-corrected
residuals; each resample adds residuals drawn with replacement to the fitted signal and refits
the CSD. The glyph is the lmax-8 SH fit of (mean + 2 standard deviations) of the bootstrap
fODF amplitudes on the 724-point sphere, so that it encloses the mean glyph (--check reports how
often it also encloses the main fit's amplitudes).

Direction frame: DIPY uses the bvecs as given, so the coefficients are expressed in the frame of
the gradient table (for this file, the image axes), not in scanner axes as MRtrix's dwi2fod
would write them. The tournier07 files are a pure change of basis of the same functions.

What VTK makes of these files (checked by --check; the glyph mapper depends on it):
  * vtkNIFTIImageReader with TimeAsVectorOn() gives one point array named "NIFTI" with 45
    components (the 4th NIfTI axis), dimensions (10,10,10), spacing (2,2,2), origin (0,0,0),
    point id = i + 10 j + 100 k as usual.
  * This header has qfac = -1 (det of the affine < 0). vtkNIFTIImageReader then REVERSES THE
    SLICE ORDER: VTK voxel (i,j,k) holds NIfTI voxel (i, j, nk-1-k). Its GetQFormMatrix() is
    correspondingly the affine with the spacing divided out, its third column negated and its
    translation moved to NIfTI voxel (0,0,nk-1), i.e. a proper rotation (det +1) that maps VTK
    data coordinates (index * spacing) to scanner coordinates. GetSFormMatrix() is the same
    matrix here (VTK applies the same slice reversal to it).
  * A NIfTI with qfac = +1 (e.g. the tiled file) is read without reversal.
"""
import argparse
import gzip
import os
import shutil
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np

try:
    import nibabel as nib
    import dipy.data
    from dipy.core.gradients import gradient_table
    from dipy.core.sphere import Sphere
    from dipy.io.gradients import read_bvals_bvecs
    from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel, auto_response_ssst
    from dipy.reconst.shm import real_sh_descoteaux, sf_to_sh, sh_to_sf
    from dipy.segment.threshold import otsu
    import dipy.reconst.dti as dti
except ImportError as error:  # a missing dependency is a failure, not a skip
    sys.exit(f"make_sh_data.py: {error} (run with /usr/bin/python3; install python3-dipy, "
             "python3-nibabel)")

# DIPY warns on every use of the legacy descoteaux07 basis; using it is the point here.
warnings.simplefilter("ignore")
# DIPY 1.6's multi-voxel fits draw a tqdm progress bar per fit (26 of them here), which would
# bury the summary lines in the CTest log: switch the bar off where that module looks it up.
try:
    import functools
    import dipy.reconst.multi_voxel as _multi_voxel
    if hasattr(_multi_voxel, "tqdm"):
        _multi_voxel.tqdm = functools.partial(_multi_voxel.tqdm, disable=True)
except ImportError:
    pass

SH_ORDER = 8
N_COEFFS = (SH_ORDER + 1) * (SH_ORDER + 2) // 2
BOOTSTRAP_SAMPLES = 20
BOOTSTRAP_SEED = 20230701
CHECK_SEED = 4242
PREFIX = "small_64D"


def log(message):
    print(message, flush=True)


def save_nifti(path, data, affine, dtype=np.float32):
    image = nib.Nifti1Image(np.asarray(data, dtype=dtype), affine)
    # Both codes 1 (scanner): vtkNIFTIImageReader and MRtrix read the qform, nibabel the sform.
    image.set_qform(affine, code=1)
    image.set_sform(affine, code=1)
    image.header.set_xyzt_units("mm", "sec")
    image.header.set_data_dtype(dtype)
    nib.save(image, path)


def load_small_64d():
    """DIPY's small_64D: affine, DWI (float64), gradient table, mean b0 and the tissue mask
    (b0 at or below Otsu's threshold: tissue, not CSF; see the module docstring)."""
    dwi_path, bval_path, bvec_path = dipy.data.get_fnames("small_64D")
    dwi_image = nib.load(dwi_path)
    data = np.asarray(dwi_image.dataobj, dtype=np.float64)
    bvals, bvecs = read_bvals_bvecs(bval_path, bvec_path)
    gtab = gradient_table(bvals, bvecs)
    b0 = data[..., gtab.b0s_mask].mean(axis=-1)
    mask = (b0 <= otsu(b0)).astype(np.uint8)
    return dwi_image.affine, data, gtab, b0, mask


def read_with_vtk(path):
    """vtkNIFTIImageReader's view of a 4-D NIfTI (TimeAsVectorOn): the reader, its point array,
    and that array as (i, j, k, component) to compare with nibabel's."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkNIFTIImageReader()
    reader.SetFileName(path)
    reader.TimeAsVectorOn()
    reader.Update()
    output = reader.GetOutput()
    scalars = output.GetPointData().GetScalars()
    dims = output.GetDimensions()
    # VTK arrays are x-fastest: reshape to (k, j, i, c) and transpose to (i, j, k, c).
    voxels = vtk_to_numpy(scalars).reshape(dims[2], dims[1], dims[0], -1).transpose(2, 1, 0, 3)
    return reader, scalars, voxels


def summary(path, data, basis):
    name = os.path.basename(path)
    if data.ndim == 4 and data.shape[-1] == N_COEFFS:
        c00 = data[..., 0]
        log(f"{name}: shape {data.shape}, basis {basis}, c00 min {c00.min():.6g} "
            f"max {c00.max():.6g}")
    else:
        log(f"{name}: shape {data.shape}, {data.dtype}, min {data.min():.6g} max {data.max():.6g}")


def dense_sphere():
    # A fixed, well-spread 724-point sphere shipped with DIPY: conditioning of the lmax-8 fits.
    return dipy.data.get_sphere("repulsion724")


def convert_basis(coeffs, sphere, to_basis, to_legacy):
    """descoteaux07-legacy coefficients -> another basis: sample densely, least-squares refit."""
    amplitudes = sh_to_sf(coeffs, sphere, SH_ORDER, "descoteaux07", legacy=True)
    return sf_to_sh(amplitudes, sphere, SH_ORDER, to_basis, legacy=to_legacy, smooth=0.0)


def linear_sh_fit_operators(gtab):
    """Hat matrix and leverages of a Laplace-Beltrami-regularised SH fit of the DWI signal."""
    directions = gtab.bvecs[~gtab.b0s_mask]
    r = np.linalg.norm(directions, axis=1)
    theta = np.arccos(np.clip(directions[:, 2] / r, -1, 1))
    phi = np.arctan2(directions[:, 1], directions[:, 0])
    basis, _, l_values = real_sh_descoteaux(SH_ORDER, theta, phi, legacy=True)
    laplace_beltrami = np.diag((l_values * (l_values + 1)) ** 2).astype(np.float64)
    fit_matrix = np.linalg.solve(basis.T @ basis + 0.006 * laplace_beltrami, basis.T)
    hat = basis @ fit_matrix
    return hat, np.diag(hat)


def residual_bootstrap(data, gtab, mask, response, sphere, rng):
    """Mean and standard deviation of the bootstrapped CSD fODF amplitudes on the sphere."""
    dwi = ~gtab.b0s_mask
    signal = data[mask][:, dwi]                       # (voxels, 64)
    hat, leverage = linear_sh_fit_operators(gtab)
    fitted = signal @ hat.T
    # Leverage correction keeps the resampled residuals' variance that of the noise.
    residuals = (signal - fitted) / np.sqrt(1.0 - leverage)
    residuals -= residuals.mean(axis=1, keepdims=True)
    model = ConstrainedSphericalDeconvModel(gtab, response, sh_order=SH_ORDER)
    total = np.zeros((signal.shape[0], sphere.vertices.shape[0]))
    total_sq = np.zeros_like(total)
    resampled = np.array(data[mask], dtype=np.float64)
    for _ in range(BOOTSTRAP_SAMPLES):
        picks = rng.integers(0, signal.shape[1], size=signal.shape)
        resampled[:, dwi] = fitted + np.take_along_axis(residuals, picks, axis=1)
        coeffs = model.fit(resampled).shm_coeff          # 2-D input: one fit per row
        amplitudes = sh_to_sf(coeffs, sphere, SH_ORDER, "descoteaux07", legacy=True)
        total += amplitudes
        total_sq += amplitudes ** 2
    mean = total / BOOTSTRAP_SAMPLES
    std = np.sqrt(np.maximum(total_sq / BOOTSTRAP_SAMPLES - mean ** 2, 0.0))
    return mean, std


def run_mrconvert(source, destination, *options):
    if shutil.which("mrconvert") is None:
        sys.exit("make_sh_data.py: mrconvert not found (install the Debian package mrtrix3)")
    subprocess.run(["mrconvert", "-quiet", "-force", *options, source, destination], check=True)


def tile_slice(sh, mask, n):
    counts = mask.sum(axis=(0, 1))
    k = int(np.argmax(counts))                  # first of the fullest slices: deterministic
    plane = sh[:, :, k, :]
    reps = (-(-n // plane.shape[0]), -(-n // plane.shape[1]), 1)
    tiled = np.tile(plane, reps)[:n, :n, None, :]
    return tiled, k, int(counts[k])


# ---------------------------------------------------------------------------------------------
# --check
# ---------------------------------------------------------------------------------------------
def check_directions():
    rng = np.random.default_rng(CHECK_SEED)
    special = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0], [1, 1, 1], [-1, 2, 0.5]], float)
    directions = np.vstack([special, rng.standard_normal((7, 3))])
    return directions / np.linalg.norm(directions, axis=1)[:, None]


def check_sh2amp(out, mask):
    """MRtrix3's sh2amp on the tournier07 files vs DIPY on the descoteaux07 file."""
    if shutil.which("sh2amp") is None:
        sys.exit("make_sh_data.py: sh2amp not found (install the Debian package mrtrix3)")
    directions = check_directions()
    desc = np.asarray(nib.load(os.path.join(out, f"{PREFIX}_sh_descoteaux07.nii.gz")).dataobj,
                      np.float64)
    expected = sh_to_sf(desc, Sphere(xyz=directions), SH_ORDER, "descoteaux07", legacy=True)
    worst = 0.0
    with tempfile.TemporaryDirectory(prefix="sh_check_") as work:
        direction_path = os.path.join(work, "directions.txt")
        np.savetxt(direction_path, directions, fmt="%.17g")   # 3 columns: Cartesian
        for name in (f"{PREFIX}_sh_tournier07.nii.gz", f"{PREFIX}_sh_tournier07.mif",
                     f"{PREFIX}_sh_tournier07.mif.gz"):
            amplitude_path = os.path.join(work, "amplitudes.nii")
            # RealignTransform false and strides 1,2,3,4: the output keeps the input's voxel
            # axes, un-flipped, so that voxel (i,j,k) of the output is voxel (i,j,k) of the
            # NIfTI read by nibabel (otherwise the .mif.gz's reversed axes would carry over).
            subprocess.run(["sh2amp", "-quiet", "-force", "-nthreads", "0",
                            "-config", "RealignTransform", "false", "-strides", "1,2,3,4",
                            "-datatype", "float64",
                            os.path.join(out, name), direction_path, amplitude_path], check=True)
            got = np.asarray(nib.load(amplitude_path).dataobj, np.float64)
            assert got.shape == expected.shape, (name, got.shape, expected.shape)
            scale = np.abs(expected).max(axis=-1)
            inside = mask > 0
            relative = np.abs(got - expected).max(axis=-1)[inside] / scale[inside]
            outside = np.abs(got[~inside]).max()
            log(f"check sh2amp {name}: {directions.shape[0]} directions x {inside.sum()} voxels,"
                f" max |MRtrix - DIPY| / max_dir |DIPY| = {relative.max():.3g}"
                f" (max abs {np.abs(got - expected).max():.3g}); outside mask max |amp| "
                f"{outside:.3g}")
            worst = max(worst, relative.max())
            if not relative.max() < 1e-4 or outside != 0:
                sys.exit(f"make_sh_data.py: sh2amp check FAILED for {name}")
    return worst


def check_vtk(out, tile):
    """How vtkNIFTIImageReader presents the SH NIfTI files: components, slice order, qform."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    names = [f"{PREFIX}_sh_descoteaux07.nii.gz", f"{PREFIX}_sh_tournier07.nii.gz"]
    if tile > 0:
        names.append(f"{PREFIX}_sh_tiled{tile}.nii.gz")     # qfac +1: read without reversal
    for name in names:
        path = os.path.join(out, name)
        image = nib.load(path)
        expected = np.asarray(image.dataobj)
        reader, scalars, got = read_with_vtk(path)
        output = reader.GetOutput()
        dims = output.GetDimensions()
        assert scalars.GetNumberOfComponents() == N_COEFFS, scalars.GetNumberOfComponents()
        assert tuple(dims) == expected.shape[:3], dims
        spacing = np.array(output.GetSpacing())
        qfac = reader.GetQFac()
        reversed_slices = np.array_equal(got, expected[:, :, ::-1, :])
        straight = np.array_equal(got, expected)
        if qfac < 0:
            assert reversed_slices, "expected VTK to reverse the slices for qfac = -1"
        else:
            assert straight
        qform = np.array([[reader.GetQFormMatrix().GetElement(r, c) for c in range(4)]
                          for r in range(4)])
        sform = np.array([[reader.GetSFormMatrix().GetElement(r, c) for c in range(4)]
                          for r in range(4)])
        # The affine with the spacing divided out, re-expressed for VTK's slice order.
        affine = image.header.get_qform()
        expected_q = affine.copy()
        expected_q[:3, :3] = affine[:3, :3] / spacing[None, :]
        if qfac < 0:
            expected_q[:3, 3] = affine[:3, :3] @ np.array([0, 0, dims[2] - 1]) + affine[:3, 3]
            expected_q[:3, 2] *= -1
        assert np.allclose(qform, expected_q, atol=1e-5), (qform, expected_q)
        assert np.allclose(sform, qform, atol=1e-5), (sform, qform)
        np.set_printoptions(precision=7, suppress=True)
        log(f"check VTK {name}: {scalars.GetNumberOfComponents()} components in array "
            f"'{scalars.GetName()}', dims {dims}, spacing {tuple(spacing)}, qfac {qfac:+g}, "
            f"slices {'REVERSED (VTK k = nk-1-k)' if qfac < 0 else 'in NIfTI order'}; "
            f"values equal nibabel's; det(QForm) {np.linalg.det(qform[:3, :3]):+.6f}")
        if name == names[0]:
            log("check VTK: nibabel affine (qform) =\n" + str(affine))
            log("check VTK: vtkNIFTIImageReader.GetQFormMatrix() =\n" + str(qform))


def check_uncertainty(out, sphere, mask):
    load = lambda name: np.asarray(nib.load(os.path.join(out, name)).dataobj, np.float64)
    main = sh_to_sf(load(f"{PREFIX}_sh_descoteaux07.nii.gz")[mask > 0], sphere, SH_ORDER,
                    "descoteaux07", legacy=True)
    glyph = sh_to_sf(load(f"{PREFIX}_sh_uncertainty_descoteaux07.nii.gz")[mask > 0], sphere,
                     SH_ORDER, "descoteaux07", legacy=True)
    fraction = np.mean(glyph >= main)
    log(f"check uncertainty: the uncertainty glyph is >= the main fit in {100 * fraction:.2f}% "
        f"of {main.size} (voxel, direction) samples")
    if fraction < 0.95:
        sys.exit("make_sh_data.py: the uncertainty glyph does not enclose the main fit")


# ---------------------------------------------------------------------------------------------
def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("output_dir")
    parser.add_argument("--tile", type=int, default=0, metavar="N",
                        help="also write an N x N x 1 tiling of the fullest axial slice")
    parser.add_argument("--check", action="store_true",
                        help="verify the files with MRtrix3's sh2amp and VTK's NIfTI reader")
    args = parser.parse_args()
    out = os.path.abspath(args.output_dir)
    os.makedirs(out, exist_ok=True)
    start = time.perf_counter()

    affine, data, gtab, b0, mask = load_small_64d()
    fa = np.clip(np.nan_to_num(dti.TensorModel(gtab).fit(data).fa), 0.0, 1.0)

    response, ratio = auto_response_ssst(gtab, data, roi_radii=10, fa_thr=0.7)
    model = ConstrainedSphericalDeconvModel(gtab, response, sh_order=SH_ORDER)
    t = time.perf_counter()
    sh = model.fit(data, mask=mask > 0).shm_coeff
    sh[mask == 0] = 0.0
    log(f"fit: CSD (ConstrainedSphericalDeconvModel, lmax {SH_ORDER}, auto_response_ssst "
        f"eigenvalues {np.array2string(response[0], precision=6)}, S0 {response[1]:.1f}) on "
        f"{int(mask.sum())} mask voxels in {time.perf_counter() - t:.2f} s")

    sphere = dense_sphere()
    # Store float32 first and convert *that*, so that both files hold the same functions to
    # float32 rounding of the conversion only.
    sh = sh.astype(np.float32)
    tournier = convert_basis(sh.astype(np.float64), sphere, "tournier07", False)
    tournier[mask == 0] = 0.0

    t = time.perf_counter()
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    mean, std = residual_bootstrap(data, gtab, mask > 0, response, sphere, rng)
    uncertainty = np.zeros_like(sh)
    uncertainty[mask > 0] = sf_to_sh(mean + 2.0 * std, sphere, SH_ORDER, "descoteaux07",
                                     legacy=True, smooth=0.0)
    log(f"uncertainty: residual bootstrap, {BOOTSTRAP_SAMPLES} CSD refits, seed "
        f"{BOOTSTRAP_SEED}, SH fit of mean + 2 sd on {sphere.vertices.shape[0]} directions, in "
        f"{time.perf_counter() - t:.2f} s")

    path = lambda name: os.path.join(out, name)
    written = [
        (f"{PREFIX}_sh_descoteaux07.nii.gz", sh, "descoteaux07 (legacy=True)"),
        (f"{PREFIX}_sh_tournier07.nii.gz", tournier, "tournier07 (legacy=False, MRtrix3)"),
        (f"{PREFIX}_sh_uncertainty_descoteaux07.nii.gz", uncertainty,
         "descoteaux07 (legacy=True)"),
        (f"{PREFIX}_b0.nii.gz", b0, None),
        (f"{PREFIX}_fa.nii.gz", fa, None),
    ]
    for name, values, basis in written:
        save_nifti(path(name), values, affine)
        summary(path(name), np.asarray(values, np.float32), basis)
    save_nifti(path(f"{PREFIX}_mask.nii.gz"), mask, affine, dtype=np.uint8)
    summary(path(f"{PREFIX}_mask.nii.gz"), mask, None)

    # MIF copies for the reader test (see the docstring for the three layouts).
    source = path(f"{PREFIX}_sh_tournier07.nii.gz")
    keep_axes = ("-config", "RealignTransform", "false")
    mif_files = [
        (f"{PREFIX}_sh_tournier07.mif", keep_axes),
        (f"{PREFIX}_sh_tournier07.mif.gz", keep_axes + ("-strides", "-2,3,-4,1")),
        (f"{PREFIX}_sh_tournier07_realigned.mif", ()),
    ]
    for name, options in mif_files:
        run_mrconvert(source, path(name), *options)
        opener = gzip.open if name.endswith(".gz") else open
        with opener(path(name), "rb") as stream:
            header = stream.read(4096).split(b"\nEND\n")[0].decode("latin-1").splitlines()
        layout = next(line for line in header if line.startswith("layout:"))
        log(f"{name}: shape {tournier.shape}, basis tournier07 (mrconvert), {layout}, c00 min "
            f"{tournier[..., 0].min():.6g} max {tournier[..., 0].max():.6g}")

    if args.tile > 0:
        tiled, k, voxels = tile_slice(sh, mask, args.tile)
        tile_affine = np.diag([2.0, 2.0, 2.0, 1.0])
        name = f"{PREFIX}_sh_tiled{args.tile}.nii.gz"
        save_nifti(path(name), tiled, tile_affine)
        summary(path(name), tiled, f"descoteaux07 (legacy=True), slice k={k} ({voxels} mask "
                                   "voxels) tiled")

    log(f"generated in {time.perf_counter() - start:.2f} s into {out}")
    if args.check:
        t = time.perf_counter()
        check_sh2amp(out, mask)
        check_vtk(out, args.tile)
        check_uncertainty(out, sphere, mask)
        log(f"checks passed in {time.perf_counter() - t:.2f} s")


if __name__ == "__main__":
    main()
