# SPDX-License-Identifier: BSD-3-Clause
"""One run of the ParaView scale benchmark: `mpirun -np N pvbatch --symmetric` on this script
(Benchmarks/paraview_scale_driver.py starts it for N = 1, 2, 4 and writes the tables).

--symmetric: every rank runs this script, so that every rank can read its own Sightline mapper
(the representation's mapper on that rank traced that rank's piece) and its own process's peak
RSS. Each rank writes RANK.json into --output; nothing is gathered through MPI.

Per rank:
  tubes     the .tck file through Sightline's TCK reader (each rank reads its own run of whole
            streamlines), shown as opaque Sightline Tubes at --size: piece points/links, geometry
            and BVH bytes (vtkSightlineMapper::GetGeometryMemoryBytes/GetBVHMemoryBytes), the
            geometry and BVH build seconds, and each frame's trace seconds (GetLastFrameSeconds);
  grid      the Sightline Spherical Field source (PREM Density) at --grid resolution: each rank's
            sub-extent (UpdatePipeline) measured, then drawn as a Sightline Spherical Volume
            (the tubes hidden): each rank draws the cells of its box (ordered compositing), so
            the cells it holds for drawing, their bytes, the first volume frame (the partition
            and the cells' exchange included) and the steady frames' trace are recorded;
  rss       peak RSS (ru_maxrss) after ParaView and the plugin are loaded (the constant part), after
            the tubes' first frame, and at the end (after the grid).
On rank 0 also: each frame's wall time (Render(), which returns after IceT has composited), the
first frame (reading, geometry, BVH, trace, composite) apart from the steady frames (the camera
turns a little each frame, the geometry stays), and the image (.npy) for the driver's comparison
with the 1-rank image.

The functions are prefixed scale_ (a ProgrammableFilter would star-import numpy into this
namespace; none is used here, the prefix is kept for the same reason as in mpi_scene.py).
"""
import argparse
import json
import math
import os
import resource
import time

import numpy as np
import paraview.simple as pvs
from paraview.simple import (CreateView, Delete, LoadPlugin, OpenDataFile, Render, SaveScreenshot,
                             SetActiveView, Show)
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkParallelCore import vtkMultiProcessController
import sightline  # noqa: F401  (wraps the mappers' getters)


def scale_rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: KiB


def scale_mapper(rep):
    return rep.GetClientSideObject().GetActiveRepresentation().GetSightlineMapper()


def scale_piece(proxy):
    data = proxy.GetClientSideObject().GetOutputDataObject(0)
    if data.IsA("vtkCompositeDataSet"):
        points = cells = size = 0
        it = data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            leaf = it.GetCurrentDataObject()
            points += leaf.GetNumberOfPoints()
            cells += leaf.GetNumberOfCells()
            size += leaf.GetActualMemorySize()
            it.GoToNextItem()
        return points, cells, size * 1024
    return data.GetNumberOfPoints(), data.GetNumberOfCells(), data.GetActualMemorySize() * 1024


def scale_save_image(view, args, rank, name):
    """NAME.png of the view and, on rank 0 (which holds the composited image), NAME.npy for the
    driver's comparison with the 1-rank image."""
    path = os.path.join(args.output, f"{name}.png")
    SaveScreenshot(path, view, ImageResolution=list(args.size), TransparentBackground=0)
    if rank == 0:
        png = vtkPNGReader()
        png.SetFileName(path)
        png.Update()
        image = png.GetOutput()
        w, h, _ = image.GetDimensions()
        pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3]
        np.save(os.path.join(args.output, f"{name}.npy"), pixels)


def scale_set_camera(view, center, distance, angle_degrees):
    a = math.radians(angle_degrees)
    view.CameraFocalPoint = list(center)
    view.CameraPosition = [center[0] + distance * math.sin(a), center[1] - distance * math.cos(a),
                           center[2] + 0.3 * distance]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraViewAngle = 30
    view.CameraParallelProjection = 0


