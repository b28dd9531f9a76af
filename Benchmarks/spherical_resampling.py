#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""An Earth model on its spherical grid drawn natively by Sightline, against resampling it to a
Cartesian image for VTK's CPU volume mapper (issue 38, "Against the usual way").

Model: radius 6371 km, cell data on an (r, colatitude, azimuth) grid (2 degree cells) whose
breakpoints hold every boundary: shells (cores, lower mantle with a 15 % degree-2 pattern, transition
zone, upper mantle, crust), a 'slab' (a lat/lon box 35-660 km deep) and a 'plume' (a 6 x 6 degree
column from the core-mantle boundary to the Moho). Values are extinctions per 1000 km; white
transfer function, opacity 1 - exp(-v) per unit distance 1000 km (linear between 33 points), no
shading, black background: a pixel's red channel is its opacity. Methods (same camera and transfer
function): sightline-window / -gl-free (vtkSightlineSphericalVolumeMapper in an offscreen VTK
window / vtkSightlineImageRenderer); fixed-point (the model resampled to N^3 points over [-R, R]^3,
each point the value of the cell it lies in, exactly, as a probe of cell data; then
vtkFixedPointVolumeRayCastMapper, nearest or trilinear, sample distance --sample-fraction x the
spacing); cartesian-exact (that image integrated exactly in numpy, each point's value on its voxel
box: the cost of resampling alone, untimed). Reference: each ray's exact optical depth in numpy
from all its crossings with the grid's spheres, cones and planes (cells found with np.searchsorted
at the segments' midpoints), checked on --check-rows pixel rows by midpoint sampling with --samples
and twice as many samples per ray. Error: |opacity - reference| over the pixels whose ray meets
the globe. Times: first image (mapper set-up included, resampling apart) and still frame (median of
--runs renders after it, the camera rolled +-1e-4 degrees between). Memory: bytes of the drawn
data, and RSS growth to the first image (for a fixed-point nearest row, resampling included).

Usage: Xvfb :78 -noreset &  DISPLAY=:78 nice /usr/bin/python3 spherical_resampling.py
         [--sizes 64 128 256 384] [--size 256] [--runs 3] [--output DIR]
