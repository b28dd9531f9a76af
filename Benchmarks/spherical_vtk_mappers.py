#!/usr/bin/python3
"""The thesis' Figures 6.11-6.14 with VTK's own volume mappers: error against frame time.

Emission-absorption images of the thesis' step field chi_0.5 (2 for r <= 1/2, 1 for
1/2 < r <= 1) on spherical grids, looking down the x axis as the thesis does (rays parallel to
a Cartesian axis, the best case for a Cartesian volume), each image against the exact one.

Grids. `N` is the number of breakpoints per axis, as in the thesis: N - 1 uniform cells in
r (0..1), theta (0..pi) and phi (0..2 pi), so for even N the step r = 1/2 falls in the middle
of a cell (vtkSightlineSphericalFieldSource, AlignWithDiscontinuities off; each cell holds the
field at its coordinate midpoint, so the straddling cell is 2). The aligned variant
(`sightline-aligned`: N cells, r = 1/2 a breakpoint) is the case where the grid holds the
field; only our mapper is run on it.

Methods (all in an offscreen vtkRenderWindow, no multisampling, 2 CPU threads each):
  sightline          vtkSightlineSphericalVolumeMapper on the vtkRectilinearGrid (r, theta, phi),
                     cell data, composited exactly per cell;
  sightline-aligned  the same on the aligned grid;
  fixed-point        the grid's cells with Cartesian points (vtkStructuredGrid), vtkResampleToImage
                     to N^3 points over [-1, 1]^3 (each point takes the value of the cell it lies
                     in; outside the ball 0, transparent), vtkFixedPointVolumeRayCastMapper with
                     AutoAdjustSampleDistances off, SampleDistance = the voxel spacing 2/(N - 1),
                     ImageSampleDistance 1, trilinear interpolation. The resampling is reported in
                     prepare_seconds and not charged to the frame (as in the thesis);
  unstructured       vtkDataSetTriangleFilter of that structured grid (tetrahedra, cell data),
                     coincident points merged (origin, poles, phi seam) and collapsed tetrahedra
                     dropped so the mesh is conforming, vtkUnstructuredGridVolumeRayCastMapper (Bunyk ray cast function, its
                     homogeneous integrator for cell data), where it fits (--max-tets) and a frame
                     is predicted under --max-frame-seconds.

Optical model, the same for all: opacity a per ScalarOpacityUnitDistance u is the extinction
tau = -ln(1 - a) / u. Our mapper does exactly that; vtkFixedPointVolumeRayCastMapper corrects
the opacity per sample of length d to 1 - (1 - a)^(d / u) (the same tau); VTK's
vtkUnstructuredGridHomogeneousRayIntegrator instead reads the opacity table as an attenuation
coefficient (alpha = 1 - exp(-L * opacity / u), see its Integrate()), so it is given -ln(1 - a)
in place of a. Transfer function: value 1 blue (0.2, 0.4, 1.0) with opacity 0.3, value 2
orange (1.0, 0.6, 0.1) with opacity 0.8, u = 0.5 (a central ray leaves 49 % of the light
through the shell, so the inner ball shows), piecewise constant around 1 and 2 (points at
0.5, 1.5 -/+ 1e-4, 2.5) so interpolation does not blur the values; 0 (outside) transparent.

Exact image: for a ray at distance b from the centre the chords of the unit sphere and of the
r = 1/2 sphere give the lengths in the shell (before and after the ball) and in the ball;
composited front to back in numpy (C = c1 (1 - e1) + e1 c2 (1 - e2) + e1 e2 c1 (1 - e1),
e_i = exp(-tau_i L_i)), over black, 0..255, at the pixel centres of a W x W image covering
[-1.05, 1.05]^2 (parallel projection, parallel scale 1.05). Error: RMS over pixels and the
three channels of image - exact, and the largest absolute difference.

Time: the first render (building, uploading) is not timed; then the median of --runs renders,
each measured with time.perf_counter() around window.Render(), with the camera rolled by
1e-4 degrees about the view axis before each render. That changes the camera, so no mapper
can reuse its last frame (our mapper keys its cached frame on the view); for our mapper the
median of GetLastFrameSeconds() (its ray casting alone) is recorded too.

Usage: xvfb-run -a /usr/bin/python3 spherical_vtk_mappers.py [--sizes 8 16 32 64 128 256]
         [--width 256] [--runs 3] [--max-tets N] [--max-voxels N] [--max-frame-seconds S]
         [--csv FILE] [--plot FILE] [--images DIR]
"""
import argparse
import csv
import math
import os
import statistics
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline

COLORS = {1.0: (0.2, 0.4, 1.0), 2.0: (1.0, 0.6, 0.1)}
OPACITY = {1.0: 0.3, 2.0: 0.8}
UNIT = 0.5
SCALE = 1.05
ROLL_DEGREES = 1e-4


def spherical_grid(cells, aligned):
    source = sightline.vtkSightlineSphericalFieldSource()
    source.SetFieldToStep()
    source.SetRadialResolution(cells)
    source.SetPolarResolution(cells)
    source.SetAzimuthalResolution(cells)
    source.SetRadiusRange(0.0, 1.0)
    source.SetPolarRange(0.0, math.pi)
    source.SetAzimuthRange(0.0, 2.0 * math.pi)
    source.SetAlignWithDiscontinuities(aligned)
    source.Update()
    grid = source.GetOutput()
    grid.GetCellData().SetActiveScalars("chi")
    return grid


def structured_cartesian(grid):
    """The same cells (and cell data) with Cartesian points, for VTK's mappers."""
    r = vtk_to_numpy(grid.GetXCoordinates())
    theta = vtk_to_numpy(grid.GetYCoordinates())
    phi = vtk_to_numpy(grid.GetZCoordinates())
    P, T, R = np.meshgrid(phi, theta, r, indexing="ij")  # r fastest, as VTK's point order
    points = np.stack([R * np.sin(T) * np.cos(P), R * np.sin(T) * np.sin(P), R * np.cos(T)],
                      axis=-1).reshape(-1, 3)
    del P, T, R
    structured = vtk.vtkStructuredGrid()
    structured.SetDimensions(len(r), len(theta), len(phi))
    vtk_points = vtk.vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    structured.SetPoints(vtk_points)
    structured.GetCellData().SetScalars(grid.GetCellData().GetArray("chi"))
    return structured