def scale_main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--tck", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--size", type=int, nargs=2, default=[1920, 1080])
    parser.add_argument("--frames", type=int, default=3, help="steady frames after the first")
    parser.add_argument("--radius", type=float, default=0.3)
    parser.add_argument("--extent", type=float, default=60.0, help="half the data's box (mm)")
    parser.add_argument("--grid", type=int, nargs=3, default=[64, 64, 128],
                        help="radial, polar, azimuthal cells of the spherical field; 0 0 0: none")
    args = parser.parse_args()
    controller = vtkMultiProcessController.GetGlobalController()
    rank = controller.GetLocalProcessId() if controller else 0
    ranks = controller.GetNumberOfProcesses() if controller else 1
    os.makedirs(args.output, exist_ok=True)
    LoadPlugin(args.plugin)
    record = {"rank": rank, "ranks": ranks, "width": args.size[0], "height": args.size[1],
              "rss_loaded": scale_rss_bytes()}

    view = CreateView("RenderView")
    view.ViewSize = list(args.size)
    view.OrientationAxesVisibility = 0
    view.Background = [0.1, 0.1, 0.15]
    view.UseColorPaletteForBackground = 0
    view.UseFXAA = 0
    SetActiveView(view)

    reader = OpenDataFile(args.tck)
    rep = Show(reader, view)
    rep.Representation = "Sightline Tubes"
    rep.ColorArrayName = ["POINTS", ""]
    rep.TubeRadius = args.radius
    # The first Render() resets the camera to the bounds; the frames below set their own.
    center, distance = [0.0, 0.0, 0.0], 3.2 * args.extent
    started = time.perf_counter()
    Render(view)
    scale_set_camera(view, center, distance, 0.0)
    Render(view)
    first = time.perf_counter() - started
    mapper = scale_mapper(rep)
    points, cells, piece_bytes = scale_piece(reader)
    record.update({
        "points": points, "streamlines": cells, "links": int(mapper.GetNumberOfLinks()),
        "piece_bytes": piece_bytes,
        "geometry_bytes": int(mapper.GetGeometryMemoryBytes()),
        "bvh_bytes": int(mapper.GetBVHMemoryBytes()),
        "geometry_seconds": mapper.GetLastGeometrySeconds(),
        "bvh_seconds": mapper.GetLastBuildSeconds(),
        "first_frame_seconds": first,
        "rss_tubes": scale_rss_bytes(),
        "distributed": int(view.GetClientSideObject().GetUseDistributedRenderingForRender()),
    })
    frames, traces = [], []
    for frame in range(args.frames):
        scale_set_camera(view, center, distance, 5.0 * (frame + 1))
        started = time.perf_counter()
        Render(view)
        frames.append(time.perf_counter() - started)
        traces.append(mapper.GetLastFrameSeconds())
    record["frame_seconds"] = frames
    record["trace_seconds"] = traces

    # The image of the last frame's camera, for the driver (rank 0 holds the composited image).
    scale_save_image(view, args, rank, "tubes")

    if all(args.grid):
        grid = pvs.SightlineSphericalField(Field="PREM Density", RadialResolution=args.grid[0],
                                       PolarResolution=args.grid[1],
                                       AzimuthalResolution=args.grid[2])
        started = time.perf_counter()
        grid.UpdatePipeline()
        record["grid_seconds"] = time.perf_counter() - started
        grid_points, grid_cells, grid_bytes = scale_piece(grid)
        record.update({"grid_points": grid_points, "grid_cells": grid_cells,
                       "grid_bytes": grid_bytes})
        rep.Visibility = 0
        volume = Show(grid, view)
        volume.Representation = "Sightline Spherical Volume"
        pvs.ColorBy(volume, ("CELLS", "density"))
        # One fixed range: with --symmetric each rank would rescale to its own piece's range.
        lut = pvs.GetColorTransferFunction("density")
        lut.ApplyPreset("Inferno (matplotlib)", True)
        lut.RescaleTransferFunction(1.0, 13.1)
        pvs.GetOpacityTransferFunction("density").RescaleTransferFunction(1.0, 13.1)
        volume.ScalarOpacityUnitDistance = 0.3
        started = time.perf_counter()
        scale_set_camera(view, [0.0, 0.0, 0.0], 3.6, 0.0)
        Render(view)
        record["volume_first_seconds"] = time.perf_counter() - started
        volume_mapper = volume.GetClientSideObject().GetActiveRepresentation().GetSphericalVolumeMapper()
        drawn = volume_mapper.GetInputDataObject(0, 0)
        record.update({"volume_cells": drawn.GetNumberOfCells() if drawn else 0,
                       "volume_bytes": drawn.GetActualMemorySize() * 1024 if drawn else 0})
        volume_frames, volume_traces = [], []
        for frame in range(args.frames):
            scale_set_camera(view, [0.0, 0.0, 0.0], 3.6, 5.0 * (frame + 1))
            started = time.perf_counter()
            Render(view)
            volume_frames.append(time.perf_counter() - started)
            volume_traces.append(volume_mapper.GetLastFrameSeconds())
        record["volume_frame_seconds"] = volume_frames
        record["volume_trace_seconds"] = volume_traces
        scale_save_image(view, args, rank, "volume")
    record["rss_end"] = scale_rss_bytes()
    with open(os.path.join(args.output, f"{rank}.json"), "w") as stream:
        json.dump(record, stream, indent=1)
    Delete(view)  # (left to exit, the view's window made Mesa report GLXBadContext)


# No sys.exit(): pvbatch then leaves without MPI_Finalize and mpirun reports the job as failed.
scale_main()
