#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Emission-absorption images of a spherical grid through VTK's own volume mappers against
Sightline's, each against the exact image (issue 6's benchmark, parts (a)-(c)).

Scene: the thesis' step function chi_0.5 (2 for r <= 1/2, 1 out to r = 1) sampled on spherical
grids with N = 8..256 per axis, as cell data; transfer function: value 1 blue with opacity 0.3,
value 2 orange with opacity 0.8, per unit distance 0.5; parallel projection along an oblique
direction (the exact image of this radial field is the same from every direction; along a
coordinate axis the unstructured mapper loses the rays that run inside tetrahedron faces),
black background, W x W pixels over [-1.05, 1.05]^2. Two grids per N: the thesis' (N breakpoints: the step falls inside
a cell) and an aligned one (N cells: the step is a breakpoint, so the cells hold the field).

Methods:
  sightline            vtkSightlineSphericalVolumeMapper on the vtkRectilinearGrid (r, theta, phi);
  fixed-point          the grid as a vtkStructuredGrid of Cartesian points, vtkResampleToImage to
                       N^3 points over [-1, 1]^3, vtkFixedPointVolumeRayCastMapper with sample
                       distance = voxel size (resampling reported apart, not charged);
  unstructured         vtkDataSetTriangleFilter of that structured grid (tetrahedra, cell data),
                       made conforming (the points that coincide at the origin, the poles and
                       the phi seam merged, collapsed tetrahedra dropped: without that, rays
                       leak through degenerate faces), vtkUnstructuredGridVolumeRayCastMapper,
                       where it fits (--max-tets); its
                       homogeneous integrator reads opacity as attenuation per unit distance,
                       so it gets -ln(1 - a) for opacity a (the same optical depth).
Exact image: sphere chords composited front to back in numpy (shell, core, shell), independent
of every mapper. Error: RMS and max over pixels and channels (0-255) of image - exact.
Frame time: median of --runs renders, the camera rolled by 1e-4 degrees between renders so no
mapper reuses a cached frame.

Usage: xvfb-run -a /usr/bin/python3 vtk_volume_mappers.py [--sizes 8 16 32 64 128 256]
         [--width 256] [--runs 3] [--max-tets 2000000] [--max-voxels 2100000] [--csv F] [--plot F]
