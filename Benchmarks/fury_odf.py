#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""FURY's ray-traced SH glyphs beside Sightline's, on the same SH field in the same window.

FURY 0.12's actor.odf is a GPU port of the SH glyph paper Sightline implements (Peters et al.):
a fragment shader on each glyph's bounding box finds the ray's roots, with the coefficients
normalised per glyph into an 8-bit texture. This script draws the same field of crossing-fibre
ODFs (DIPY's multi_tensor_odf fitted with DIPY's sf_to_sh in the descoteaux07 basis) with each,
in one offscreen VTK window (Debian's VTK 9.1 under Xvfb: Mesa's llvmpipe), at SH orders 4, 8
and 12, and reports, without tuning either:

- frame time (median of the frames after two warm-up frames; the camera turns by 0.1 degree
  each frame so neither can reuse a frame);
- coverage: pixels drawn by only one of the two, against the pixels Sightline draws;
- depth: where both draw, |z_FURY - z_Sightline| in world units, Sightline's exact roots being
  the reference (FURY writes no gl_FragDepth: the depth it leaves is its box's);
- size: three order-0 glyphs (spheres of radius c0 / (2 sqrt(pi)) for c0 = 1, 2, 4), seen
  from above with a parallel camera: the radius each draws against the exact one.

Writes results-fury-odf-DATE.csv and fury-odf-DATE.png (Sightline | FURY | differences, order 8)
into --output. Needs FURY 0.12 on Debian's VTK (a virtual environment of /usr/bin/python3 with
`pip install --no-deps fury==0.12.0 lazy-loader pygltflib`) and an X display (Xvfb).
Usage: python fury_odf.py [--glyphs N] [--size PIXELS] [--frames F] [--output DIR]
"""
import argparse
import csv
import datetime
import math
import os
import platform
import statistics
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline

MAX_RADIUS = 0.4  # each glyph's largest amplitude, world units (glyphs 1 apart)


def odf_field(count, order, seed=7):
    """count x count crossing-fibre ODFs (one to three fibres, random directions and weights)
    as descoteaux07 (legacy, DIPY's default) SH coefficients of `order`, each scaled so that its
    largest amplitude on DIPY's 724-direction sphere is MAX_RADIUS."""
    from dipy.data import get_sphere
    from dipy.reconst.shm import sf_to_sh, sh_to_sf
    from dipy.sims.voxel import multi_tensor_odf

    sphere = get_sphere("repulsion724")
    rng = np.random.default_rng(seed)
    coefficients = []
    for _ in range(count * count):
        fibres = int(rng.integers(1, 4))
        angles = [(float(rng.uniform(0, 180)), float(rng.uniform(0, 360))) for _ in range(fibres)]
        weights = rng.dirichlet(np.ones(fibres)) * 100
        evals = np.array([[0.0017, 0.0003, 0.0003]] * fibres)
        sf = multi_tensor_odf(sphere.vertices, evals, angles, weights)
        sh = sf_to_sh(sf, sphere, sh_order=order, basis_type="descoteaux07")
        amplitude = np.abs(sh_to_sf(sh, sphere, sh_order=order, basis_type="descoteaux07")).max()
        coefficients.append(sh * MAX_RADIUS / amplitude)
    return np.array(coefficients)


def sightline_actor(coefficients, count):
    """Sightline's glyphs: an image of spacing 1 whose voxels hold the coefficients, drawn
    unnormalised at scale 2 (half voxels), so a glyph's radius is |F| in world units."""
    image = vtk.vtkImageData()
    image.SetDimensions(count, count, 1)
    array = numpy_to_vtk(np.ascontiguousarray(coefficients, dtype=np.float32), deep=True)
    array.SetName("sh")
    image.GetPointData().SetScalars(array)
    mapper = sightline.vtkSightlineSHGlyphMapper()
    mapper.SetInputDataObject(image)
    mapper.SetBasisByName("descoteaux07")
    mapper.SetLegacyBasis(True)
    mapper.SetNormalizationToNone()
    mapper.SetScaleFactor(2.0)
    mapper.SetSliceOrientationToExtent()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    return actor


def fury_actor(coefficients, count):
    from fury import actor

    centres = np.array([[i, j, 0.0] for j in range(count) for i in range(count)])
    # FURY sizes each glyph by its box ('scales: ODF size'): boxes as wide as the glyphs are.
    return actor.odf(centres, coefficients, sh_basis="descoteaux", scales=2 * MAX_RADIUS)


def window_depth(window, size):
    """The window's depth buffer as a (rows, columns) array, row 0 at the bottom."""
    z = vtk.vtkFloatArray()
    window.GetZbufferData(0, 0, size - 1, size - 1, z)
    return vtk_to_numpy(z).reshape(size, size).copy()


def window_pixels(window, size):
    rgb = vtk.vtkUnsignedCharArray()
    window.GetPixelData(0, 0, size - 1, size - 1, 1, rgb, 0)
    return vtk_to_numpy(rgb).reshape(size, size, 3)[::-1].copy()


def eye_distance(z, near, far):
    """Window depth (0..1) of a perspective camera -> distance along the view axis."""
    ndc = 2.0 * z - 1.0
    return 2.0 * near * far / (far + near - ndc * (far - near))


def draw(window, renderer, actor, frames, size):
    """(median frame seconds, first frame seconds, depth, pixels) of `actor` alone."""
    renderer.RemoveAllViewProps()
    renderer.AddActor(actor)
    camera = renderer.GetActiveCamera()
    start = time.perf_counter()
    window.Render()
    first = time.perf_counter() - start
    times = []
    for frame in range(frames + 2):
        camera.Azimuth(0.1 if frame % 2 == 0 else -0.1)
        start = time.perf_counter()
        window.Render()
        times.append(time.perf_counter() - start)
    window.Render()
    return statistics.median(times[2:]), first, window_depth(window, size), window_pixels(window, size)


def drawn_radii(window, renderer, actor, centres, size, half_height):
    """Radius of the disc drawn around each centre (from its pixel count), parallel camera
    along -z with `half_height` world units from the centre to the top."""
    renderer.RemoveAllViewProps()
    renderer.AddActor(actor)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(0, 0, 20)
    camera.SetViewUp(0, 1, 0)
    camera.ParallelProjectionOn()
    camera.SetParallelScale(half_height)
    camera.SetClippingRange(1, 40)
    window.Render()
    hit = window_depth(window, size) < 1.0
    pixel = 2.0 * half_height / size
    radii = []
    for x, y, _ in centres:
        column, row = int((x + half_height) / pixel), int((y + half_height) / pixel)
        reach = int(1.2 / pixel)
        patch = hit[max(row - reach, 0):row + reach, max(column - reach, 0):column + reach]
        radii.append(math.sqrt(patch.sum() / math.pi) * pixel)
    camera.ParallelProjectionOff()
    return radii


def size_check(window, renderer, size):
    """(exact, Sightline, FURY) radii of order-0 glyphs with c0 = 1, 2, 4 (order 2 arrays)."""
    from fury import actor

    c0 = np.array([1.0, 2.0, 4.0])
    coefficients = np.zeros((3, 6))
    coefficients[:, 0] = c0
    centres = np.array([[-2.5, 0.0, 0.0], [0.0, 0.0, 0.0], [2.5, 0.0, 0.0]])
    image = vtk.vtkImageData()
    image.SetDimensions(3, 1, 1)
    image.SetOrigin(-2.5, 0, 0)
    image.SetSpacing(2.5, 1, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(coefficients.astype(np.float32), deep=True))
    mapper = sightline.vtkSightlineSHGlyphMapper()
    mapper.SetInputDataObject(image)
    mapper.SetNormalizationToNone()
    mapper.SetScaleFactor(2.0 / 2.5)  # half voxels of 2.5: radius = |F| in world units
    ours = vtk.vtkActor()
    ours.SetMapper(mapper)
    theirs = actor.odf(centres, coefficients, sh_basis="descoteaux", scales=2.4)
    exact = c0 / (2.0 * math.sqrt(math.pi))
    return (exact, drawn_radii(window, renderer, ours, centres, size, 4.0),
            drawn_radii(window, renderer, theirs, centres, size, 4.0))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--glyphs", type=int, default=10, help="N for an N x N field (default 10)")
    parser.add_argument("--size", type=int, default=600, help="window width = height (pixels)")
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--orders", type=int, nargs="+", default=[4, 8, 12])
    parser.add_argument("--output", default=os.path.dirname(os.path.abspath(__file__)))
    args = parser.parse_args()
    import fury

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.SetSize(args.size, args.size)
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0, 0, 0)
    window.AddRenderer(renderer)
    window.Render()
    gl = window.ReportCapabilities()
    renderer_line = next((line for line in gl.splitlines() if "renderer string" in line), "?")
    print(f"{platform.node()}: {os.cpu_count()} cores; {renderer_line.strip()}; "
          f"VTK {vtk.vtkVersion.GetVTKVersion()}, FURY {fury.__version__}")

    exact, ours, theirs = size_check(window, renderer, args.size)
    print("order-0 glyphs c0 = 1, 2, 4: exact radius " + ", ".join(f"{r:.3f}" for r in exact)
          + "; Sightline " + ", ".join(f"{r:.3f}" for r in ours)
          + "; FURY (boxes 2.4 wide) " + ", ".join(f"{r:.3f}" for r in theirs))

    today = datetime.date.today().isoformat()
    rows, pictures = [], None
    n = args.glyphs
    for order in args.orders:
        coefficients = odf_field(n, order)
        camera = renderer.GetActiveCamera()
        centre = (n - 1) / 2.0
        camera.SetFocalPoint(centre, centre, 0.0)
        camera.SetPosition(centre + 0.35 * n, centre - 0.9 * n, 1.1 * n)
        camera.SetViewUp(0, 0, 1)
        camera.SetViewAngle(30)
        near, far = 0.3 * n, 3.0 * n
        camera.SetClippingRange(near, far)
        results = {}
        for name, make in (("Sightline", sightline_actor), ("FURY", fury_actor)):
            camera.SetPosition(centre + 0.35 * n, centre - 0.9 * n, 1.1 * n)
            camera.SetViewUp(0, 0, 1)
            results[name] = draw(window, renderer, make(coefficients, n), args.frames, args.size)
            camera.SetClippingRange(near, far)
        (s_time, s_first, s_z, s_rgb), (f_time, f_first, f_z, f_rgb) = (results["Sightline"],
                                                                          results["FURY"])
        s_hit, f_hit = s_z < 1.0, f_z < 1.0
        only = s_hit ^ f_hit
        both = s_hit & f_hit
        depth = np.abs(eye_distance(f_z[both], near, far) - eye_distance(s_z[both], near, far))
        row = {
            "date": today, "machine": platform.node(), "renderer": renderer_line.split(":")[-1].strip(),
            "order": order, "glyphs": n * n, "pixels": f"{args.size}x{args.size}",
            "sightline_frame_s": round(s_time, 4), "fury_frame_s": round(f_time, 4),
            "fury_over_sightline": round(f_time / s_time, 2),
            "sightline_first_s": round(s_first, 3), "fury_first_s": round(f_first, 3),
            "sightline_pixels": int(s_hit.sum()), "pixels_only_one_draws": int(only.sum()),
            "pixels_off_percent": round(100.0 * only.sum() / max(1, s_hit.sum()), 2),
            "fury_only": int((f_hit & ~s_hit).sum()), "sightline_only": int((s_hit & ~f_hit).sum()),
            "depth_median": float(f"{np.median(depth):.4g}"),
            "depth_p99": float(f"{np.percentile(depth, 99):.4g}"),
            "depth_max": float(f"{depth.max():.4g}"),
            "depth_median_over_radius": float(f"{np.median(depth) / MAX_RADIUS:.3g}"),
            "order0_exact_radii": " ".join(f"{r:.3f}" for r in exact),
            "order0_sightline_radii": " ".join(f"{r:.3f}" for r in ours),
            "order0_fury_radii": " ".join(f"{r:.3f}" for r in theirs),
        }
        rows.append(row)
        print(", ".join(f"{k} {v}" for k, v in row.items() if k not in ("date", "machine")))
        if order == 8 or pictures is None:
            difference = np.zeros_like(s_rgb)
            difference[(f_hit & ~s_hit)[::-1]] = (255, 80, 80)   # FURY only: red
            difference[(s_hit & ~f_hit)[::-1]] = (80, 160, 255)  # Sightline only: blue
            pictures = np.concatenate([s_rgb, f_rgb, difference], axis=1)

    path = os.path.join(args.output, f"results-fury-odf-{today}.csv")
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {path}")
    image = vtk.vtkImageData()
    height, width = pictures.shape[:2]
    image.SetDimensions(width, height, 1)
    colours = numpy_to_vtk(pictures[::-1].reshape(-1, 3), deep=True)
    image.GetPointData().SetScalars(colours)
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(os.path.join(args.output, f"fury-odf-{today}.png"))
    writer.SetInputData(image)
    writer.Write()
    print(f"wrote {writer.GetFileName()} (Sightline | FURY | red: FURY only, blue: Sightline only)")


if __name__ == "__main__":
    main()
