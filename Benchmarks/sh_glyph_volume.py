#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""A whole 3-D field of exact SH glyphs in a VTK window, as a user's Python pipeline builds it:
DIPY's small_64D CSD fit (lmax 8, all-zero outside its tissue mask), tiled to 100 x 100 x 60
voxels, numpy -> vtkImageData -> vtkSightlineSHGlyphMapper (SetBasisToDIPY, every voxel of the
extent), 1920x1080.

Reports: the glyphs drawn; the box computation (the mapper's geometry, which VTK's first
ResetCameraClippingRange asks for through GetBounds); the first Render; the first image (both);
a still frame after a small turn; then a frame of the other view: the close-up (dolly 3x, or
--dolly: most glyphs behind the camera or outside the view) after the whole field, or the whole field after
the close-up (--first-view close); peak RSS before the mapper and at the end. With --culling the
mapper's FrustumCulling is on: boxes only for the glyphs in view (the rest get loose boxes until
a still frame shows them); the boxes computed and left loose are reported per frame. Timings
are the machine's, not pass/fail.

Usage: xvfb-run -a -s "-noreset -screen 0 1920x1080x24" /usr/bin/python3 sh_glyph_volume.py
         [--data-dir DIR] [--tile 10 10 6] [--size 1920 1080] [--culling]
         [--first-view whole|close] [--dolly 3] [--png FILE]
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
    parser.add_argument("--png", help="write the last frame here")
    parser.add_argument("--culling", action="store_true", help="FrustumCulling on")
    parser.add_argument("--first-view", choices=["whole", "close"], default="whole",
                        help="the view of the first image (the other one comes last)")
    parser.add_argument("--dolly", type=float, default=3.0,
                        help="how far the close-up moves towards the centre (camera Dolly)")
    parser.add_argument("--check", action="store_true",
                        help="fail unless every glyph is drawn and, with --culling and a "
                        "close first view, the close-up left boxes loose and the whole field "
                        "computed boxes and left fewer loose (the smoke test)")
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
    mapper.SetFrustumCulling(args.culling)
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
    # The view of the default 100-voxel-wide field, scaled with the field.
    camera.SetPosition(*(centre + np.array([260.0, -330.0, 300.0]) * max(nx, ny, nz) / 100.0))
    if args.first_view == "close":
        camera.Dolly(args.dolly)

    def boxes():
        return (f"{mapper.GetLastComputedBoxes()} boxes computed, "
                f"{mapper.GetLastLooseBoxes()} loose")

    started = time.perf_counter()
    renderer.ResetCameraClippingRange()  # asks for the bounds: the boxes
    bounded = time.perf_counter()
    bounds_geometry = (mapper.GetLastGeometrySeconds(), mapper.GetLastBuildSeconds())
    window.Render()
    first = time.perf_counter()
    first_boxes = boxes()
    first_loose = mapper.GetLastLooseBoxes()
    camera.Azimuth(3.0)
    window.Render()
    still = time.perf_counter()
    camera.Dolly(args.dolly if args.first_view == "whole" else 1.0 / args.dolly)
    renderer.ResetCameraClippingRange()
    window.Render()
    other = time.perf_counter()
    other_name = "close-up" if args.first_view == "whole" else "whole-field"
    print(f"{glyphs} glyphs ({nx} x {ny} x {nz} voxels), {args.size[0]}x{args.size[1]}, "
          f"first view {args.first_view}, frustum culling {'on' if args.culling else 'off'}")
    print(f"boxes (GetBounds) {bounded - started:.2f} s (mapper geometry "
          f"{bounds_geometry[0]:.2f} s, BVH {bounds_geometry[1]:.2f} s); "
          f"first Render {first - bounded:.2f} s ({first_boxes}); first image {first - started:.2f} s")
    print(f"still frame {still - first:.2f} s; {other_name} frame {other - still:.2f} s ({boxes()})")
    print(f"peak RSS {peak_rss_mib():.0f} MiB ({before:.0f} MiB with the input alone, "
          f"+{peak_rss_mib() - before:.0f} MiB)")
    if args.check:
        problems = []
        if mapper.GetNumberOfPrimitives() != glyphs:
            problems.append(f"{mapper.GetNumberOfPrimitives()} glyphs drawn, not {glyphs}")
        if args.culling and args.first_view == "close":
            if not 0 < first_loose < glyphs:
                problems.append(f"the close-up left {first_loose} of {glyphs} boxes loose")
            if not (mapper.GetLastComputedBoxes() > 0 and mapper.GetLastLooseBoxes() < first_loose):
                problems.append(f"the whole field computed {mapper.GetLastComputedBoxes()} boxes "
                                f"and left {mapper.GetLastLooseBoxes()} loose")
        if problems:
            print("check failed: " + "; ".join(problems))
            return 1
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
