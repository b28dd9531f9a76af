#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Real higher-order tensor test and showcase data from DIPY's shipped DWI `small_64D`.

Usage: make_tensor_data.py OUTPUT_DIR [--check]

Run with Debian's /usr/bin/python3 (python3-dipy, python3-nibabel, python3-vtk9 for --check).
Everything goes into OUTPUT_DIR, never into the repository; deterministic and fast (a few
seconds). CTest runs it as the fixture setup test TensorData.Generate.

Input: dipy.data.get_fnames('small_64D'): 10x10x10x65 int16, one b=0 and 64 directions at
b=1000 s/mm^2, 2 mm voxels, an affine that permutes and rotates the axes (qfac = -1). The
b-vectors are in the image's voxel axes (see make_sh_data.py), so the tensors are too.

Component order (Sightline's unique components, vtkSightlineTensorGlyphMapper's
LAYOUT_SYMMETRIC_UNIQUE): one value T_i per monomial x^a y^b z^c with a + b + c = n, sorted by a
descending, then b descending. Order 2: xx, xy, xz, yy, yz, zz (FSL dtifit's order; DIPY's own
lower-triangular order is xx, xy, yy, xz, yz, zz). Each value is the tensor entry, standing for
its n!/(a! b! c!) equal entries of the full tensor; T(g) = sum_i mult_i T_i g^(a,b,c).

Files written (float32, the DWI's affine as qform and sform, code 1; zero outside the mask):
  small_64D_dti.nii.gz        (10,10,10,6)  diffusion tensor, DIPY TensorModel (WLS, its
                              default), mm^2/s (about 1e-3).
  small_64D_gdti4.nii.gz      (10,10,10,15) generalised DTI of order 4 (Ozarslan and Mareci
  small_64D_gdti6.nii.gz      (10,10,10,28) 2003): the apparent diffusion coefficient
  small_64D_gdti8.nii.gz      (10,10,10,45) D(g) = -ln(S(g)/S0)/b fitted per voxel by ordinary
                              least squares as a symmetric tensor of order 4, 6, 8 (S/S0
                              clipped to [1e-3, 1] before the logarithm, S0 the b=0 volume).
  small_64D_dti_fa.nii.gz     FA of the DTI fit (an underlay).
  small_64D_tensor_mask.nii.gz (uint8) the tissue mask of make_sh_data.py: b0 at or below
                              Otsu's threshold of the b0 (the crop lies inside the brain; this
                              separates tissue from CSF, whose profiles are near-isotropic
                              noise).

--check verifies: (a) the order-2 fit of the same least-squares code equals DIPY's
TensorModel(fit_method='LS') (validates design matrix and multiplicities); (b) each order
reproduces its own fitted ADC values at the 64 directions (the normal equations hold) and the
mean residual does not grow with the order; (c) vtkNIFTIImageReader (TimeAsVectorOn) reads each
file as one array of 6/15/28/45 components with nibabel's values, slices reversed (qfac -1).
"""
import argparse
import math
import os
import sys
import time
import warnings

import numpy as np

try:
    import nibabel as nib
    import dipy.reconst.dti as dti
except ImportError as error:  # a missing dependency is a failure, not a skip
    sys.exit(f"make_tensor_data.py: {error} (run with /usr/bin/python3; install python3-dipy, "
             "python3-nibabel)")
# The same input, mask, NIfTI writer and VTK reading as the SH data (this script's folder).
from make_sh_data import load_small_64d, log, read_with_vtk, save_nifti

warnings.simplefilter("ignore")
PREFIX = "small_64D"
ORDERS = (4, 6, 8)
SIGNAL_FLOOR = 1e-3


def exponents(order):
    """(a, b, c) of each unique component, in Sightline's order."""
    return [(a, b, order - a - b) for a in range(order, -1, -1) for b in range(order - a, -1, -1)]


def design_matrix(bvecs, order):
    """Rows: mult_i g_x^a g_y^b g_z^c, so that design @ T = T(g)."""
    columns = []
    for a, b, c in exponents(order):
        mult = math.factorial(order) / (math.factorial(a) * math.factorial(b) * math.factorial(c))
        columns.append(mult * bvecs[:, 0] ** a * bvecs[:, 1] ** b * bvecs[:, 2] ** c)
    return np.stack(columns, axis=1)


def adc(data, gtab):
    """-ln(S/S0)/b at every diffusion-weighted direction, (..., directions)."""
    s0 = data[..., gtab.b0s_mask].mean(axis=-1)
    weighted = ~gtab.b0s_mask
    ratio = data[..., weighted] / np.maximum(s0[..., None], 1e-12)
    ratio = np.clip(ratio, SIGNAL_FLOOR, 1.0)
    return -np.log(ratio) / gtab.bvals[weighted]


def fit_tensor(values, bvecs, order):
    """Ordinary least squares of the ADC values as an order-n tensor: (..., components)."""
    design = design_matrix(bvecs, order)
    flat = values.reshape(-1, values.shape[-1])
    tensors, *_ = np.linalg.lstsq(design, flat.T, rcond=None)
    return tensors.T.reshape(values.shape[:-1] + (design.shape[1],)), design


