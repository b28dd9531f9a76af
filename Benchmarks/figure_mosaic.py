#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Report figures on cluster nodes (issue 36): an ODF mosaic of 3 rows x 8 slices (axial,
coronal, sagittal) at 3200x1200, 400x400 a panel, of a whole-brain lmax-8 FOD over a T1.

Two ways, each in a child process of its own, timed from start to the PNG on disk (wall
seconds, Python start and file reading included) with its peak RSS from /usr/bin/time -v:

  baseline   the way pipelines make it today, what DIPY/FURY's odf_slicer does (FURY is not
             needed; this is written out here): nibabel get_fdata(dtype=float32) of the whole
             FOD; for each panel the slice's nonzero voxels, sh_to_sf on DIPY's repulsion724
             sphere (tournier07, legacy False, lmax 8), one vtkPolyData of all glyph meshes
             (centre + 0.5 voxel * odf/max|odf| * direction, the sphere's 1444 triangles a glyph,
             RGB = |direction|), the T1 slice as a vtkImageSlice one voxel behind it, a 400x400
             offscreen vtkRenderWindow (parallel projection framed on the brain) on an Xvfb
             started here for that child only, vtkWindowToImageFilter into a numpy mosaic,
             vtkPNGWriter. Slices: 8 evenly spaced within the brain's extent along each axis,
             the outer 15 % at either end skipped. Xvfb's own peak RSS goes in the note.
  sightline  build/bin/sightline-view FOD --underlay T1 --mosaic axial:8,coronal:8,sagittal:8
             --size 3200 1200 --basis tournier07 --no-legacy --output OUT.png, with DISPLAY
             removed from its environment (no X, no OpenGL). A failure is recorded as a row
             with the last line of its stderr.

A 10^6-link tractogram (Benchmarks/whole_brain.py's synthetic brain, made when missing) as a
3x8 tract mosaic over the same T1, each panel the streamlines within an 8 mm slab around its
slice, the two ways:

  tracts-baseline   what FURY's streamtube does: nibabel loads the .tck, per panel the runs
                    of points inside the slab as polylines, vtkTubeFilter (8 sides, radius
                    0.5 mm, direction colours), the T1 slice behind the slab, offscreen
                    window under Xvfb, grabbed into the mosaic.
  tracts-sightline  sightline-view brain-1000000.trx --underlay T1 --mosaic ... --slab 8
                    (exact tubes, radius 0.5 mm), no DISPLAY.

Usage: /usr/bin/python3 figure_mosaic.py [--data DIR] [--rows baseline,sightline,
       tracts-baseline,tracts-sightline] [--csv PATH]
Data: DIR/fod.nii.gz and DIR/t1.nii.gz (default /tmp/sightline-figures), made by
scripts/make_figure_data.py when missing (HCP size 145x174x145x45, ~0.5 min). Writes the CSV
(default Benchmarks/results-figure-mosaic-DATE.csv; columns how, panels, size, seconds,
peak_rss_mb (MiB: kB / 1024), output, machine, note), DIR/mosaic-baseline.png and
DIR/mosaic-sightline.png, and prints a table. Targets of the issue: peak RSS <= 1.5 GB and <= 60 s on 2 cores.
"""
import argparse
import csv
import datetime
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
VIEW = os.path.join(ROOT, "build", "bin", "sightline-view")
PANEL = 400
ROWS = ("axial", "coronal", "sagittal")
AXIS = {"axial": 2, "coronal": 1, "sagittal": 0}
# Camera side along the slice normal and view-up: axial from above (anterior up), coronal
# from behind, sagittal from the right (anterior on the right); left on the left in axial and
# coronal (neurological), as sightline-view --mosaic draws them.
TOWARD_CAMERA = {"axial": 1.0, "coronal": -1.0, "sagittal": 1.0}
VIEW_UP = {"axial": (0, 1, 0), "coronal": (0, 0, 1), "sagittal": (0, 0, 1)}


def panel_slices(mask, count=8, skip=0.15):
    """(orientation, index) for each panel: count slices over the mask's inner extent."""
    panels = []
    for name in ROWS:
        axis = AXIS[name]
        present = np.flatnonzero(mask.any(axis=tuple(a for a in range(3) if a != axis)))
        low, high = present[0], present[-1]
        span = high - low
        picks = np.linspace(low + skip * span, high - skip * span, count)
        panels += [(name, int(round(i))) for i in picks]
    return panels


def panel_window():
    """(window, renderer, grab): one offscreen PANEL x PANEL VTK window (needs the X server the
    benchmark starts) and the filter that reads its pixels back."""
    import vtk

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(PANEL, PANEL)
    renderer = vtk.vtkRenderer()
    window.AddRenderer(renderer)
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    return window, renderer, grab


def grab_panel(window, grab, mosaic, row, column):
    """Renders the window and copies its pixels into the mosaic's panel (row, column)."""
    from vtk.util.numpy_support import vtk_to_numpy

    window.Render()
    grab.Modified()
    grab.Update()
    shot = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).reshape(PANEL, PANEL, -1)
    mosaic[row * PANEL:(row + 1) * PANEL, column * PANEL:(column + 1) * PANEL] = shot[::-1, :, :3]


