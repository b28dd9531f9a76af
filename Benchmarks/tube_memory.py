#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Where a real pipeline's bytes go: 1M tube links (random-walk streamlines, float32 points,
polylines) built in numpy -> vtkPolyData -> vtkSightlineTubeMapper in a 1920x1080 VTK window.

The process's resident set (VmRSS) and its peak (VmHWM) are read from /proc/self/status:
  - after the imports;
  - after the window's first (empty) Render: the GL context and Mesa's buffers;
  - after the poly data is built (numpy temporaries freed);
  - after the first and the second Render with the tubes;
and the mapper's own accounting (GetGeometryMemoryBytes, GetBVHMemoryBytes). The same script
with a single link (run as a child process) gives what a Sightline frame costs whatever the data
(framebuffers, GL upload buffers, threads, Embree's device). Timings and sizes are the machine's,
not pass/fail.

Usage: xvfb-run -a -s "-noreset -screen 0 1920x1080x24" /usr/bin/python3 tube_memory.py
         [--links N] [--size W H] [--arrays]
with PYTHONPATH at the build tree's lib/python3/dist-packages. --arrays adds a per-point radius
array (VaryRadius by scalar) and scalars coloured through the lookup table.
"""
import argparse
import json
import subprocess
import sys
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray

import sightline

MIB = 1024.0 * 1024.0
POINTS_PER_LINE = 101


def memory():
    """(VmRSS, VmHWM) in MiB."""
    values = {}
    with open("/proc/self/status") as status:
        for line in status:
            key, _, rest = line.partition(":")
            if key in ("VmRSS", "VmHWM"):
                values[key] = int(rest.split()[0]) / 1024.0
    return values["VmRSS"], values["VmHWM"]


def streamlines(links, arrays):
    lines = max(1, links // (POINTS_PER_LINE - 1))
    per = POINTS_PER_LINE if links >= POINTS_PER_LINE - 1 else links + 1
    rng = np.random.default_rng(1)
    steps = rng.normal(size=(lines, per, 3)).astype(np.float32) * 0.05
    starts = rng.uniform(-5, 5, size=(lines, 1, 3)).astype(np.float32)
    points = vtk.vtkPoints()
    points.SetData(numpy_to_vtk((starts + np.cumsum(steps, axis=1)).reshape(-1, 3), deep=1))
    cells = vtk.vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(np.arange(0, lines * per + 1, per, dtype=np.int64), deep=1),
                  numpy_to_vtkIdTypeArray(np.arange(lines * per, dtype=np.int64), deep=1))
    poly = vtk.vtkPolyData()
    poly.SetPoints(points)
    poly.SetLines(cells)
    if arrays:
        radius = numpy_to_vtk(rng.uniform(0.005, 0.02, size=lines * per).astype(np.float32), deep=1)
        radius.SetName("radius")
        poly.GetPointData().AddArray(radius)
        scalars = numpy_to_vtk(rng.uniform(0.0, 1.0, size=lines * per).astype(np.float32), deep=1)
        scalars.SetName("fa")
        poly.GetPointData().SetScalars(scalars)
    return poly, lines * (per - 1)


def measure(links, size, arrays):
    result = {"imports": memory()}
    window = vtk.vtkRenderWindow()
    window.SetSize(*size)
    window.SetOffScreenRendering(1)
    renderer = vtk.vtkRenderer()
    window.AddRenderer(renderer)
    window.Render()
    result["window"] = memory()
    poly, result["links"] = streamlines(links, arrays)
    result["polydata"] = memory()
    result["polydata_actual"] = poly.GetActualMemorySize() * 1024.0
    mapper = sightline.vtkSightlineTubeMapper()
    mapper.SetInputDataObject(poly)
    mapper.SetRadius(0.01)
    if arrays:
        mapper.SetRadiusArrayName("radius")
        mapper.SetVaryRadiusToVaryRadiusByScalar()
        mapper.SetScalarRange(0.0, 1.0)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    renderer.AddActor(actor)
    renderer.ResetCamera()
    started = time.perf_counter()
    window.Render()
    result["first_render_seconds"] = time.perf_counter() - started
    result["first"] = memory()
    window.Render()
    result["second"] = memory()
    result["geometry"] = mapper.GetGeometryMemoryBytes()
    result["bvh"] = mapper.GetBVHMemoryBytes()
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--links", type=int, default=1000000)
    parser.add_argument("--size", type=int, nargs=2, default=[1920, 1080])
    parser.add_argument("--arrays", action="store_true")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 unless every link was drawn and the accounting adds up (smoke test)")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(args.links, args.size, args.arrays)))
        return

    def run(links):
        command = [sys.executable, __file__, "--child", "--links", str(links), "--size",
                   *map(str, args.size)] + (["--arrays"] if args.arrays else [])
        return json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)

    tiny, big = run(1), run(args.links)
    width, height = args.size
    pixels = width * height
    # The kernel's framebuffer (RGBA float, window depth, distance) and the window compositor's
    # RGBA8 colour and float depth that go to OpenGL: sizes, not measurements.
    framebuffers = pixels * (16 + 4 + 4) / MIB + pixels * (4 + 4) / MIB
    geometry, bvh = big["geometry"] / MIB, big["bvh"] / MIB
    frame_fixed = tiny["second"][0] - tiny["polydata"][0]
    mapper_rss = big["second"][0] - big["polydata"][0]
    mapper_peak = big["second"][1] - big["polydata"][0]
    links = big["links"]
    print(f"{links} links, {width}x{height}, first Render {big['first_render_seconds']:.2f} s")
    print("| what | MiB | bytes/link |")
    print("|---|---|---|")

    def row(what, mib):
        print(f"| {what} | {mib:.1f} | {mib * MIB / links:.0f} |")

    row("window and GL context (empty first Render; from the imports)", big["window"][0] - big["imports"][0])
    row("vtkPolyData as built (RSS; numpy temporaries freed)", big["polydata"][0] - big["window"][0])
    row("  of it GetActualMemorySize", big["polydata_actual"] / MIB)
    row("Sightline, steady RSS after two Renders (from the poly data)", mapper_rss)
    row("Sightline, peak RSS (from the poly data)", mapper_peak)
    row("  geometry (GetGeometryMemoryBytes)", geometry)
    row("  BVH (GetBVHMemoryBytes)", bvh)
    row("  framebuffers (computed: kernel 24 B + compositor 8 B a pixel)", framebuffers)
    row("  a 1-link scene's whole frame cost (measured: framebuffers, GL buffers, threads)", frame_fixed)
    row("  the rest: input conversion and build temporaries kept by the allocator",
        mapper_peak - geometry - bvh - frame_fixed)
    if args.check:
        # Each link holds at least its end point and radius (16 bytes); the BVH has a node per
        # few links; a frame costs at least the kernel's framebuffer.
        problems = []
        if links != args.links:
            problems.append(f"{links} links built for {args.links}")
        if not big["geometry"] >= 16 * links:
            problems.append(f"geometry {big['geometry']} bytes for {links} links")
        if not big["bvh"] > 8 * links:
            problems.append(f"BVH {big['bvh']} bytes for {links} links")
        if not frame_fixed > 0.0:
            problems.append(f"a frame costs {frame_fixed} MiB")
        for problem in problems:
            print("FAILED:", problem)
        if problems:
            sys.exit(1)
    print(f"peak / (geometry + BVH + framebuffers) = {mapper_peak / (geometry + bvh + framebuffers):.2f}; "
          f"peak / (geometry + BVH + 1-link frame cost) = {mapper_peak / (geometry + bvh + frame_fixed):.2f}")


if __name__ == "__main__":
    main()