"""
import argparse
import csv
import math
import os
import platform
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


def spherical_grid(n, aligned):
    breakpoints = n + 1 if aligned else n
    s = np.linspace(0.0, 1.0, breakpoints)
    r, theta, phi = s, s * math.pi, s * 2.0 * math.pi
    grid = vtk.vtkRectilinearGrid()
    grid.SetDimensions(len(r), len(theta), len(phi))
    grid.SetXCoordinates(numpy_to_vtk(r, deep=True))
    grid.SetYCoordinates(numpy_to_vtk(theta, deep=True))
    grid.SetZCoordinates(numpy_to_vtk(phi, deep=True))
    rm = 0.5 * (r[1:] + r[:-1])
    cell_r = np.tile(rm, (len(theta) - 1) * (len(phi) - 1))  # r fastest
    values = np.where(cell_r <= 0.5, 2.0, 1.0)
    array = numpy_to_vtk(values, deep=True)
    array.SetName("chi")
    grid.GetCellData().SetScalars(array)
    return grid, (r, theta, phi)


def structured_cartesian(grid, coordinates):
    """The same cells with Cartesian points (for VTK's mappers)."""
    r, theta, phi = coordinates
    P, T, R = np.meshgrid(phi, theta, r, indexing="ij")  # r fastest in memory
    points = np.stack([R * np.sin(T) * np.cos(P), R * np.sin(T) * np.sin(P), R * np.cos(T)],
                      axis=-1).reshape(-1, 3)
    structured = vtk.vtkStructuredGrid()
    structured.SetDimensions(len(r), len(theta), len(phi))
    vtk_points = vtk.vtkPoints()
    vtk_points.SetData(numpy_to_vtk(points, deep=True))
    structured.SetPoints(vtk_points)
    structured.GetCellData().SetScalars(grid.GetCellData().GetScalars())
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
    """`attenuation`: for vtkUnstructuredGridVolumeRayCastMapper, whose homogeneous integrator
    reads the scalar opacity as an attenuation coefficient (alpha = 1 - exp(-opacity / unit x
    length)): -ln(1 - a) there models the same optical depth as opacity a elsewhere."""
    color = vtk.vtkColorTransferFunction()
    opacity = vtk.vtkPiecewiseFunction()
    # Piecewise constant around the two values; 0 below 0.5 (outside the ball after resampling).
    color.AddRGBPoint(0.0, *COLORS[1.0])
    opacity.AddPoint(0.0, 0.0)
    opacity.AddPoint(0.5, 0.0)
    for v0, v1, value in ((0.5001, 1.4999, 1.0), (1.5, 2.5, 2.0)):
        color.AddRGBPoint(v0, *COLORS[value])
        color.AddRGBPoint(v1, *COLORS[value])
        a = -math.log(1.0 - OPACITY[value]) if attenuation else OPACITY[value]
        opacity.AddPoint(v0, a)
        opacity.AddPoint(v1, a)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(UNIT)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    return prop


def exact_image(width):
    """Front to back through shell, core, shell: sphere chords, in numpy."""
    centres = (np.arange(width) + 0.5) / width * 2.0 * SCALE - SCALE
    b2 = centres[None, :] ** 2 + centres[:, None] ** 2
    outer = np.sqrt(np.maximum(1.0 - b2, 0.0))
    inner = np.sqrt(np.maximum(0.25 - b2, 0.0))
    tau = {v: -math.log(1.0 - a) / UNIT for v, a in OPACITY.items()}
    color = np.zeros((width, width, 3))
    transmittance = np.ones((width, width))
    for value, length in ((1.0, outer - inner), (2.0, 2.0 * inner), (1.0, outer - inner)):
        alpha = 1.0 - np.exp(-tau[value] * length)
        color += (transmittance * alpha)[..., None] * np.array(COLORS[value])
        transmittance *= 1.0 - alpha
    return 255.0 * color


def make_window(width):
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0, 0, 0)
    camera = renderer.GetActiveCamera()
    camera.ParallelProjectionOn()
    camera.SetParallelScale(SCALE)
    # An oblique view: the exact image of a radial field does not depend on the direction, and
    # rays along a coordinate axis run inside the tetrahedra's faces (the half-planes through
    # the polar axis), where vtkUnstructuredGridVolumeRayCastMapper loses them (dark cracks).
    direction = np.array([1.3, 0.9, 4.7])
    camera.SetPosition(*(5.0 * direction / np.linalg.norm(direction)))
    camera.SetFocalPoint(0, 0, 0)
    camera.SetViewUp(0, 1, 0)
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
    window, renderer = make_window(width)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(volume_property(attenuation))
    renderer.AddVolume(volume)
    window.Render()  # first frame: builds and uploads, not timed
    image = capture(window)
    times = []
    for _ in range(runs):
        renderer.GetActiveCamera().Roll(1e-4)
        start = time.perf_counter()
        window.Render()
        times.append(time.perf_counter() - start)
    return image, statistics.median(times)