def write_png(mosaic, output):
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

    picture = vtk.vtkImageData()
    picture.SetDimensions(mosaic.shape[1], mosaic.shape[0], 1)
    picture.GetPointData().SetScalars(numpy_to_vtk(mosaic[::-1].reshape(-1, 3), deep=True))
    writer = vtk.vtkPNGWriter()
    writer.SetInputData(picture)
    writer.SetFileName(output)
    writer.Write()


def grey_slice(plane, axis, origin, spacing, grey):
    """A vtkImageSlice of a 2-D T1 plane (normal to data axis `axis`), white matter at about
    70 % grey (grey: the 0.5th and 99.5th percentiles)."""
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk

    plane = np.ascontiguousarray(plane)
    dims = [plane.shape[0], plane.shape[1]]
    dims.insert(axis, 1)
    image = vtk.vtkImageData()
    image.SetDimensions(*dims)
    image.SetSpacing(*spacing)
    image.SetOrigin(*origin)
    image.GetPointData().SetScalars(numpy_to_vtk(plane.ravel(order="F"), deep=True))
    mapper = vtk.vtkImageSliceMapper()
    mapper.SetInputData(image)
    mapper.SetOrientation(axis)
    underlay = vtk.vtkImageSlice()
    underlay.SetMapper(mapper)
    underlay.GetProperty().SetColorWindow(1.4 * (grey[1] - grey[0]))
    underlay.GetProperty().SetColorLevel(grey[0] + 0.7 * (grey[1] - grey[0]))
    return underlay