def tetrahedra(structured):
    """vtkDataSetTriangleFilter's tetrahedra (5 per hexahedron) with the grid's coincident
    points merged (the origin, the poles at each radius, the phi = 0 / 2 pi seam) and the
    tetrahedra that collapse there (a repeated point, or no volume) removed: a conforming mesh
    whose only boundary is the sphere r = 1, as VTK's unstructured ray caster needs (without the
    merge, rays along the polar axis and across the seam leave or re-enter the mesh through
    degenerate faces and show cracks)."""
    nr, nt, nphi = structured.GetDimensions()
    tetra = vtk.vtkDataSetTriangleFilter()
    tetra.SetInputData(structured)
    tetra.Update()
    raw = tetra.GetOutput()
    if raw.GetNumberOfPoints() != structured.GetNumberOfPoints():
        raise RuntimeError("vtkDataSetTriangleFilter renumbered the points")
    ids = vtk_to_numpy(raw.GetCells().GetConnectivityArray()).reshape(-1, 4).astype(np.int64)
    chi = vtk_to_numpy(raw.GetCellData().GetArray("chi"))
    i = ids % nr
    j = (ids // nr) % nt
    k = (ids // (nr * nt)) % (nphi - 1)  # phi = 2 pi is phi = 0
    pole = (j == 0) | (j == nt - 1)
    k = np.where(pole, 0, k)
    j = np.where(i == 0, 0, j)
    k = np.where(i == 0, 0, k)
    merged = i + nr * (j + nt * k)
    points = vtk_to_numpy(structured.GetPoints().GetData())
    s = np.sort(merged, axis=1)
    distinct = np.all(s[:, 1:] != s[:, :-1], axis=1)
    p = points[merged]
    volume = np.einsum("ij,ij->i", p[:, 1] - p[:, 0],
                       np.cross(p[:, 2] - p[:, 0], p[:, 3] - p[:, 0])) / 6.0
    keep = distinct & (np.abs(volume) > 1e-15)
    merged = merged[keep]
    cells = vtk.vtkCellArray()
    offsets = np.arange(0, 4 * len(merged) + 1, 4, dtype=np.int64)
    cells.SetData(numpy_to_vtk(offsets, deep=True, array_type=vtk.VTK_ID_TYPE),
                  numpy_to_vtk(merged.reshape(-1), deep=True, array_type=vtk.VTK_ID_TYPE))
    mesh = vtk.vtkUnstructuredGrid()
    mesh.SetPoints(structured.GetPoints())
    mesh.SetCells(vtk.VTK_TETRA, cells)
    array = numpy_to_vtk(np.ascontiguousarray(chi[keep]), deep=True)
    array.SetName("chi")
    mesh.GetCellData().SetScalars(array)
    return mesh, len(ids)


def volume_property(attenuation=False):
    """`attenuation`: the table holds -ln(1 - a) (vtkUnstructuredGridHomogeneousRayIntegrator
    reads the opacity as an attenuation coefficient per unit distance)."""
    color = vtk.vtkColorTransferFunction()
    opacity = vtk.vtkPiecewiseFunction()
    color.AddRGBPoint(0.0, *COLORS[1.0])
    opacity.AddPoint(0.0, 0.0)
    opacity.AddPoint(0.5, 0.0)
    eps = 1e-4
    for v0, v1, value in ((0.5 + eps, 1.5 - eps, 1.0), (1.5 + eps, 2.5, 2.0)):
        a = -math.log(1.0 - OPACITY[value]) if attenuation else OPACITY[value]
        for v in (v0, v1):
            color.AddRGBPoint(v, *COLORS[value])
            opacity.AddPoint(v, a)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(UNIT)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


def exact_image(width):
    """Front to back through shell, ball, shell, from sphere chords."""
    centres = (np.arange(width) + 0.5) / width * 2.0 * SCALE - SCALE
    b2 = centres[None, :] ** 2 + centres[:, None] ** 2
    outer = 2.0 * np.sqrt(np.maximum(1.0 - b2, 0.0))   # chord of the unit sphere
    inner = 2.0 * np.sqrt(np.maximum(0.25 - b2, 0.0))  # chord of the r = 1/2 sphere
    tau = {v: -math.log(1.0 - a) / UNIT for v, a in OPACITY.items()}
    e1 = np.exp(-tau[1.0] * 0.5 * (outer - inner))  # one shell crossing
    e2 = np.exp(-tau[2.0] * inner)
    c1, c2 = np.array(COLORS[1.0]), np.array(COLORS[2.0])
    color = ((1 - e1)[..., None] * c1 + (e1 * (1 - e2))[..., None] * c2
             + (e1 * e2 * (1 - e1))[..., None] * c1)
    return 255.0 * color


def make_window(width):
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0, 0, 0)
    camera = renderer.GetActiveCamera()
    camera.ParallelProjectionOn()
    camera.SetParallelScale(SCALE)
    camera.SetPosition(5, 0, 0)  # rays along -x, as the thesis aligns them with the x axis
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 0, 1)
    camera.SetClippingRange(1, 9)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.SetSize(width, width)
    window.AddRenderer(renderer)
    return window, renderer


def capture(window):
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.ShouldRerenderOff()
    grab.Update()
    image = grab.GetOutput()
    w, h, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, 3).astype(float)


def measure(mapper, width, runs, attenuation=False):
    """(image, median frame seconds, first frame seconds, median GetLastFrameSeconds or nan)."""
    window, renderer = make_window(width)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(volume_property(attenuation))
    renderer.AddVolume(volume)
    start = time.perf_counter()
    window.Render()  # builds and uploads: not timed
    first = time.perf_counter() - start
    image = capture(window)
    times, own = [], []
    for _ in range(runs):
        renderer.GetActiveCamera().Roll(ROLL_DEGREES)
        start = time.perf_counter()
        window.Render()
        times.append(time.perf_counter() - start)
        if hasattr(mapper, "GetLastFrameSeconds"):
            own.append(mapper.GetLastFrameSeconds())
    window.Finalize()
    return image, statistics.median(times), first, (statistics.median(own) if own else math.nan)


def errors(image, exact):
    difference = image - exact
    return float(np.sqrt(np.mean(difference ** 2))), float(np.abs(difference).max())


def machine():
    cpu = "unknown"
    with open("/proc/cpuinfo") as stream:
        for line in stream:
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    return cpu, os.cpu_count()


def load():
    with open("/proc/loadavg") as stream:
        return stream.read().split()[0]


def save_png(image, path):
    h, w, _ = image.shape
    data = vtk.vtkImageData()
    data.SetDimensions(w, h, 1)
    array = numpy_to_vtk(np.clip(np.rint(image), 0, 255).astype(np.uint8).reshape(-1, 3), deep=True)
    data.GetPointData().SetScalars(array)
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(data)
    writer.Write()