Writes DIR/results-spherical-resampling-DATE.csv and DIR/spherical-resampling-DATE.png
(DIR: this script's folder).
"""
import argparse
import csv
import datetime
import math
import os
import statistics
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline

R = 6371.0
UNIT = 1000.0  # km: ScalarOpacityUnitDistance, and the unit of the values' extinction
LAYERS = ((1221.5, 0.15), (3480.0, 0.05), (5711.0, 0.12), (5961.0, 0.25), (6336.0, 0.2), (R, 0.6))
SLAB = dict(r=(5711.0, 6336.0), colat=(60.0, 80.0), lon=(100.0, 140.0), value=0.9)
PLUME = dict(r=(3480.0, 6336.0), colat=(110.0, 116.0), lon=(200.0, 206.0), value=1.0)
TF_V = np.linspace(0.0, 1.6, 33)
TF_A = 1.0 - np.exp(-TF_V)
VIEW = np.array([1.0, -1.7, 0.8])  # from the globe's centre towards the camera


def build_model(dr):
    """Breakpoints (r km, colatitude, azimuth in radians, 2 degree cells) and cell values, shape
    (nphi, ntheta, nr). The slab's and plume's edges are breakpoints."""
    r, lo = [], 0.0
    for top, _ in LAYERS:
        r.extend(np.linspace(lo, top, max(1, math.ceil((top - lo) / dr)) + 1)[:-1])
        lo = top
    coords = (np.array(r + [R]), np.radians(np.arange(0, 181, 2.0)), np.radians(np.arange(0, 361, 2.0)))
    rc, tc, pc = (0.5 * (a[1:] + a[:-1]) for a in coords)
    layer = np.searchsorted([top for top, _ in LAYERS], rc)
    values = np.tile(np.array([v for _, v in LAYERS])[layer], (len(pc), len(tc), 1))
    pattern = np.sin(tc)[None, :] ** 2 * np.cos(2 * pc)[:, None]  # degree 2, lower mantle only
    values[:, :, layer == 2] *= (1.0 + 0.15 * pattern)[:, :, None]
    for box in (SLAB, PLUME):
        inside = [(c > lo) & (c < hi) for c, (lo, hi) in
                  ((pc, np.radians(box["lon"])), (tc, np.radians(box["colat"])), (rc, box["r"]))]
        values[np.ix_(*inside)] = box["value"]
    return coords, values.astype(np.float32)


def lookup(points, coords, cells):
    """The value of the cell containing each point (..., 3); 0 outside the globe."""
    r, theta, phi = coords
    x, y, z = np.moveaxis(points, -1, 0)
    rr = np.sqrt(x * x + y * y + z * z)
    th = np.arccos(np.clip(z / np.maximum(rr, 1e-300), -1.0, 1.0))
    i = np.searchsorted(r, rr, side="right") - 1
    j = np.clip(np.searchsorted(theta, th, side="right") - 1, 0, len(theta) - 2)
    k = np.clip(np.searchsorted(phi, np.mod(np.arctan2(y, x), 2 * np.pi), side="right") - 1, 0,
                len(phi) - 2)
    return np.where(i < len(r) - 1, cells[k, j, np.minimum(i, len(r) - 2)], 0.0)


def extinction(values):
    return -np.log(1.0 - np.interp(values, TF_V, TF_A)) / UNIT


def camera_and_rays(width):
    """An oblique parallel camera, and each pixel ray's point in the plane through the centre
    (width, width, 3; row 0 at the bottom) and direction."""
    camera = vtk.vtkCamera()
    camera.ParallelProjectionOn()
    camera.SetParallelScale(1.05 * R)
    camera.SetPosition(*(4 * R * VIEW / np.linalg.norm(VIEW)))
    camera.SetViewUp(0, 0, 1)
    camera.OrthogonalizeViewUp()
    camera.SetClippingRange(2 * R, 6 * R)
    d, up = np.array(camera.GetDirectionOfProjection()), np.array(camera.GetViewUp())
    x = ((np.arange(width) + 0.5) / width * 2 - 1) * 1.05 * R
    return camera, x[None, :, None] * np.cross(d, up) + x[:, None, None] * up, d


def exact_depth(origins, d, coords, ext, chunk=1024):
    """Optical depth along each ray (origins perpendicular to d through the centre): all crossings
    with spheres r_i, cones theta_j (z^2 = cos^2 theta_j |p|^2, both nappes) and planes phi_k."""
    r, theta, phi = coords
    b2 = np.einsum("ij,ij->i", origins, origins)
    tau, hits = np.zeros(len(origins)), np.nonzero(b2 < R * R)[0]
    c2, a = np.cos(theta[1:-1]) ** 2, d[2] ** 2 - np.cos(theta[1:-1]) ** 2
    planes = np.unique(np.round(np.mod(phi, np.pi), 12))
    normals = np.stack([-np.sin(planes), np.cos(planes), np.zeros_like(planes)], axis=1)
    normals = normals[np.abs(normals @ d) > 1e-12]
    for s in range(0, len(hits), chunk):
        o, q = origins[hits[s:s + chunk]], b2[hits[s:s + chunk], None]
        half, b, c = np.sqrt(R * R - q), 2 * o[:, 2:3] * d[2], o[:, 2:3] ** 2 - c2 * q
        disc = np.sqrt(np.maximum(b * b - 4 * a * c, 0.0))
        sphere = np.sqrt(np.maximum(r[1:-1] ** 2 - q, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.concatenate([-half, half, sphere, -sphere, (-b + disc) / (2 * a),
                                (-b - disc) / (2 * a), -(o @ normals.T) / (normals @ d)], axis=1)
        t = np.sort(np.clip(np.where(np.isfinite(t), t, -half), -half, half), axis=1)
        points = o[:, None, :] + 0.5 * (t[:, 1:] + t[:, :-1])[..., None] * d
        tau[hits[s:s + chunk]] = (lookup(points, coords, ext) * np.diff(t, axis=1)).sum(axis=1)
    return tau


def sampled_depth(origins, d, coords, ext, samples, chunk=32):
    """Optical depth by the midpoint rule with `samples` samples over each ray's chord."""
    half = np.sqrt(np.maximum(R * R - np.einsum("ij,ij->i", origins, origins), 0.0))
    u, tau = (np.arange(samples) + 0.5) / samples * 2 - 1, np.zeros(len(origins))
    for s in range(0, len(origins), chunk):
        points = origins[s:s + chunk, None, :] + (half[s:s + chunk, None] * u)[..., None] * d
        tau[s:s + chunk] = lookup(points, coords, ext).sum(axis=1) * 2 * half[s:s + chunk] / samples
    return tau


def named(values, deep=True):
    array = numpy_to_vtk(values.reshape(-1), deep=deep)
    array.SetName("extinction")
    return array


def spherical_grid(coords, values):
    grid = vtk.vtkRectilinearGrid()
    grid.SetDimensions(*(len(a) for a in coords))
    grid.SetXCoordinates(numpy_to_vtk(coords[0], deep=True))
    grid.SetYCoordinates(numpy_to_vtk(coords[1], deep=True))
    grid.SetZCoordinates(numpy_to_vtk(coords[2], deep=True))
    grid.GetCellData().SetScalars(named(values))
    return grid, values.nbytes + sum(a.nbytes for a in coords)


def cartesian_image(n, coords, values):
    """n^3 points over [-R, R]^3, each the value of the cell it lies in (nearest-cell lookup)."""
    h = 2 * R / (n - 1)
    axis, data = -R + h * np.arange(n), np.empty((n, n, n), np.float32)  # z, y, x
    for kz in range(n):
        data[kz] = lookup(np.stack(np.broadcast_arrays(axis[None, :], axis[:, None], axis[kz]),
                                   axis=-1), coords, values)
    image = vtk.vtkImageData()
    image.SetDimensions(n, n, n)
    image.SetOrigin(-R, -R, -R)
    image.SetSpacing(h, h, h)
    image.GetPointData().SetScalars(named(data, deep=False))  # shares data: keep data alive
    return image, data, h


def voxel_depth(origins, d, data, h, chunk=256):
    """Exact optical depth through the nearest-resampled image as a perfect renderer would see it
    (each point's value on its voxel box, within [-R, R]^3): all crossings of the voxel planes."""
    n, tau = data.shape[0], np.zeros(len(origins))
    planes = -R + h * (np.arange(n - 1) + 0.5)
    for s in range(0, len(origins), chunk):
        o = origins[s:s + chunk]
        ends = np.stack([(-R - o) / d, (R - o) / d])
        t0 = ends.min(axis=0).max(axis=1, keepdims=True)
        t1 = np.maximum(ends.max(axis=0).min(axis=1, keepdims=True), t0)
        t = np.concatenate([t0, t1] + [(planes - o[:, a:a + 1]) / d[a] for a in range(3)], axis=1)
        t = np.sort(np.clip(t, t0, t1), axis=1)
        points = o[:, None, :] + 0.5 * (t[:, 1:] + t[:, :-1])[..., None] * d
        i = np.clip(np.rint((points + R) / h), 0, n - 1).astype(np.intp)
        ext = extinction(data[i[..., 2], i[..., 1], i[..., 0]].astype(np.float64))
        tau[s:s + chunk] = (ext * np.diff(t, axis=1)).sum(axis=1)
    return tau


def volume_of(mapper, interpolation="nearest"):
    color, opacity = vtk.vtkColorTransferFunction(), vtk.vtkPiecewiseFunction()
    prop, volume = vtk.vtkVolumeProperty(), vtk.vtkVolume()
    color.AddRGBPoint(0.0, 1.0, 1.0, 1.0)
    for v, a in zip(TF_V, TF_A):
        opacity.AddPoint(v, a)
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(UNIT)
    prop.SetInterpolationType(vtk.VTK_LINEAR_INTERPOLATION if interpolation == "trilinear"
                              else vtk.VTK_NEAREST_INTERPOLATION)
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    return volume


def rss():
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) * 1024 for line in f if line.startswith("VmRSS"))