def check_vtk(out, names):
    for name, components in names:
        path = os.path.join(out, name)
        expected = np.asarray(nib.load(path).dataobj)
        reader, scalars, got = read_with_vtk(path)
        dims = reader.GetOutput().GetDimensions()
        assert scalars.GetNumberOfComponents() == components, scalars.GetNumberOfComponents()
        assert reader.GetQFac() < 0
        assert np.array_equal(got, expected[:, :, ::-1, :]), "expected reversed slices (qfac -1)"
        log(f"check VTK {name}: {components} components in array '{scalars.GetName()}', "
            f"dims {dims}, slices reversed (qfac -1), values equal nibabel's")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("output_dir")
    parser.add_argument("--check", action="store_true",
                        help="verify the fits against DIPY and the files with VTK's reader")
    args = parser.parse_args()
    out = os.path.abspath(args.output_dir)
    os.makedirs(out, exist_ok=True)
    start = time.perf_counter()

    affine, data, gtab, b0, mask = load_small_64d()
    weighted = ~gtab.b0s_mask
    directions = gtab.bvecs[weighted]
    inside = mask > 0

    fit = dti.TensorModel(gtab).fit(data)
    lower = dti.lower_triangular(fit.quadratic_form)  # xx, xy, yy, xz, yz, zz
    tensor = lower[..., [0, 1, 3, 2, 4, 5]]             # -> xx, xy, xz, yy, yz, zz
    tensor[~inside] = 0.0
    fa = np.clip(np.nan_to_num(fit.fa), 0.0, 1.0)
    save_nifti(os.path.join(out, f"{PREFIX}_dti.nii.gz"), tensor, affine)
    save_nifti(os.path.join(out, f"{PREFIX}_dti_fa.nii.gz"), fa, affine)
    save_nifti(os.path.join(out, f"{PREFIX}_tensor_mask.nii.gz"), mask, affine, np.uint8)
    log(f"DTI: {int(inside.sum())} voxels in the tissue mask; eigenvalues "
        f"{np.linalg.eigvalsh(fit.quadratic_form[inside]).min():.3g} .. "
        f"{np.linalg.eigvalsh(fit.quadratic_form[inside]).max():.3g} mm^2/s; mean FA "
        f"{fa[inside].mean():.3f}")

    values = adc(data, gtab)
    residuals = {}
    for order in ORDERS:
        tensors, design = fit_tensor(values, directions, order)
        tensors[~inside] = 0.0
        save_nifti(os.path.join(out, f"{PREFIX}_gdti{order}.nii.gz"), tensors, affine)
        predicted = np.einsum("dc,...c->...d", design, tensors)
        residuals[order] = np.sqrt(((predicted - values)[inside] ** 2).mean())
        profile = predicted[inside]
        log(f"GDTI order {order}: {tensors.shape[-1]} components; ADC profile "
            f"{profile.min():.3g} .. {profile.max():.3g} mm^2/s at the measured directions; "
            f"RMS residual {residuals[order]:.3g}")

    if args.check:
        # (a) Our design matrix at order 2, in DIPY's LS model (ln S = ln S0 - b T(g), S0
        # free, every measurement), against DIPY's own fit.
        rows = np.zeros((len(gtab.bvals), 3))
        rows[weighted] = directions
        design = np.concatenate([-gtab.bvals[:, None] * design_matrix(rows, 2),
                                 np.ones((len(gtab.bvals), 1))], axis=1)
        logs = np.log(np.maximum(data[inside], 1.0))  # both clip the signal at 1
        ours = np.linalg.lstsq(design, logs.T, rcond=None)[0].T[:, :6]
        ls = dti.TensorModel(gtab, fit_method="LS", min_signal=1.0).fit(data[inside])
        theirs = dti.lower_triangular(ls.quadratic_form)[..., [0, 1, 3, 2, 4, 5]]
        # DIPY clips eigenvalues at its minimum diffusivity: compare where ours are positive.
        matrices = ours[:, [0, 1, 2, 1, 3, 4, 2, 4, 5]].reshape(-1, 3, 3)
        definite = np.linalg.eigvalsh(matrices).min(axis=1) > 1e-6
        error = np.abs(ours - theirs)[definite].max() / np.abs(theirs[definite]).max()
        log(f"check (a): order-2 tensors from our design matrix against DIPY "
            f"TensorModel(fit_method='LS') in the {int(definite.sum())} voxels whose tensor is "
            f"positive definite ({int((~definite).sum())} others DIPY clips): largest difference "
            f"{error:.2e} of the largest entry")
        assert error < 1e-5, error
        # (b) Normal equations and residuals per order.
        previous = np.inf
        for order in ORDERS:
            tensors, design = fit_tensor(values, directions, order)
            gradient = design.T @ (np.einsum("dc,...c->...d", design, tensors) - values)[inside].T
            assert np.abs(gradient).max() < 1e-9, np.abs(gradient).max()
            assert residuals[order] <= previous * (1 + 1e-9), (order, residuals[order], previous)
            previous = residuals[order]
        log("check (b): normal equations hold for every order; RMS residual by order "
            + ", ".join(f"{n}: {residuals[n]:.3g}" for n in ORDERS))
        check_vtk(out, [(f"{PREFIX}_dti.nii.gz", 6)] +
                  [(f"{PREFIX}_gdti{n}.nii.gz", len(exponents(n))) for n in ORDERS])
    log(f"wrote {out} in {time.perf_counter() - start:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