def interpolate_loglog(x, xs, ys):
    """y at x on the log-log polyline (xs ascending); None outside its range."""
    if len(xs) < 2 or not xs[0] <= x <= xs[-1]:
        return None
    for (x0, y0), (x1, y1) in zip(zip(xs, ys), zip(xs[1:], ys[1:])):
        if x0 <= x <= x1:
            if x1 == x0:
                return y0
            t = (math.log(x) - math.log(x0)) / (math.log(x1) - math.log(x0))
            return math.exp(math.log(y0) + t * (math.log(y1) - math.log(y0)))
    return None


def comparisons(rows):
    """Target checks: our error against fixed-point's at our frame time, and fixed-point's and
    the unstructured mapper's frame time at our error (log-log interpolation along N)."""
    def series(method, key_x, key_y):
        points = sorted((r[key_x], r[key_y]) for r in rows
                        if r["method"] == method and not math.isnan(r[key_y]))
        return [p[0] for p in points], [p[1] for p in points]

    lines = []
    for ours in ("sightline", "sightline-aligned"):
        for r in (r for r in rows if r["method"] == ours and not math.isnan(r["rms_error"])):
            t, e = r["frame_seconds_median"], r["rms_error"]
            parts = [f"{ours:17s} N={r['N']:3d} ({t:.3f} s, RMS {e:.2f}):"]
            times, errs = series("fixed-point", "frame_seconds_median", "rms_error")
            # error is not monotonic in time for noisy timings; sort by time as measured
            fp_error = interpolate_loglog(t, times, errs)
            parts.append("fixed-point at equal time: " + (
                f"RMS {fp_error:.2f} ({fp_error / e:.1f}x ours)" if fp_error else "out of range"))
            for method in ("fixed-point", "unstructured"):
                errs_desc, times_at = series(method, "rms_error", "frame_seconds_median")
                their_time = interpolate_loglog(e, errs_desc, times_at)
                parts.append(f"{method} at equal error: " + (
                    f"{their_time:.3f} s ({their_time / t:.1f}x ours)" if their_time
                    else "never reached in the measured range"))
            lines.append("  ".join(parts))
    return lines