def baseline(data, output):
    """The child: odf_slicer's way (see the docstring). Prints one JSON line of details."""
    started = time.perf_counter()
    import nibabel as nib
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray
    from dipy.data import get_sphere
    from dipy.reconst.shm import sh_to_sf

    image = nib.load(os.path.join(data, "fod.nii.gz"))
    fod = image.get_fdata(dtype=np.float32)  # the whole 4-D image, as pipelines load it
    t1 = nib.load(os.path.join(data, "t1.nii.gz")).get_fdata(dtype=np.float32)
    loaded = time.perf_counter() - started
    affine = image.affine
    voxel = float(np.abs(affine[:3, :3]).sum(0).max())
    mask = fod[..., 0] != 0
    sphere = get_sphere("repulsion724")
    vertices, faces = sphere.vertices.astype(np.float32), sphere.faces.astype(np.int64)
    colours = (np.abs(vertices) * 255).astype(np.uint8)
    ijk = np.argwhere(mask)
    world = ijk @ affine[:3, :3].T + affine[:3, 3]
    low, high = world.min(0) - voxel, world.max(0) + voxel
    centre = (low + high) / 2
    grey = np.percentile(t1[mask], [0.5, 99.5])

    window, renderer, grab = panel_window()
    mosaic = np.zeros((3 * PANEL, 8 * PANEL, 3), np.uint8)
    glyphs, most_triangles, panels = 0, 0, panel_slices(mask)
    phase = dict.fromkeys(("sf", "mesh", "render"), 0.0)
    for number, (name, index) in enumerate(panels):
        axis = AXIS[name]
        cut = tuple(index if a == axis else slice(None) for a in range(3))
        inside = np.argwhere(mask[cut])
        full = np.insert(inside, axis, index, axis=1)
        centres = (full @ affine[:3, :3].T + affine[:3, 3]).astype(np.float32)
        clock = time.perf_counter()
        sf = sh_to_sf(fod[cut][mask[cut]], sphere, sh_order=8, basis_type="tournier07",
                      legacy=False)
        sf /= np.maximum(np.abs(sf).max(axis=1, keepdims=True), 1e-12)  # fury's norm=True
        phase["sf"] += time.perf_counter() - clock
        clock = time.perf_counter()
        points = centres[:, None, :] + (0.5 * voxel) * sf[..., None].astype(np.float32) * vertices
        n = len(centres)
        connectivity = (faces[None] + (np.arange(n) * len(vertices))[:, None, None]).ravel()
        offsets = np.arange(0, len(connectivity) + 1, 3, dtype=np.int64)
        cells = vtk.vtkCellArray()
        cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                      numpy_to_vtkIdTypeArray(connectivity, deep=True))
        poly = vtk.vtkPolyData()
        vtk_points = vtk.vtkPoints()
        vtk_points.SetData(numpy_to_vtk(points.reshape(-1, 3), deep=True))
        poly.SetPoints(vtk_points)
        poly.SetPolys(cells)
        rgb = numpy_to_vtk(np.tile(colours, (n, 1)), deep=True)
        rgb.SetName("rgb")
        poly.GetPointData().SetScalars(rgb)
        del sf, points, connectivity, offsets
        mapper = vtk.vtkPolyDataMapper()
        mapper.SetInputData(poly)
        mapper.SetColorModeToDirectScalars()
        glyph_actor = vtk.vtkActor()
        glyph_actor.SetMapper(mapper)
        glyphs, most_triangles = glyphs + n, max(most_triangles, n * len(faces))

        # The T1 slice, one voxel behind the glyphs as seen from the camera.
        origin = affine[:3, 3].copy()
        origin[axis] += index * voxel - TOWARD_CAMERA[name] * voxel
        underlay = grey_slice(t1[cut], axis, origin, [voxel] * 3, grey)
        label = vtk.vtkTextActor()
        label.SetInput(f"{name} {'xyz'[axis]} = {origin[axis] + TOWARD_CAMERA[name] * voxel:+.1f} mm")
        label.GetTextProperty().SetFontSize(16)
        label.SetDisplayPosition(8, PANEL - 24)

        renderer.RemoveAllViewProps()
        for prop in (underlay, glyph_actor, label):
            renderer.AddViewProp(prop)
        camera = renderer.GetActiveCamera()
        camera.ParallelProjectionOn()
        focal = centre.copy()
        focal[axis] = origin[axis]
        position = focal.copy()
        position[axis] += TOWARD_CAMERA[name] * 500.0
        camera.SetFocalPoint(*focal)
        camera.SetPosition(*position)
        camera.SetViewUp(*VIEW_UP[name])
        camera.SetParallelScale(0.52 * max(np.delete(high - low, axis)))
        renderer.ResetCameraClippingRange()
        phase["mesh"] += time.perf_counter() - clock
        clock = time.perf_counter()
        grab_panel(window, grab, mosaic, ROWS.index(name), number % 8)
        renderer.RemoveAllViewProps()
        del poly, cells, vtk_points, rgb, mapper, glyph_actor
        phase["render"] += time.perf_counter() - clock

    write_png(mosaic, output)
    print(json.dumps({"load_s": loaded, "total_s": time.perf_counter() - started, **phase,
                      "glyphs": glyphs, "most_triangles": most_triangles,
                      "renderer": [line.split(":", 1)[1].strip() for line in
                                   window.ReportCapabilities().splitlines()
                                   if line.startswith("OpenGL renderer string")]}))