def measure(volume, camera, width, runs, gl_free=False):
    """(opacity image (width, width), first image s, still frame median s, RSS growth)."""
    cam, before, pixels = vtk.vtkCamera(), rss(), vtk.vtkUnsignedCharArray()
    cam.DeepCopy(camera)
    renderer = sightline.vtkSightlineImageRenderer() if gl_free else vtk.vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetActiveCamera(cam)
    renderer.SetBackground(0, 0, 0)
    if gl_free:
        renderer.SetSize(width, width)
        render = renderer.Update
    else:
        window = vtk.vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetMultiSamples(0)
        window.SetSize(width, width)
        window.AddRenderer(renderer)
        render = window.Render
    start = time.perf_counter()
    render()
    first, grown = time.perf_counter() - start, rss() - before
    if gl_free:
        pixels = renderer.GetOutput().GetPointData().GetScalars()
    else:  # the back (rendered) colour buffer, RGB, bottom row first; no depth or alpha needed
        window.GetPixelData(0, 0, width - 1, width - 1, 0, pixels, 0)
    opacity = vtk_to_numpy(pixels).reshape(width, width, -1)[..., 0] / 255.0
    times = []
    for run in range(runs):
        cam.Roll(1e-4 if run % 2 == 0 else -1e-4)
        start = time.perf_counter()
        render()
        times.append(time.perf_counter() - start)
    return opacity, first, statistics.median(times), grown


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256, 384])
    parser.add_argument("--size", type=int, default=256, help="image width = height, pixels")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--radial-step", type=float, default=100.0, help="km (at most)")
    parser.add_argument("--sample-fraction", type=float, default=0.5,
                        help="fixed-point sample distance / voxel spacing")
    parser.add_argument("--samples", type=int, default=20000, help="reference check: samples/ray")
    parser.add_argument("--check-rows", type=int, default=4, help="pixel rows checked by sampling")
    parser.add_argument("--output", default=os.path.dirname(os.path.abspath(__file__)))
    args = parser.parse_args()
    with open("/proc/cpuinfo") as f:
        cpu = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), "?")
    info = dict(cpu=cpu, cores=os.cpu_count(), load=round(os.getloadavg()[0], 2), vtk=vtk.vtkVersion.GetVTKVersion())
    today, w = datetime.date.today().isoformat(), args.size
    coords, values = build_model(args.radial_step)
    ext = extinction(values.astype(np.float64))
    camera, origins, d = camera_and_rays(w)
    rays = origins.reshape(-1, 3)
    start = time.perf_counter()
    tau = exact_depth(rays, d, coords, ext).reshape(w, w)
    reference, reference_s, mask = 1.0 - np.exp(-tau), time.perf_counter() - start, tau > 0
    rows = np.linspace(w * 0.1, w * 0.9, args.check_rows).astype(int)
    check, exact = origins[rows][mask[rows]], reference[rows][mask[rows]]
    checks = {n: float(np.abs(1 - np.exp(-sampled_depth(check, d, coords, ext, n)) - exact).max())
              for n in (args.samples, 2 * args.samples)}
    print(f"model: {values.size} cells ({' x '.join(str(len(a) - 1) for a in coords)} in r, theta, "
          f"phi); reference in {reference_s:.1f} s, opacity up to {reference.max():.3f}; dense "
          f"sampling of {len(check)} of its rays differs by "
          + ", ".join(f"{v:.1e} ({n} samples)" for n, v in checks.items()))
    results = []

    def record(method, interpolation, n, image, first, still, grown, data_bytes, resample_s):
        error = np.abs(image - reference)
        results.append(dict(
            date=today, method=method, interpolation=interpolation, N=n, pixels=f"{w}x{w}",
            data_bytes=data_bytes, rss_increase_bytes=grown, resample_seconds=resample_s,
            first_image_seconds=first, still_frame_seconds=still, max_error=float(error.max()),
            mean_error=float(error[mask].mean()),
            share_over_1_255=float((error[mask] > 1.0 / 255 + 1e-9).mean()),
            sample_fraction=args.sample_fraction if method == "fixed-point" else math.nan,
            **{f"reference_check_{n}": v for n, v in checks.items()}, **info))
        print(f"{method:17s} {interpolation:9s} N={n:4d} first {first:7.3f} s still {still:7.3f} s "
              f"max {error.max():.4f} mean {error[mask].mean():.5f}", flush=True)

    warm = vtk.vtkRenderWindow()  # load OpenGL (llvmpipe) before anything is measured
    warm.SetOffScreenRendering(1)
    warm.Render()
    grid, grid_bytes = spherical_grid(coords, values)
    kept = []  # mappers stay alive, so that each row's RSS growth is its own
    for gl_free in (False, True):
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputData(grid)
        kept.append(mapper)
        record("sightline-gl-free" if gl_free else "sightline-window", "cell", len(coords[0]) - 1,
               *measure(volume_of(mapper), camera, w, args.runs, gl_free), grid_bytes, math.nan)
    for n in args.sizes:
        before, start = rss(), time.perf_counter()
        cartesian, data, spacing = cartesian_image(n, coords, values)
        resample_s, grown = time.perf_counter() - start, rss() - before
        for interpolation in ("nearest", "trilinear"):
            mapper = vtk.vtkFixedPointVolumeRayCastMapper()
            mapper.SetInputData(cartesian)
            mapper.AutoAdjustSampleDistancesOff()
            mapper.SetSampleDistance(args.sample_fraction * spacing)
            mapper.SetImageSampleDistance(1.0)
            image, first, still, more = measure(volume_of(mapper, interpolation), camera, w, args.runs)
            record("fixed-point", interpolation, n, image, first, still, grown + more, data.nbytes,
                   resample_s)
            grown = 0  # the resampling is counted once
        ideal = 1.0 - np.exp(-voxel_depth(rays, d, data, spacing)).reshape(w, w)
        record("cartesian-exact", "nearest", n, ideal, math.nan, math.nan, 0, data.nbytes,
               resample_s)
        del cartesian, data

    path = os.path.join(args.output, f"results-spherical-resampling-{today}.csv")
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(results[0].keys()))
        writer.writeheader()
        writer.writerows(results)
    print(f"\n{info['cpu']}, {info['cores']} cores, load {info['load']}, VTK {info['vtk']}; {w}x{w} "
          f"pixels; N for sightline: shells ({values.size} cells)\n\n| method | interp. | N | data MB | RSS +MB "
          "| resample s | first image s | still frame s | max err | mean err | > 1/255 |\n"
          "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")

    def cell(x, digits, scale=1.0):
        return "-" if math.isnan(x) else f"{x * scale:.{digits}f}"
    for r in results:
        print(f"| {r['method']} | {r['interpolation']} | {r['N']} | {r['data_bytes'] / 1e6:.1f} | "
              f"{cell(r['rss_increase_bytes'], 0, 1e-6)} | {cell(r['resample_seconds'], 2)} | "
              f"{cell(r['first_image_seconds'], 3)} | {cell(r['still_frame_seconds'], 3)} | "
              f"{r['max_error']:.4f} | {r['mean_error']:.5f} | {100 * r['share_over_1_255']:.2f} % |")
    ours = results[0]
    for method in ("fixed-point nearest", "fixed-point trilinear", "cartesian-exact nearest"):
        mine = [r for r in results if f"{r['method']} {r['interpolation']}" == method]
        for key in ("mean_error", "max_error"):
            enough = [r["N"] for r in mine if r[key] <= ours[key]]
            best = f"at N = {enough[0]}" if enough else f"(best {min(r[key] for r in mine):.4f})"
            print(f"{method}: {key} {'reaches' if enough else 'stays above'} Sightline's "
                  f"{ours[key]:.4f} {best}")
    (e0, n0), (e1, n1) = [(r["mean_error"], r["N"]) for r in (mine * 2)[-2:]]
    if e1 < e0 and n1 > n0:  # cartesian-exact's mean error ~ N^-p, extrapolated
        p = math.log(e0 / e1) / math.log(n1 / n0)
        need = n1 * (e1 / ours["mean_error"]) ** (1 / p)
        print(f"cartesian-exact: mean error ~ N^-{p:.2f}: Sightline's mean error at N ~ {need:.0f} "
              f"({need ** 3 * 4 / 1e9:.1f} GB of float32), extrapolated")
    print("wrote", path)
    plot(results, os.path.join(args.output, f"spherical-resampling-{today}.png"))