def errors(image, exact):
    difference = image - exact
    return float(np.sqrt(np.mean(difference ** 2))), float(np.abs(difference).max())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[8, 16, 32, 64, 128, 256])
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--max-tets", type=int, default=2_000_000)
    parser.add_argument("--max-voxels", type=int, default=2_100_000)
    parser.add_argument("--csv", default="results-spherical-vtk-mappers.csv")
    parser.add_argument("--plot")
    parser.add_argument("--check", action="store_true",
                        help="smoke test: fail unless Sightline's aligned images are exact to 8-bit "
                        "rounding and VTK's mappers are less accurate")
    args = parser.parse_args()
    exact = exact_image(args.width)
    with open("/proc/loadavg") as stream:
        load = stream.read().split()[0]
    cpu = platform.processor() or "unknown"
    with open("/proc/cpuinfo") as stream:
        for line in stream:
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    rows = []
    for aligned in (False, True):
        for n in args.sizes:
            grid, coordinates = spherical_grid(n, aligned)
            label = "aligned" if aligned else "thesis"

            def record(method, image, frame, prepare=float("nan"), size=0, notes=""):
                rms, worst = errors(image, exact) if image is not None else (float("nan"),) * 2
                rows.append(dict(grid=label, method=method, N=n, cells=grid.GetNumberOfCells(),
                                 cartesian_elements=size, prepare_seconds=prepare,
                                 frame_seconds_median=frame, rms_error=rms, max_error=worst,
                                 notes=notes, cpu=cpu, cores=os.cpu_count(), load=load,
                                 width=args.width))
                print(f"{label:8s} N={n:4d} {method:13s} frame {frame:8.4f} s  RMS {rms:8.3f}  "
                      f"max {worst:6.1f}  {notes}", flush=True)

            mapper = sightline.vtkSightlineSphericalVolumeMapper()
            mapper.SetInputData(grid)
            image, frame = measure(mapper, args.width, args.runs)
            record("sightline", image, frame)

            structured = None
            voxels = n ** 3
            if voxels <= args.max_voxels:
                structured = structured_cartesian(grid, coordinates)
                start = time.perf_counter()
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
                fixed.SetSampleDistance(2.0 / n)
                fixed.SetImageSampleDistance(1.0)
                image, frame = measure(fixed, args.width, args.runs)
                record("fixed-point", image, frame, prepared, voxels,
                       f"vtkResampleToImage to {n}^3 points in {prepared:.2f} s")
            else:
                record("fixed-point", None, float("nan"), size=voxels, notes="skipped: --max-voxels")

            tets_estimate = 6 * grid.GetNumberOfCells()
            if tets_estimate <= args.max_tets:
                if structured is None:
                    structured = structured_cartesian(grid, coordinates)
                start = time.perf_counter()
                mesh, raw = tetrahedra(structured)
                prepared = time.perf_counter() - start
                unstructured = vtk.vtkUnstructuredGridVolumeRayCastMapper()
                unstructured.SetInputData(mesh)
                unstructured.AutoAdjustSampleDistancesOff()
                unstructured.SetImageSampleDistance(1.0)
                image, frame = measure(unstructured, args.width, args.runs, attenuation=True)
                record("unstructured", image, frame, prepared, mesh.GetNumberOfCells(),
                       f"{mesh.GetNumberOfCells()} tetrahedra (of {raw}: coincident points merged, "
                       f"collapsed ones dropped) in {prepared:.2f} s")
            else:
                record("unstructured", None, float("nan"), size=tets_estimate,
                       notes="skipped: --max-tets")
    with open(args.csv, "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print("wrote", args.csv)
    if args.plot:
        plot(rows, args.plot)
    if args.check:
        aligned = {(r["method"], r["N"]): r["rms_error"] for r in rows if r["grid"] == "aligned"}
        for n in args.sizes:
            ours = aligned[("sightline", n)]
            if not ours < 1.0:
                raise SystemExit(f"N = {n}: Sightline's aligned image is off by RMS {ours}")
            for method in ("fixed-point", "unstructured"):
                theirs = aligned.get((method, n), float("nan"))
                if not math.isnan(theirs) and not theirs > ours:
                    raise SystemExit(f"N = {n}: {method} ({theirs}) is not less accurate than Sightline")
        print("check: OK")


def plot(rows, output):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(1, 2, figsize=(13, 5.2))
    colors = {"sightline": "tab:blue", "fixed-point": "tab:orange", "unstructured": "tab:green"}
    for axis, label in zip(axes, ("thesis", "aligned")):
        for method, color in colors.items():
            points = [(r["frame_seconds_median"], max(r["rms_error"], 1e-2), r["N"]) for r in rows
                      if r["grid"] == label and r["method"] == method and not math.isnan(r["rms_error"])]
            if not points:
                continue
            axis.plot([p[0] for p in points], [p[1] for p in points], "o-", color=color, label=method)
            for t, e, n in points:
                axis.annotate(str(n), (t, e), fontsize=7, xytext=(3, 3), textcoords="offset points")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("frame time [s] (median, in a VTK window)")
        axis.set_ylabel("RMS error against the exact image (0-255; labels: N)")
        title = ("step inside a cell (thesis grids)" if label == "thesis"
                 else "step on a breakpoint (the cells hold the field)")
        axis.set_title(f"chi_0.5, emission-absorption: {title}", fontsize=9)
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=8)
    first = rows[0]
    figure.suptitle(f"VTK volume mappers against Sightline's, {first['width']}^2 pixels; "
                    f"{first['cpu']}, {first['cores']} cores, load {first['load']}", fontsize=9)
    figure.tight_layout()
    figure.savefig(output, dpi=100)
    print("plot:", output)


if __name__ == "__main__":
    main()
