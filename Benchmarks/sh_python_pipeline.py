#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The SH glyph first image as a Python user meets it: a fit in DIPY, numpy -> vtkImageData ->
vtkSightlineSHGlyphMapper in a VTK window, each step timed.

Usage (a display is needed: Xvfb and Mesa's llvmpipe here):
  xvfb-run -a -s "-noreset -screen 0 1920x1080x24" /usr/bin/python3 Benchmarks/sh_python_pipeline.py \
      [--fit csa|csd] [--tile 140] [--width 1920 --height 1080] [--runs 3] [--image out.png]

Data: DIPY's shipped small_64D (10x10x10 voxels, 64 directions at b = 1000), fitted with DIPY's
CsaOdfModel (Q-ball with constant solid angle, lmax 8, the default) or its CSD model, the axial
slice with the most tissue tiled periodically to N x N voxels, float64 as the fit returns it.
The window (1920x1080, VTK's default headlight, the camera as `sightline-benchmark --scene
sh-glyph-window` sets it: down on the slice tilted by 20 degrees) keeps VTK's default
multisampling unless --multisamples says otherwise (the C++ benchmark turns it off), and is
rendered empty before the clock starts, so creating the OpenGL context is not counted; an empty
frame's time is printed, the floor under every frame of that window.

Timed, each on its own line: importing vtk and sightline, the fit (not part of the image), numpy -> vtkImageData (a copy into
a vtkDoubleArray, or a view with --no-copy), and the first image: mapper, SetBasisToDIPY, actor
and Render until glFinish, split into the mapper's own GetLastGeometrySeconds (glyph boxes and
largest amplitudes), GetLastBuildSeconds (BVH) and GetLastFrameSeconds (trace); then --runs
still frames, each after Azimuth(1); and the wall clock from the script's start to the first
image (imports, fit, context and all), which is what a user timing the whole script sees. Also printed: glyphs drawn and the share of the image's
pixels they cover, which is what the trace time follows.
"""
import time

PROCESS_START = time.perf_counter()

import argparse
import sys

import numpy as np

import vtkmodules.all as vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline

IMPORT_SECONDS = time.perf_counter() - PROCESS_START


def fit_slice(kind, masked):
    """Fits small_64D and returns its axial slice with the most tissue (nx, ny, 45), float64;
    without the mask every voxel is fitted (CSF included), as a first try often does."""
    from dipy.core.gradients import gradient_table
    from dipy.data import get_fnames
    from dipy.io import read_bvals_bvecs
    import nibabel as nib

    image_path, bvals_path, bvecs_path = get_fnames("small_64D")
    dwi = np.asarray(nib.load(image_path).dataobj, dtype=np.float64)
    bvals, bvecs = read_bvals_bvecs(bvals_path, bvecs_path)
    gtab = gradient_table(bvals, bvecs)
    if kind == "csa":
        from dipy.reconst.shm import CsaOdfModel

        model = CsaOdfModel(gtab, sh_order=8)
    else:
        from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel, auto_response_ssst

        response, _ = auto_response_ssst(gtab, dwi, roi_radii=10, fa_thr=0.7)
        model = ConstrainedSphericalDeconvModel(gtab, response, sh_order=8)
    b0 = dwi[..., bvals < 50].mean(axis=-1)
    # Tissue: b0 at or below Otsu's threshold (CSF is bright on b0), as scripts/make_sh_data.py.
    from dipy.segment.threshold import otsu

    mask = b0 <= otsu(b0)
    best = int(np.argmax(mask.sum(axis=(0, 1))))
    fitted = model.fit(dwi[:, :, best], mask=mask[:, :, best] if masked else None)
    coefficients = fitted.shm_coeff
    return np.asarray(coefficients, dtype=np.float64)


def tiled_image(coefficients, tile, copy):
    """An N x N x 1 vtkImageData with the coefficients as its point array (x fastest)."""
    nx, ny, count = coefficients.shape
    repeated = np.tile(coefficients, (tile // nx + 1, tile // ny + 1, 1))[:tile, :tile]
    # VTK's point order is x fastest: transpose to (y, x, c) before flattening.
    flat = np.ascontiguousarray(repeated.transpose(1, 0, 2).reshape(-1, count))
    image = vtk.vtkImageData()
    image.SetDimensions(tile, tile, 1)
    image.SetSpacing(2.0, 2.0, 2.0)
    array = numpy_to_vtk(flat, deep=1 if copy else 0)
    array.SetName("sh")
    image.GetPointData().AddArray(array)
    return image, flat  # keep the numpy buffer alive when VTK only views it


def make_camera(bounds):
    """sightline-benchmark's window camera: down on the slice, tilted by 20 degrees, zoomed 1.35x,
    the clipping range around the slice's bounding sphere."""
    center = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
    r = 0.5 * np.sqrt(sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)))
    camera = vtk.vtkCamera()
    tilt = np.radians(20.0)
    distance = r / np.sin(0.5 * np.radians(camera.GetViewAngle()))
    camera.SetFocalPoint(center)
    camera.SetPosition(center[0], center[1] - distance * np.sin(tilt), center[2] + distance * np.cos(tilt))
    camera.SetViewUp(0.0, np.cos(tilt), np.sin(tilt))
    camera.Zoom(1.35)
    camera.SetClippingRange(distance - 1.05 * r, distance + 1.05 * r)
    return camera


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fit", choices=["csa", "csd"], default="csa")
    parser.add_argument("--tile", type=int, default=140)
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--order", type=int, default=8, help="SetMaximumOrder")
    parser.add_argument("--multisamples", type=int, default=None,
                        help="the window's MultiSamples (default: VTK's own, 4 here)")
    parser.add_argument("--no-mask", action="store_true", help="fit every voxel, CSF included")
    parser.add_argument("--no-copy", action="store_true", help="VTK views the numpy buffer")
    parser.add_argument("--image", help="write the first image to this PNG")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 unless every non-zero voxel is drawn, its box computed, "
                        "and the glyphs cover part of the image (a smoke test)")
    args = parser.parse_args()

    start = time.perf_counter()
    coefficients = fit_slice(args.fit, not args.no_mask)  # DIPY's own imports included
    fit_seconds = time.perf_counter() - start

    start = time.perf_counter()
    image, flat = tiled_image(coefficients, args.tile, not args.no_copy)
    convert_seconds = time.perf_counter() - start
    bounds = image.GetBounds()

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    if args.multisamples is not None:
        window.SetMultiSamples(args.multisamples)
    window.SetSize(args.width, args.height)
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0.1, 0.1, 0.12)
    renderer.SetActiveCamera(make_camera(bounds))
    window.AddRenderer(renderer)
    start = time.perf_counter()
    window.Render()  # the OpenGL context: not part of the first image
    window.WaitForCompletion()
    context_seconds = time.perf_counter() - start
    empty = []
    for _ in range(3):  # what VTK's own frame costs in this window, whatever it draws
        renderer.GetActiveCamera().Azimuth(1.0)
        start = time.perf_counter()
        window.Render()
        window.WaitForCompletion()
        empty.append(time.perf_counter() - start)
    renderer.GetActiveCamera().Azimuth(-3.0)

    start = time.perf_counter()
    mapper = sightline.vtkSightlineSHGlyphMapper()
    mapper.SetInputDataObject(image)
    mapper.SetCoefficientArrayName("sh")
    mapper.SetBasisToDIPY()
    mapper.SetMaximumOrder(args.order)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    renderer.AddActor(actor)
    window.Render()
    window.WaitForCompletion()
    first_seconds = time.perf_counter() - start
    script_seconds = time.perf_counter() - PROCESS_START
    geometry = mapper.GetLastGeometrySeconds()
    bvh = mapper.GetLastBuildSeconds()
    trace = mapper.GetLastFrameSeconds()
    computed_boxes = mapper.GetLastComputedBoxes()

    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    rgb = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
    background = np.round(np.array(renderer.GetBackground()) * 255)
    covered = float(np.mean(np.any(np.abs(rgb[:, :3].astype(float) - background) > 1, axis=1)))
    if args.image:
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(args.image)
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()

    still = []
    traces = []
    for _ in range(args.runs):
        renderer.GetActiveCamera().Azimuth(1.0)
        start = time.perf_counter()
        window.Render()
        window.WaitForCompletion()
        still.append(time.perf_counter() - start)
        traces.append(mapper.GetLastFrameSeconds())

    print(f"data: small_64D, {args.fit.upper()} fit (lmax 8) of its fullest axial slice "
          f"({'every voxel' if args.no_mask else 'tissue mask'}), tiled to {args.tile} x {args.tile}, float64; k = {args.order}")
    print(f"glyphs drawn: {mapper.GetNumberOfPrimitives()}; glyph pixels: {100 * covered:.1f} % "
          f"of {args.width} x {args.height}")
    print(f"import vtk and sightline:           {IMPORT_SECONDS:.3f} s")
    print(f"fit (DIPY, not part of the image):  {fit_seconds:.3f} s")
    print(f"numpy -> vtkImageData ({'view' if args.no_copy else 'copy'}):  {convert_seconds:.3f} s")
    print(f"OpenGL context (first empty Render): {context_seconds:.3f} s")
    print(f"an empty frame of this window ({window.GetMultiSamples()} samples a pixel): "
          f"{sorted(empty)[1]:.3f} s")
    print(f"first image:                        {first_seconds:.3f} s")
    print(f"  glyph boxes and amplitudes:       {geometry:.3f} s")
    print(f"  BVH:                              {bvh:.3f} s")
    print(f"  trace:                            {trace:.3f} s")
    print(f"  the rest (upload, compositing, VTK): {first_seconds - geometry - bvh - trace:.3f} s")
    print(f"the script from its start to the first image: {script_seconds:.3f} s")
    print(f"still frame (median of {args.runs}):       {sorted(still)[len(still) // 2]:.3f} s "
          f"(trace {sorted(traces)[len(traces) // 2]:.3f} s)")
    if args.check:
        expected = int(np.count_nonzero(np.any(flat != 0.0, axis=1)))
        problems = []
        if mapper.GetNumberOfPrimitives() != expected:
            problems.append(f"{mapper.GetNumberOfPrimitives()} glyphs drawn, {expected} non-zero voxels")
        if computed_boxes != expected:
            problems.append(f"{computed_boxes} boxes computed for {expected} glyphs")
        if not 0.0 < covered < 0.9:
            problems.append(f"glyphs cover {100 * covered:.1f} % of the image")
        if not all(t > 0.0 for t in traces):
            problems.append("a still frame was not traced again")
        for problem in problems:
            print("check failed:", problem, file=sys.stderr)
        return 1 if problems else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