def plot(results, output):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(1, 3, figsize=(20, 5.6))
    styles = {"sightline-window cell": ("tab:blue", "o"), "sightline-gl-free cell": ("tab:cyan", "D"),
              "fixed-point nearest": ("tab:orange", "s"), "fixed-point trilinear": ("tab:red", "^"),
              "cartesian-exact nearest": ("tab:green", "v")}
    for axis, key, label in ((axes[0], "still_frame_seconds", "still frame [s] (median)"),
                             (axes[1], "total", "first image [s] (resampling included)"),
                             (axes[2], "data_bytes", "bytes of the drawn grid or image")):
        for name, (color, marker) in styles.items():
            rows = [r for r in results if f"{r['method']} {r['interpolation']}" == name]
            x = [r[key] if key != "total" else r["first_image_seconds"] + (
                0 if math.isnan(r["resample_seconds"]) else r["resample_seconds"]) for r in rows]
            if any(math.isnan(v) for v in x):
                continue
            for error, style in (("mean_error", "-"), ("max_error", "--")):
                axis.plot(x, [r[error] for r in rows], marker=marker, color=color, ls=style,
                          mfc=color if style == "-" else "none", label=f"{name}: {error[:-6]}")
            for v, r in zip(x, rows if not name.startswith("sightline") else []):
                axis.annotate(f"{r['N']}^3", (v, r["mean_error"]), fontsize=7, xytext=(3, 3),
                              textcoords="offset points")
        axis.axhline(1 / 255, color="gray", lw=0.8, ls=":")
        axis.set(xscale="log", yscale="log", xlabel=label,
                 ylabel="|opacity - exact| over the globe (solid: mean, dashed: max)")
        axis.grid(True, which="both", alpha=0.3)
    axes[2].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    first = results[0]
    figure.suptitle(f"Earth model ({first['N']} shells): Sightline against resampled to N^3 for "
                    "vtkFixedPointVolumeRayCastMapper (cartesian-exact: that image integrated exactly)"
                    f", {first['pixels']} px; {first['cpu']}, {first['cores']} cores, load "
                    f"{first['load']}; dotted: 1/255", fontsize=9)
    figure.tight_layout()
    figure.savefig(output, dpi=100)
    print("wrote", output)


if __name__ == "__main__":
    main()
