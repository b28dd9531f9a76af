#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""A whole 3-D field of exact SH glyphs in a VTK window, as a user's Python pipeline builds it:
DIPY's small_64D CSD fit (lmax 8, all-zero outside its tissue mask), tiled to 100 x 100 x 60
voxels, numpy -> vtkImageData -> vtkSightlineSHGlyphMapper (SetBasisToDIPY, every voxel of the
extent), 1920x1080.

Reports: the glyphs drawn; the box computation (the mapper's geometry, which VTK's first
ResetCameraClippingRange asks for through GetBounds); the first Render; the first image (both);
a still frame after a small turn; a close-up frame (dolly 3x: most glyphs behind the camera or
outside the view); peak RSS before the mapper and at the end. Timings are the machine's, not
pass/fail.

Usage: xvfb-run -a -s "-noreset -screen 0 1920x1080x24" /usr/bin/python3 sh_glyph_volume.py
         [--data-dir DIR] [--tile 10 10 6] [--size 1920 1080] [--png FILE]
with PYTHONPATH at the build tree's lib/python3/dist-packages. DIR holds
small_64D_sh_descoteaux07.nii.gz (scripts/make_sh_data.py DIR writes it; it is run when missing).
"""
import argparse
import os
import resource
import subprocess
import sys
import time

import nibabel as nib
import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk

import sightline

HERE = os.path.dirname(os.path.abspath(__file__))


def peak_rss_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--data-dir", default="/tmp/sh-data")
    parser.add_argument("--tile", type=int, nargs=3, default=[10, 10, 6])
    parser.add_argument("--size", type=int, nargs=2, default=[1920, 1080])
    parser.add_argument("--png", help="write the close-up frame here")
    args = parser.parse_args()

    path = os.path.join(args.data_dir, "small_64D_sh_descoteaux07.nii.gz")
    if not os.path.exists(path):
        subprocess.run([sys.executable, os.path.join(HERE, os.pardir, "scripts", "make_sh_data.py"),
                        args.data_dir], check=True)
    sh = np.asarray(nib.load(path).dataobj, dtype=np.float32)
    field = np.tile(sh, (*args.tile, 1))
    nx, ny, nz, count = field.shape
    glyphs = int(np.count_nonzero(np.any(field != 0, axis=3)))
    image = vtk.vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(2.0, 2.0, 2.0)
    array = numpy_to_vtk(np.ascontiguousarray(field.transpose(2, 1, 0, 3).reshape(-1, count)), deep=1)
    array.SetName("sh")
    image.GetPointData().SetScalars(array)
    del field
    before = peak_rss_mib()

    mapper = sightline.vtkSightlineSHGlyphMapper()
    mapper.SetInputDataObject(image)
    mapper.SetBasisToDIPY()
    mapper.SetSliceOrientationToExtent()
    mapper.SetDisplayExtent(0, nx - 1, 0, ny - 1, 0, nz - 1)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    renderer = vtk.vtkRenderer()
    renderer.AddActor(actor)
    window = vtk.vtkRenderWindow()
    window.SetSize(*args.size)
    window.AddRenderer(renderer)
    window.SetOffScreenRendering(1)
    camera = renderer.GetActiveCamera()
    centre = np.array([nx - 1, ny - 1, nz - 1], dtype=float)  # 2 mm voxels: the extent's centre
    camera.SetFocalPoint(*centre)
    camera.SetPosition(*(centre + [260.0, -330.0, 300.0]))

    started = time.perf_counter()
    renderer.ResetCameraClippingRange()  # asks for the bounds: the boxes
    bounded = time.perf_counter()
    window.Render()
    first = time.perf_counter()
    camera.Azimuth(3.0)
    window.Render()
    still = time.perf_counter()
    camera.Dolly(3.0)
    renderer.ResetCameraClippingRange()
    window.Render()
    close = time.perf_counter()
    print(f"{glyphs} glyphs ({nx} x {ny} x {nz} voxels), {args.size[0]}x{args.size[1]}")
    print(f"boxes (GetBounds) {bounded - started:.2f} s (mapper geometry "
          f"{mapper.GetLastGeometrySeconds():.2f} s, BVH {mapper.GetLastBuildSeconds():.2f} s); "
          f"first Render {first - bounded:.2f} s; first image {first - started:.2f} s")
    print(f"still frame {still - first:.2f} s; close-up frame {close - still:.2f} s")
    print(f"peak RSS {peak_rss_mib():.0f} MiB ({before:.0f} MiB with the input alone, "
          f"+{peak_rss_mib() - before:.0f} MiB)")
    if args.png:
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(args.png)
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()
    return 0


if __name__ == "__main__":
    sys.exit(main())