def slab_runs(points, offsets, axis, position, slab):
    """(connectivity, offsets) of the runs of consecutive points within slab / 2 of position."""
    keep = np.abs(points[:, axis] - position) <= 0.5 * slab
    line = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    start = keep & np.concatenate([[True], (line[1:] != line[:-1]) | ~keep[:-1]])
    run = np.cumsum(start) - 1
    counts = np.bincount(run[keep], minlength=int(start.sum()))
    chosen = keep.copy()
    chosen[keep] = counts[run[keep]] >= 2
    return np.flatnonzero(chosen), np.concatenate([[0], np.cumsum(counts[counts >= 2])])


def tracts_baseline(data, tck, output):
    """The child: FURY streamtube's way for a slab per panel (see the docstring)."""
    started = time.perf_counter()
    import nibabel as nib
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray

    tractogram = nib.streamlines.load(tck)
    points = np.asarray(tractogram.streamlines.get_data(), np.float32)
    offsets = np.concatenate([[0], np.cumsum(tractogram.streamlines._lengths)]).astype(np.int64)
    line = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    tangents = np.gradient(points, axis=0)  # direction colours (ends approximate)
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-9)
    colours = (np.abs(tangents) * 255).astype(np.uint8)
    del line, tangents
    t1_image = nib.load(os.path.join(data, "t1.nii.gz"))
    t1, affine = t1_image.get_fdata(dtype=np.float32), t1_image.affine
    grey = np.percentile(t1[t1 > 0], [0.5, 99.5])
    loaded = time.perf_counter() - started
    low, high = points.min(0), points.max(0)
    window, renderer, grab = panel_window()
    mosaic = np.zeros((3 * PANEL, 8 * PANEL, 3), np.uint8)
    phase = dict.fromkeys(("mesh", "render"), 0.0)
    most_triangles = 0
    for row, name in enumerate(ROWS):
        axis = AXIS[name]
        for column in range(8):
            clock = time.perf_counter()
            position = low[axis] + (high - low)[axis] * (column + 1) / 9
            chosen, run_offsets = slab_runs(points, offsets, axis, position, 8.0)
            poly = vtk.vtkPolyData()
            vtk_points = vtk.vtkPoints()
            vtk_points.SetData(numpy_to_vtk(points[chosen], deep=True))
            poly.SetPoints(vtk_points)
            cells = vtk.vtkCellArray()
            cells.SetData(numpy_to_vtkIdTypeArray(run_offsets.astype(np.int64), deep=True),
                          numpy_to_vtkIdTypeArray(np.arange(len(chosen), dtype=np.int64), deep=True))
            poly.SetLines(cells)
            rgb = numpy_to_vtk(colours[chosen], deep=True)
            rgb.SetName("rgb")
            poly.GetPointData().SetScalars(rgb)
            tubes = vtk.vtkTubeFilter()
            tubes.SetInputData(poly)
            tubes.SetRadius(0.5)
            tubes.SetNumberOfSides(8)
            tubes.CappingOn()
            tubes.Update()
            strips = tubes.GetOutput().GetStrips()
            triangles = (strips.GetNumberOfConnectivityIds() - 2 * strips.GetNumberOfCells()
                         + tubes.GetOutput().GetPolys().GetNumberOfCells())
            most_triangles = max(most_triangles, triangles)
            mapper = vtk.vtkPolyDataMapper()
            mapper.SetInputConnection(tubes.GetOutputPort())
            mapper.SetColorModeToDirectScalars()
            actor = vtk.vtkActor()
            actor.SetMapper(mapper)
            # The T1 slice just behind the slab, as seen from the camera.
            toward = TOWARD_CAMERA[name]
            behind = position - toward * 4.0
            index = int(round((behind - affine[axis, 3]) / affine[axis, axis]))
            index = min(max(index, 0), t1.shape[axis] - 1)
            cut = tuple(index if a == axis else slice(None) for a in range(3))
            origin = affine[:3, 3].copy()
            origin[axis] = behind
            underlay = grey_slice(t1[cut], axis, origin, np.abs(np.diag(affine)[:3]), grey)
            renderer.RemoveAllViewProps()
            renderer.AddViewProp(underlay)
            renderer.AddViewProp(actor)
            camera = renderer.GetActiveCamera()
            camera.ParallelProjectionOn()
            focal = (low + high) / 2
            focal[axis] = position
            camera.SetFocalPoint(*focal)
            eye = focal.copy()
            eye[axis] += toward * 500.0
            camera.SetPosition(*eye)
            camera.SetViewUp(*VIEW_UP[name])
            camera.SetParallelScale(0.52 * max(np.delete(high - low, axis)))
            renderer.ResetCameraClippingRange()
            phase["mesh"] += time.perf_counter() - clock
            clock = time.perf_counter()
            grab_panel(window, grab, mosaic, row, column)
            renderer.RemoveAllViewProps()
            del poly, cells, vtk_points, rgb, tubes, mapper, actor
            phase["render"] += time.perf_counter() - clock
    write_png(mosaic, output)
    print(json.dumps({"load_s": loaded, **phase, "most_triangles": most_triangles,
                      "links": int(len(points) - (len(offsets) - 1))}))