def plot(rows, output, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    styles = {"sightline": ("tab:blue", "o-"), "sightline-aligned": ("tab:cyan", "s--"),
              "fixed-point": ("tab:orange", "^-"), "unstructured": ("tab:green", "v-")}
    labels = {"sightline": "Sightline spherical mapper (step inside a cell)",
              "sightline-aligned": "Sightline spherical mapper, aligned grid (step on a breakpoint)",
              "fixed-point": "vtkResampleToImage N^3 + vtkFixedPointVolumeRayCastMapper",
              "unstructured": "tetrahedra + vtkUnstructuredGridVolumeRayCastMapper"}
    figure, (left, right) = plt.subplots(1, 2, figsize=(14, 7), gridspec_kw={"width_ratios": [3, 2]})
    for method, (color, style) in styles.items():
        points = [(r["frame_seconds_median"], r["rms_error"], r["N"]) for r in rows
                  if r["method"] == method and not math.isnan(r["rms_error"])]
        if not points:
            continue
        left.plot([p[0] for p in points], [p[1] for p in points], style, color=color,
                  label=labels[method], markersize=6)
        for t, e, n in points:
            left.annotate(f"N={n}", (t, e), fontsize=8, color=color, textcoords="offset points",
                          xytext=(-8, -13) if method == "sightline-aligned" else (4, 4))
        right.plot([p[2] for p in points], [p[0] for p in points], style, color=color,
                   label=method, markersize=6)
    left.set_xscale("log")
    left.set_yscale("log")
    left.set_xlabel("frame time [s] (median of the renders, offscreen VTK window)")
    left.set_ylabel("RMS error against the exact image [0-255 levels]")
    left.set_title("error against frame time (cf. thesis Figs. 6.13-6.14)", fontsize=10)
    left.grid(True, which="both", alpha=0.3)
    left.set_ylim(bottom=0.12)
    left.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    right.set_xscale("log", base=2)
    right.set_yscale("log")
    right.set_xlabel("N (breakpoints per axis)")
    right.set_ylabel("frame time [s]")
    right.set_title("frame time against resolution (cf. thesis Fig. 6.11)", fontsize=10)
    right.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=8, loc="upper left")
    figure.suptitle(title, fontsize=10)
    figure.tight_layout()
    figure.savefig(output, dpi=100)
    print("plot:", output)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[8, 16, 32, 64, 128, 256])
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--max-tets", type=int, default=13_000_000,
                        help="skip the unstructured mapper above this many tetrahedra (memory)")
    parser.add_argument("--max-voxels", type=int, default=17_000_000,
                        help="skip the Cartesian resampling above this many voxels")
    parser.add_argument("--max-frame-seconds", type=float, default=60.0,
                        help="skip a method whose frame, extrapolated from the last N, exceeds this")
    parser.add_argument("--methods", nargs="+",
                        default=["sightline", "sightline-aligned", "fixed-point", "unstructured"])
    parser.add_argument("--csv", default="results-spherical-vtk-mappers.csv")
    parser.add_argument("--plot")
    parser.add_argument("--images", help="write each image and the exact one here (PNG)")
    args = parser.parse_args()

    exact = exact_image(args.width)
    if args.images:
        os.makedirs(args.images, exist_ok=True)
        save_png(exact[::-1], os.path.join(args.images, "exact.png"))
    cpu, cores = machine()
    load_start = load()
    print(f"machine: {cpu}, {cores} cores, load {load_start}; {args.width}x{args.width} pixels, "
          f"{args.runs} timed renders per method", flush=True)
    rows = []
    last = {}  # method -> (elements, frame seconds) for extrapolating the next N

    def record(method, n, cells, elements, prepare, frame, image, notes, first=math.nan, own=math.nan):
        rms, worst = errors(image, exact) if image is not None else (math.nan, math.nan)
        if image is not None and args.images:
            save_png(image[::-1], os.path.join(args.images, f"{method}-{n}.png"))
            save_png(np.clip(4.0 * np.abs(image - exact), 0, 255)[::-1],
                     os.path.join(args.images, f"{method}-{n}-diff4x.png"))
        rows.append({"method": method, "N": n, "cells": cells, "cartesian_voxels/tets": elements,
                     "prepare_seconds": prepare, "frame_seconds_median": frame,
                     "rms_error": rms, "max_error": worst, "first_frame_seconds": first,
                     "mapper_last_frame_seconds_median": own, "notes": notes,
                     "cpu": cpu, "cores": cores, "load": load(), "width": args.width,
                     "runs": args.runs})
        print(f"N={n:4d} {method:18s} frame {frame:8.4f} s  RMS {rms:7.3f}  max {worst:6.1f}  "
              f"{notes}", flush=True)

    def too_slow(method, elements):
        if method not in last:
            return None
        prev_elements, prev_frame = last[method]
        predicted = prev_frame * elements / prev_elements
        return predicted if predicted > args.max_frame_seconds else None

    for n in args.sizes:
        cells_per_axis = n - 1
        grid = spherical_grid(cells_per_axis, aligned=False)
        cells = grid.GetNumberOfCells()

        if "sightline" in args.methods:
            mapper = sightline.vtkSightlineSphericalVolumeMapper()
            mapper.SetInputData(grid)
            image, frame, first, own = measure(mapper, args.width, args.runs)
            record("sightline", n, cells, 0, math.nan, frame, image,
                   f"{cells_per_axis}^3 cells, step inside a cell; own ray casting {own:.4f} s",
                   first, own)
            del mapper

        if "sightline-aligned" in args.methods:
            aligned = spherical_grid(n, aligned=True)
            mapper = sightline.vtkSightlineSphericalVolumeMapper()
            mapper.SetInputData(aligned)
            image, frame, first, own = measure(mapper, args.width, args.runs)
            record("sightline-aligned", n, aligned.GetNumberOfCells(), 0, math.nan, frame, image,
                   f"{n}^3 cells, r = 1/2 a breakpoint; own ray casting {own:.4f} s", first, own)
            del mapper, aligned

        structured = None
        if "fixed-point" in args.methods:
            voxels = n ** 3
            slow = too_slow("fixed-point", voxels)
            if voxels > args.max_voxels or slow:
                record("fixed-point", n, cells, voxels, math.nan, math.nan, None,
                       f"skipped: {voxels} voxels > --max-voxels" if not slow else
                       f"skipped: predicted frame {slow:.0f} s > {args.max_frame_seconds:.0f} s")
            else:
                start = time.perf_counter()
                structured = structured_cartesian(grid)
                resample = vtk.vtkResampleToImage()
                resample.SetInputDataObject(structured)
                resample.SetUseInputBounds(False)
                resample.SetSamplingBounds(-1, 1, -1, 1, -1, 1)
                resample.SetSamplingDimensions(n, n, n)
                resample.Update()
                prepared = time.perf_counter() - start
                image_data = resample.GetOutput()
                image_data.GetPointData().SetActiveScalars("chi")
                fixed = vtk.vtkFixedPointVolumeRayCastMapper()
                fixed.SetInputData(image_data)
                fixed.AutoAdjustSampleDistancesOff()
                fixed.SetSampleDistance(2.0 / (n - 1))
                fixed.SetImageSampleDistance(1.0)
                image, frame, first, _ = measure(fixed, args.width, args.runs)
                record("fixed-point", n, cells, voxels, prepared, frame, image,
                       f"{n}^3 points, sample distance {2.0 / (n - 1):.4g}; structured grid + "
                       f"vtkResampleToImage {prepared:.2f} s (not in the frame); first frame "
                       f"{first:.2f} s", first)
                last["fixed-point"] = (voxels, frame)
                del fixed, resample, image_data

        if "unstructured" in args.methods:
            tets = 5 * cells  # vtkDataSetTriangleFilter: 5 per hexahedron on structured input
            slow = too_slow("unstructured", tets)
            if tets > args.max_tets or slow:
                reasons = []
                if tets > args.max_tets:
                    reasons.append(f"about {tets} tetrahedra > --max-tets {args.max_tets} (memory: "
                                   f"the process peaked at 5.5 GB with 10M tetrahedra, 23 GB here)")
                if slow:
                    reasons.append(f"predicted frame {slow:.0f} s > {args.max_frame_seconds:.0f} s")
                record("unstructured", n, cells, tets, math.nan, math.nan, None,
                       "skipped: " + "; ".join(reasons))
            else:
                start = time.perf_counter()
                if structured is None:
                    structured = structured_cartesian(grid)
                mesh, raw_tets = tetrahedra(structured)
                prepared = time.perf_counter() - start
                tets = mesh.GetNumberOfCells()
                unstructured = vtk.vtkUnstructuredGridVolumeRayCastMapper()
                unstructured.SetInputData(mesh)
                unstructured.AutoAdjustSampleDistancesOff()
                unstructured.SetImageSampleDistance(1.0)
                image, frame, first, _ = measure(unstructured, args.width, args.runs,
                                                 attenuation=True)
                # Rays in the plane y = 0 run inside the phi = 0 and phi = pi faces; the mapper
                # loses them there (a one-pixel crack down the middle). Report the error without
                # the central columns too.
                centre = range(args.width // 2 - 2, args.width // 2 + 2)
                column_max = np.abs(image - exact).max(axis=(0, 2))
                around = np.median(np.r_[column_max[args.width // 2 - 10:args.width // 2 - 2],
                                         column_max[args.width // 2 + 2:args.width // 2 + 10]])
                cracked = [c for c in centre if column_max[c] > max(100.0, 2.0 * around)]
                rest = np.delete(image - exact, cracked, axis=1)
                crack_note = (f"crack in pixel column(s) {cracked} (rays in the y = 0 faces); "
                              f"RMS without them {np.sqrt(np.mean(rest ** 2)):.3f}; ") if cracked else ""
                record("unstructured", n, cells, tets, prepared, frame, image,
                       f"{crack_note}{tets} tetrahedra ({raw_tets} from vtkDataSetTriangleFilter, coincident "
                       f"points merged, degenerate ones dropped; {prepared:.2f} s); opacity "
                       f"table -ln(1 - a); first frame {first:.2f} s", first)
                last["unstructured"] = (tets, frame)
                del unstructured, mesh
        del structured, grid

    with open(args.csv, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", args.csv)

    print(f"\n{'method':18s} {'N':>4s} {'cells':>9s} {'vox/tets':>9s} {'prep s':>7s} "
          f"{'frame s':>8s} {'RMS':>7s} {'max':>6s}")
    for r in rows:
        print(f"{r['method']:18s} {r['N']:4d} {r['cells']:9d} {r['cartesian_voxels/tets']:9d} "
              f"{r['prepare_seconds']:7.2f} {r['frame_seconds_median']:8.4f} "
              f"{r['rms_error']:7.3f} {r['max_error']:6.1f}")
    print("\nequal time / equal error (log-log interpolation between the measured N):")
    for line in comparisons(rows):
        print(" ", line)
    print(f"load: {load_start} at the start, {load()} at the end")
    if args.plot:
        plot(rows, args.plot,
             f"chi_0.5 on spherical grids, emission-absorption, {args.width}^2 pixels, rays along x; "
             f"{cpu}, {cores} cores, load {load_start}-{load()}")


if __name__ == "__main__":
    main()
