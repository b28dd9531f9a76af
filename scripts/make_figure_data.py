#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Synthetic HCP-sized fibre ODF image and T1-like underlay for report-figure benchmarks.

Usage: /usr/bin/python3 make_figure_data.py [--output DIR] [--shape NX NY NZ] [--seed N]

Writes into DIR (default /tmp/sightline-figures), never into the repository:
  fod.nii.gz  float32 (NX,NY,NZ,45): lmax-8 SH coefficients in MRtrix3's basis (DIPY's
              tournier07 with legacy=False: orthonormal real SH, m<0 from sqrt(2) Im, m>0 from
              sqrt(2) Re), directions in scanner (RAS) axes; all zero outside the brain.
  t1.nii.gz   float32 (NX,NY,NZ): a T1-like image (scalp, dark skull, CSF, cortex, bright
              white matter, ventricles, a little smooth noise).
Both have 1.25 mm voxels and a RAS affine centring the volume on the origin (qform = sform,
code 1). The default shape 145 174 145 is HCP's; --shape 20 24 20 makes a tiny copy for tests
(the brain ellipsoid, semi-axes 70 x 85 x 65 mm, shrinks to fit the field of view).

Why: issue 36 compares ODF mosaics for reports (3 x 8 slices at 3200x1200 over a T1) made by
tessellating glyphs under Xvfb (odf_slicer's way) with Sightline's GL-free renderer; this is a
whole-brain input of the real size (660 MB as float32) without needing a dataset download.

The FODs: inside the ellipsoid a smooth tissue model (white matter core, a folded cortical
band, thin CSF rim, two ventricles) and four direction fields: left-right commissural arches,
inferior-superior projections fanning out, anterior-posterior association arcs, and radial
fibres in the cortex. Their weights vary smoothly (plus seeded low-frequency modulation), the
strongest three are kept and those under 12 % of the voxel's total dropped, so voxels hold 1-3
crossing populations. Each population is a Watson-like lobe exp(-kappa (1 - (u.d)^2))
(kappa 14, broader in grey matter) expanded to lmax 8 exactly through its zonal Legendre
coefficients a_l = 2 pi int F(t) P_l(t) dt, c_lm = a_l Y_lm(d), with a mild apodisation so the
truncation leaves only small negative ripples, as CSD FODs have. A weak seeded SH noise (l >= 2)
is added. Everything is computed in slabs of z in float32/float64 slab temporaries; the only
whole-volume array is the float32 output (Fortran order, which nibabel writes as it is).
"""
import argparse
import os
import time

import numpy as np
import nibabel as nib
from numpy.polynomial import legendre
from scipy import ndimage
from dipy.reconst.shm import real_sh_tournier

SH_ORDER = 8
N_COEFFS = 45
VOXEL = 1.25
SEMI_AXES = np.array([70.0, 85.0, 65.0])  # mm, x (left-right), y (posterior-anterior), z
SLAB = 4                                   # z slices per slab


def zonal_coefficients(kappa):
    """a_l (l = 0, 2, ..., 8) of F(t) = exp(-kappa (1 - t^2)), apodised, peak amplitude ~1."""
    t, w = legendre.leggauss(200)
    f = np.exp(-kappa * (1.0 - t * t))
    a = np.array([2.0 * np.pi * np.sum(w * f * legendre.Legendre.basis(l)(t))
                  for l in range(0, SH_ORDER + 1, 2)])
    a *= np.exp(-0.5 * (np.arange(0, SH_ORDER + 1, 2) / 9.0) ** 2)  # soften truncation ringing
    peak = np.sum(a * (2 * np.arange(0, SH_ORDER + 1, 2) + 1) / (4 * np.pi))  # value at t = 1
    return a / peak


def tissue(u, fold):
    """Smooth (white matter, grey matter) fractions at normalised coordinates u (..., 3)."""
    r = np.sqrt((u ** 2).sum(-1)) * (1.0 + fold)
    wm = 1.0 / (1.0 + np.exp((r - 0.8) / 0.015))
    brain = 1.0 / (1.0 + np.exp((r - 0.95) / 0.01))
    for side in (-1.0, 1.0):  # lateral ventricles: crescents either side of the midline
        v = ((u[..., 0] - side * 0.13) / 0.08) ** 2 + ((u[..., 1] + 0.05) / 0.35) ** 2 + \
            ((u[..., 2] - 0.12) / 0.12) ** 2
        wm = wm * (1.0 / (1.0 + np.exp(-(v - 1.0) / 0.1)))
        brain = brain * (1.0 / (1.0 + np.exp(-(v - 1.0) / 0.1)))
    return wm, np.clip(brain - wm, 0.0, 1.0), brain


def folding(u):
    """Gyri: a smooth ripple (products of sines, no angular seams) of the tissue surfaces."""
    x, y, z = 9.0 * u[..., 0], 8.0 * u[..., 1], 9.0 * u[..., 2]
    return 0.02 * (np.sin(x + 0.7 * y) * np.sin(z + 1.0) + np.sin(y - 0.5 * z) * np.sin(x + 2.0)
                   + np.sin(z + 0.6 * x) * np.sin(y + 0.3))


def fields(u):
    """Unit directions (n, 4, 3): commissural, projection, association, radial."""
    d = np.empty(u.shape[:-1] + (4, 3))
    x, y, z = u[:, 0], u[:, 1], u[:, 2]
    d[:, 0] = np.stack([np.ones_like(x), 0.15 * np.sin(3.0 * y), -1.2 * x + 0.2 * z], -1)
    d[:, 1] = np.stack([1.1 * x, 0.8 * y, np.ones_like(x)], -1)
    d[:, 2] = np.stack([0.4 * x * y, np.ones_like(x), -y * (0.6 + 0.4 * z)], -1)
    d[:, 3] = u / SEMI_AXES + 1e-6  # the ellipsoid's normal (cortex: radial fibres)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def weights(u, wm, gm, modulation):
    x, y, z = u[:, 0], u[:, 1], u[:, 2]
    w = np.empty((len(u), 4))
    w[:, 0] = np.exp(-((z - 0.2) / 0.35) ** 2) * (0.55 + 0.45 * np.cos(np.pi * x / 1.4))
    w[:, 1] = np.exp(-((np.abs(x) - 0.3) / 0.25) ** 2) * np.exp(-(y / 0.65) ** 2)
    w[:, 2] = np.exp(-((np.abs(x) - 0.55) / 0.22) ** 2) * np.exp(-((z - 0.05) / 0.5) ** 2)
    for b, (k, phase) in enumerate(modulation):  # seeded low-frequency variation
        w[:, b] *= 1.0 + 0.35 * np.sin(u @ k + phase)
    w[:, :3] *= wm[:, None]
    w[:, 3] = 1.6 * gm
    w[np.arange(len(w)), np.argmin(w, axis=1)] = 0.0  # at most three populations
    w /= np.maximum(w.sum(1, keepdims=True), 1e-9)
    w[w < 0.12] = 0.0
    return w / np.maximum(w.sum(1, keepdims=True), 1e-9)


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--output", default="/tmp/sightline-figures")
    parser.add_argument("--shape", type=int, nargs=3, default=[145, 174, 145])
    parser.add_argument("--seed", type=int, default=36)
    args = parser.parse_args()
    started = time.perf_counter()
    os.makedirs(args.output, exist_ok=True)
    shape = np.array(args.shape)
    half_fov = shape * VOXEL / 2.0
    semi = SEMI_AXES * min(1.0, float(np.min(half_fov / (SEMI_AXES + 15.0))))
    affine = np.diag([VOXEL, VOXEL, VOXEL, 1.0])
    affine[:3, 3] = -(shape - 1) * VOXEL / 2.0
    rng = np.random.default_rng(args.seed)
    modulation = [(rng.normal(0, 2.5, 3), rng.uniform(0, 2 * np.pi)) for _ in range(3)]
    a_wm = zonal_coefficients(14.0)[:, None]
    a_gm = zonal_coefficients(5.0)[:, None]
    l_of = np.repeat(np.arange(0, SH_ORDER + 1, 2), 2 * np.arange(0, SH_ORDER + 1, 2) + 1)

    fod = np.zeros(tuple(shape) + (N_COEFFS,), np.float32, order="F")
    t1 = np.zeros(tuple(shape), np.float32, order="F")
    xs, ys = (np.arange(n) * VOXEL + affine[i, 3] for i, n in enumerate(shape[:2]))
    for z0 in range(0, shape[2], SLAB):
        zs = np.arange(z0, min(z0 + SLAB, shape[2])) * VOXEL + affine[2, 3]
        p = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), -1)
        u = p / semi
        fold = folding(u)
        wm, gm, brain = tissue(u, fold)
        # T1: scalp (bright), skull (dark), CSF (dark), cortex, white matter (brightest).
        r_head = np.sqrt((u ** 2).sum(-1)) * (1.0 + 0.3 * fold)
        scalp = (1.0 / (1.0 + np.exp(-(r_head - 1.09) / 0.01))) * \
            (1.0 / (1.0 + np.exp((r_head - 1.16) / 0.01)))
        inside = 1.0 / (1.0 + np.exp((r_head - 1.03) / 0.01))
        t1[:, :, z0:z0 + len(zs)] = 0.62 * scalp + 0.15 * inside + 0.28 * gm + 0.55 * wm
        mask = (brain > 0.05) & ((u ** 2).sum(-1) < 1.0)
        if not mask.any():
            continue
        um, wmm, gmm = u[mask], wm[mask], gm[mask]
        w = weights(um, wmm, gmm, modulation)
        d = fields(um)
        amplitude = 0.55 * (0.25 + 0.75 * wmm / np.maximum(wmm + gmm, 1e-6)) * brain[mask]
        coeffs = np.zeros((len(um), N_COEFFS))
        for b in range(4):  # only the populations a voxel holds
            on = w[:, b] > 0
            theta = np.arccos(np.clip(d[on, b, 2], -1.0, 1.0))
            phi = np.arctan2(d[on, b, 1], d[on, b, 0])
            zonal = (a_wm if b < 3 else a_gm)[l_of // 2, 0]
            coeffs[on] += real_sh_tournier(SH_ORDER, theta, phi, legacy=False)[0] * \
                (w[on, b] * amplitude[on])[:, None] * zonal
        noise = rng.standard_normal(coeffs.shape) * 0.006 * amplitude[:, None]
        block = np.zeros(mask.shape + (N_COEFFS,), np.float32)
        block[mask] = coeffs + noise * (l_of >= 2)
        fod[:, :, z0:z0 + len(zs)] = block
    noise = ndimage.gaussian_filter(rng.standard_normal(t1.shape).astype(np.float32), 2.0)
    t1 += (0.03 / max(float(noise.std()), 1e-9)) * noise * (t1 > 0.05)
    np.clip(t1, 0.0, None, out=t1)
    t1 *= 1000.0
    print(f"computed in {time.perf_counter() - started:.1f} s")

    for name, data in (("fod.nii.gz", fod), ("t1.nii.gz", t1)):
        path = os.path.join(args.output, name)
        begun = time.perf_counter()
        image = nib.Nifti1Image(data, affine)
        image.set_qform(affine, code=1)
        image.set_sform(affine, code=1)
        image.header.set_xyzt_units("mm", "sec")
        image.header.set_data_dtype(np.float32)
        nib.save(image, path)
        print(f"{path}: shape {data.shape} float32, {data.nbytes / 1e6:.0f} MB in memory, "
              f"{os.path.getsize(path) / 1e6:.1f} MB on disk, written in "
              f"{time.perf_counter() - begun:.1f} s")
    inside = fod[..., 0] != 0
    print(f"brain voxels {int(inside.sum()):,} of {inside.size:,}; c00 range "
          f"{fod[..., 0][inside].min():.3f}..{fod[..., 0].max():.3f}; "
          f"total {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