def tract_data():
    """The 10^6-link synthetic brain of whole_brain.py (.trx and .tck), made when missing."""
    folder = "/tmp/sightline-whole-brain"
    trx, tck = (os.path.join(folder, "brain-1000000" + e) for e in (".trx", ".tck"))
    if not (os.path.exists(trx) and os.path.exists(tck)):
        os.makedirs(folder, exist_ok=True)
        sys.path.insert(0, HERE)
        import whole_brain
        whole_brain.write(1e6, trx, tck)
    return trx, tck


def measure(command, env):
    """(wall seconds, peak RSS MiB, return code, stdout, stderr) of a child under /usr/bin/time."""
    started = time.perf_counter()
    done = subprocess.run(["/usr/bin/time", "-v"] + command, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - started
    found = re.search(r"Maximum resident set size \(kbytes\): (\d+)", done.stderr)
    peak = int(found.group(1)) / 1024.0 if found else float("nan")
    stderr = re.sub(r"Command exited with non-zero status \d+\s*$", "",
                    done.stderr.split("\tCommand being timed:")[0].strip())
    return seconds, peak, done.returncode, done.stdout, stderr


def start_xvfb():
    number = next(n for n in range(91, 200) if not os.path.exists(f"/tmp/.X11-unix/X{n}")
                  and not os.path.exists(f"/tmp/.X{n}-lock"))
    server = subprocess.Popen(["Xvfb", f":{number}", "-screen", "0", "1280x1024x24", "-noreset",
                               "-nolisten", "tcp"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(100):
        if os.path.exists(f"/tmp/.X11-unix/X{number}"):
            break
        time.sleep(0.1)
    return server, f":{number}"


def peak_of(pid):
    with open(f"/proc/{pid}/status") as status:
        return next(int(line.split()[1]) / 1024.0 for line in status if line.startswith("VmHWM"))


def machine():
    with open("/proc/cpuinfo") as f:
        model = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), "?")
    with open("/proc/loadavg") as f:
        load = " ".join(f.read().split()[:3])
    return f"{model}, {os.cpu_count()} cores, loadavg {load}"


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--data", default="/tmp/sightline-figures")
    parser.add_argument("--rows", default="baseline,sightline,tracts-baseline,tracts-sightline")
    parser.add_argument("--csv", default=os.path.join(
        HERE, f"results-figure-mosaic-{datetime.date.today().isoformat()}.csv"))
    parser.add_argument("--baseline", nargs=2, metavar=("DATA", "OUTPUT"), help=argparse.SUPPRESS)
    parser.add_argument("--tracts-baseline", nargs=3, metavar=("DATA", "TCK", "OUTPUT"),
                        help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.baseline:
        baseline(*args.baseline)
        return
    if args.tracts_baseline:
        tracts_baseline(*args.tracts_baseline)
        return
    fod, t1 = (os.path.join(args.data, name) for name in ("fod.nii.gz", "t1.nii.gz"))
    if not (os.path.exists(fod) and os.path.exists(t1)):
        print(f"making the data in {args.data} ...", flush=True)
        subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "make_figure_data.py"),
                        "--output", args.data], check=True)
    size = f"{8 * PANEL}x{3 * PANEL}"
    rows = []
    for how in args.rows.split(","):
        output = os.path.join(args.data, f"mosaic-{how}.png")
        if os.path.exists(output):
            os.remove(output)
        env = dict(os.environ)
        env.pop("DISPLAY", None)
        note, server = "", None
        if how.startswith("tracts"):
            trx, tck = tract_data()
        if how == "tracts-baseline":
            server, env["DISPLAY"] = start_xvfb()
            command = [sys.executable, os.path.abspath(__file__), "--tracts-baseline", args.data,
                       tck, output]
            label = "tracts: vtkTubeFilter meshes under Xvfb (FURY streamtube's way)"
        elif how == "tracts-sightline":
            command = [VIEW, trx, "--underlay", t1, "--mosaic", "axial:8,coronal:8,sagittal:8",
                       "--size", str(8 * PANEL), str(3 * PANEL), "--slab", "8", "--radius", "0.5",
                       "--output", output]
            label = "tracts: Sightline GL-free"
        elif how == "baseline":
            server, env["DISPLAY"] = start_xvfb()
            command = [sys.executable, os.path.abspath(__file__), "--baseline", args.data, output]
            label = "mesh under Xvfb (odf_slicer's way)"
        elif how == "sightline":
            command = [VIEW, fod, "--underlay", t1, "--mosaic", "axial:8,coronal:8,sagittal:8",
                       "--size", str(8 * PANEL), str(3 * PANEL), "--basis", "tournier07",
                       "--no-legacy", "--output", output]
            label = "Sightline GL-free"
        else:
            sys.exit(f"unknown row {how!r} (baseline, sightline, tracts-baseline, "
                     "tracts-sightline)")
        print(f"{label}: ...", end="", flush=True)
        seconds, peak, code, out, err = measure(command, env)
        if server is not None:
            note = f"Xvfb peak RSS {peak_of(server.pid):.0f} MiB (not counted); "
            server.terminate()
            server.wait()
        if code != 0 or not os.path.exists(output):
            last = (err.strip().splitlines() or ["(no stderr)"])[-1]
            note += f"FAILED (exit {code}): {last}"
        elif how == "tracts-baseline":
            detail = json.loads(out.strip().splitlines()[-1])
            note += (f"load {detail['load_s']:.1f} s, slabs+tubes {detail['mesh']:.1f} s, "
                     f"render+grab {detail['render']:.1f} s; {detail['links']:,} links, up to "
                     f"{detail['most_triangles'] / 1e6:.1f} M triangles a panel")
        elif how == "baseline":
            detail = json.loads(out.strip().splitlines()[-1])
            note += (f"load {detail['load_s']:.1f} s, sh_to_sf {detail['sf']:.1f} s, meshes "
                     f"{detail['mesh']:.1f} s, render+grab {detail['render']:.1f} s; "
                     f"{detail['glyphs']:,} glyphs, up to "
                     f"{detail['most_triangles'] / 1e6:.1f} M triangles a panel; "
                     f"{' '.join(detail['renderer'])}")
        print(f" {seconds:.1f} s, peak {peak:.0f} MiB {note}")
        rows.append({"how": label, "panels": 24, "size": size, "seconds": f"{seconds:.2f}",
                     "peak_rss_mb": f"{peak:.0f}", "output": output if os.path.exists(output) else "",
                     "machine": machine(), "note": note.strip("; ")})
    with open(args.csv, "w", newline="") as f:
        writer = csv.DictWriter(f, list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"\n{args.csv}\n")
    print("| how | panels | size | seconds | peak RSS MiB | note |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['how']} | {r['panels']} | {r['size']} | {r['seconds']} | {r['peak_rss_mb']} | {r['note']} |")


if __name__ == "__main__":
    main()
