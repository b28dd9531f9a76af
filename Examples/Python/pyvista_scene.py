#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Sightline in a PyVista plotter, as a notebook would use it (no X server needed with
off_screen=True on a VTK that renders offscreen; Debian's X-only VTK needs Xvfb).

Left: DIPY's minimal_bundles.zip (arcuate fasciculus, corticospinal tract, forceps major of one
subject) as exact tubes coloured per streamline by its length through a PyVista colour map,
with PyVista's scalar bar and an ordinary PyVista outline. Right: DIPY's func_coef.nii.gz
(order-8 SH coefficients, DIPY's basis) as exact SH glyphs coloured by direction.

Usage: python pyvista_scene.py [--output FILE.png] [--size W H] [--subject N]
Needs PyVista (on the same VTK as Sightline) and python3-dipy for the data files.
"""
import argparse
import os
import tempfile
import zipfile

import numpy as np
import pyvista as pv

import sightline.pyvista  # noqa: F401  (gives every plotter its `sightline` component)
from sightline import nifti
from sightline.view import read_tubes


def dipy_file(name):
    import dipy.data

    path = os.path.join(os.path.dirname(dipy.data.__file__), "files", name)
    if not os.path.exists(path):
        raise SystemExit(f"DIPY's {name} is missing ({path}): apt-get install python3-dipy")
    return path


def bundles(subject, folder):
    """sub_N's three bundles as one PyVista PolyData, with each streamline's length in mm."""
    with zipfile.ZipFile(dipy_file("minimal_bundles.zip")) as archive:
        parts = []
        for bundle in ("AF_L", "CST_R", "CC_ForcepsMajor"):
            path = archive.extract(f"sub_{subject}/{bundle}.trk", folder)
            parts.append(pv.wrap(read_tubes(path)))
    lines = parts[0].merge(parts[1:])
    lengths = []
    for cell in range(lines.n_cells):
        points = lines.get_cell(cell).points
        lengths.append(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())
    lines.cell_data["length (mm)"] = np.array(lengths)
    return lines


def sh_image():
    """func_coef.nii.gz as ImageData in its voxel grid (spacing from the header)."""
    return pv.wrap(nifti.read(dipy_file("func_coef.nii.gz")).GetOutput())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--output", default=os.path.join(tempfile.gettempdir(), "pyvista_scene.png"))
    parser.add_argument("--size", type=int, nargs=2, default=(1200, 560), metavar=("W", "H"))
    parser.add_argument("--subject", type=int, default=1, choices=range(1, 6))
    args = parser.parse_args()

    plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=args.size, border=False)
    plotter.set_background("white")
    with tempfile.TemporaryDirectory() as folder:
        lines = bundles(args.subject, folder)
    plotter.subplot(0, 0)
    plotter.sightline.add_tubes(lines, radius=0.4, scalars="length (mm)", cmap="plasma",
                                scalar_bar_args={"color": "black", "fmt": "%.0f",
                                                 "title": "streamline length (mm)"})
    plotter.add_mesh(lines.outline(), color="grey")
    plotter.view_vector((-1.0, 0.35, 0.25), viewup=(0, 0, 1))
    plotter.add_text(f"{lines.n_cells} streamlines, exact tubes", font_size=10, color="black")

    plotter.subplot(0, 1)
    image = sh_image()
    plotter.sightline.add_sh_glyphs(image, basis="descoteaux07", scale=0.9)
    plotter.add_mesh(image.outline(), color="grey")
    plotter.view_vector((1.0, -0.6, 0.8), viewup=(0, 0, 1))
    plotter.add_text(f"{image.n_points} SH glyphs (order 8), exact", font_size=10, color="black")

    shot = plotter.screenshot(args.output, return_img=True)
    plotter.close()
    drawn = np.any(shot != 255, axis=2).mean() * 100
    print(f"wrote {args.output} ({drawn:.1f}% of pixels drawn)")


if __name__ == "__main__":
    main()
