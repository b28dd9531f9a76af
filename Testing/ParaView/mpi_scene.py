# SPDX-License-Identifier: BSD-3-Clause
"""The scenes of ParaView.MPI, run by `mpirun -np N pvbatch` (test_mpi.py starts it for N = 1, 2, 4).

pvbatch runs this script on rank 0; every rank holds a piece of each filter's output and renders
it, and IceT composites the ranks' colour and depth into rank 0's image. The TrackVis reader
gives each rank its own run of streamlines (file order); RedistributeDataSet then regroups them
by region, each streamline kept whole on one rank ("Assign to one region"), as an unstructured
grid of poly-line cells.

A ProgrammableFilter after each data source records every rank's own piece (its points, cell
count and rank) as NAME-piece-RANK.npz in --output, so the driver checks what each rank held.
Each scene is saved as PNG and as .npy pixels under the same explicit camera.

The functions are prefixed mpi_: a ProgrammableFilter's script runs in this script's namespace on
rank 0 and star-imports numpy there, which replaced functions named save() and record().

Scenes: Spheres (the streamlines' points, redistributed), Tubes (the streamlines, opaque,
redistributed), TubesSplit (the same with RedistributeDataSet cutting streamlines at the regions'
boundaries), Ranks (the tubes coloured by rank: vtkProcessId through a LUT), ReaderPieces (the
reader's own pieces as they are), EmptyRanks (an SWC neuron: the SWC reader puts the whole file
on rank 0, the other ranks hold nothing). With --bad-rank R (and
--scene-set bad): the redistributed points with a radius array that is NaN on rank R only.
"""
import argparse
import json
import math
import os
import sys

from paraview.simple import (ColorBy, Delete, GetColorTransferFunction, Hide, LoadPlugin,
                             OpenDataFile, ProcessIdScalars, ProgrammableFilter,
                             RedistributeDataSet, Render, SaveScreenshot, Show)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paraview_test_support as support  # noqa: E402
import numpy as np
import sightline  # noqa: F401  (wraps the representations' mappers for mpi_drawn_points)

SIZE = (640, 480)
# The explicit camera (CST_R.trk of DIPY's minimal_bundles, sub_1): the same for every rank count.
# Its points span x 5.8..38.5, y -57.3..21.2, z -81.4..52.5 (mm): seen from the right, a little
# from the front and above, 270 mm from the middle.
FOCAL_POINT = [22.0, -18.0, -14.0]
POSITION = [272.0, -118.0, 16.0]
VIEW_UP = [0.0, 0.0, 1.0]

# Runs on every rank (a ProgrammableFilter executes where its piece is): passes the piece on and
# saves what this rank holds.
RECORD = """
import numpy as np
from vtkmodules.vtkParallelCore import vtkMultiProcessController
from vtkmodules.util.numpy_support import vtk_to_numpy
source = self.GetInputDataObject(0, 0)
out = self.GetOutputDataObject(0)
out.ShallowCopy(source)
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller else 0
size = controller.GetNumberOfProcesses() if controller else 1
points = source.GetPoints()
xyz = vtk_to_numpy(points.GetData()).astype(float) if points is not None else np.zeros((0, 3))
np.savez("{folder}/{name}-piece-%d.npz" % rank, points=xyz, cells=source.GetNumberOfCells(),
         rank=rank, size=size)
{extra}
"""

# A radius per point, NaN on one rank only: that rank's spheres are bad input.
BAD_RADIUS = """
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
radius = np.full(source.GetNumberOfPoints(), {radius})
if rank == {bad_rank}:
    radius[:] = np.nan
array = numpy_to_vtk(radius, deep=1)
array.SetName("radius")
out.GetPointData().AddArray(array)
"""


def mpi_record(source, folder, name, extra=""):
    script = RECORD.format(folder=folder, name=name, extra=extra)
    return ProgrammableFilter(Input=source, Script=script, CopyArrays=1)


def mpi_show(source, view, representation, **properties):
    """`source` shown in `view` as a Sightline representation in solid colour, with `properties`."""
    rep = Show(source, view)
    rep.Representation = representation
    rep.ColorArrayName = ["POINTS", ""]  # Solid Color
    for name, value in properties.items():
        setattr(rep, name, value)
    return rep


def mpi_make_view():
    return support.make_view(SIZE)


def mpi_drawn_points(rep):
    """Points in the input rank 0's Sightline mapper traced for `rep` (its own piece)."""
    mapper = rep.GetClientSideObject().GetActiveRepresentation().GetSightlineMapper()
    data = mapper.GetInputDataObject(0, 0)
    if data is None:
        return 0
    if data.IsA("vtkCompositeDataSet"):
        total, it = 0, data.NewIterator()
        it.InitTraversal()
        while not it.IsDoneWithTraversal():
            total += it.GetCurrentDataObject().GetNumberOfPoints()
            it.GoToNextItem()
        return total
    return data.GetNumberOfPoints()


def mpi_save_view(view, folder, name, rep=None, camera=None):
    # paraview.simple resets the camera to the bounds on a view's first Render(): set the
    # camera after it, so that every rank count renders from the same one.
    Render(view)
    focal_point, position, view_up = camera or (FOCAL_POINT, POSITION, VIEW_UP)
    view.CameraFocalPoint = focal_point
    view.CameraPosition = position
    view.CameraViewUp = view_up
    view.CameraViewAngle = 30
    view.CameraParallelProjection = 0
    Render(view)
    if rep is not None:
        # Where the view rendered (distributed: every rank its piece, IceT compositing) and
        # what rank 0 traced, for the driver to check against rank 0's piece.
        distributed = view.GetClientSideObject().GetUseDistributedRenderingForRender()
        print(f"{name}: distributed rendering {int(distributed)}, rank 0 traced "
              f"{mpi_drawn_points(rep)} points", flush=True)
    path = os.path.join(folder, f"{name}.png")
    SaveScreenshot(path, view, ImageResolution=list(SIZE), TransparentBackground=0)
    pixels = support.read_png(path)
    np.save(os.path.join(folder, f"{name}.npy"), pixels)
    print(f"{name}: {path}", flush=True)


def mpi_region(rep):
    """Rank 0's region as its Sightline mapper clips to it (all of space on one rank)."""
    return rep.GetClientSideObject().GetActiveRepresentation().GetSightlineMapper().GetRegion()


def mpi_border_camera(rep, args):
    """A camera whose view direction lies in a plane between two ranks' regions: a finite face of
    rank 0's region. Several ranks write it to border_camera.json; --border-camera reads it, so
    that every rank count renders from the same one."""
    if args.border_camera:
        with open(args.border_camera) as f:
            return json.load(f)
    region = mpi_region(rep)
    faces = [i for i, value in enumerate(region) if math.isfinite(value)]
    if not faces:
        return None
    axis, plane = faces[0] // 2, region[faces[0]]
    focal_point = list(FOCAL_POINT)
    focal_point[axis] = plane
    position = list(focal_point)
    position[(axis + 1) % 3] += 280.0  # a view direction in the plane
    view_up = [0.0, 0.0, 0.0]
    view_up[axis] = 1.0
    camera = [focal_point, position, view_up]
    with open(os.path.join(args.output, "border_camera.json"), "w") as f:
        json.dump(camera, f)
    print(f"border camera: the plane {'xyz'[axis]} = {plane:.3f} of rank 0's region {region}",
          flush=True)
    return camera


def mpi_translucent(args, view, reader, split):
    """Translucent tubes: the ranks' layers blended in visibility order (ordered compositing)."""
    # The reader's own pieces: runs of streamlines in file order, interleaved in space; the
    # representation sends every link to each region it reaches into.
    rep = mpi_show(reader, view, "Sightline Tubes", TubeRadius=0.6, Opacity=0.4)
    mpi_save_view(view, args.output, "Translucent", rep)
    print(f"Translucent: rank 0's region {mpi_region(rep)}", flush=True)
    camera = mpi_border_camera(rep, args)
    mpi_save_view(view, args.output, "TranslucentBorder", rep, camera=camera)
    # From the front and below: the regions' order along the rays reversed.
    mpi_save_view(view, args.output, "TranslucentBelow", rep,
                  camera=(FOCAL_POINT, [22.0, 232.0, -164.0], [0.0, 0.0, 1.0]))
    # With opaque spheres in the same view: they are drawn by region too.
    mpi_show(split, view, "Sightline Spheres", SphereRadius=0.5, DiffuseColor=[0.9, 0.6, 0.3])
    mpi_save_view(view, args.output, "TranslucentWithSpheres", rep)
    Hide(split, view)
    Hide(reader, view)

    # A bifurcating tree (an SWC neuron, all of it on rank 0 as the SWC reader gives it) from its
    # predecessor array, crossing the regions' borders.
    neuron = OpenDataFile(args.swc)
    rep = mpi_show(neuron, view, "Sightline Tubes", TubeRadiusArray=["POINTS", "Radius"],
                   TubePredecessorArray=["POINTS", "ParentIndex"], Opacity=0.5)
    for name, camera in (("TranslucentTree", ([-2.0, 2.0, 0.0], [-2.0, 2.0, 60.0], [0.0, 1.0, 0.0])),
                         ("TranslucentTreeSide", ([-2.0, 2.0, 0.0], [50.0, 20.0, 20.0], [0.0, 1.0, 0.0]))):
        mpi_save_view(view, args.output, name, rep, camera=camera)
    print(f"TranslucentTree: rank 0's region {mpi_region(rep)}", flush=True)
    Hide(neuron, view)


def mpi_volume(args, view):
    """A spherical volume on several ranks: PREM's density with a strong lateral perturbation
    (structure on both sides of every border), a wedge cut out. The ranks split the section's
    box into one box each, each rank receives the cells that may meet its box, and IceT blends
    the boxes' images in visibility order (ordered compositing)."""
    import paraview.simple as simple
    source, rep = support.show_prem(view, simple.SightlineSphericalField)
    source.PerturbationAmplitude = 0.6
    rep.RescaleTransferFunctionToDataRange(True)
    rep.ScalarOpacityUnitDistance = 0.3
    representation = rep.GetClientSideObject().GetActiveRepresentation()
    mapper = representation.GetSphericalVolumeMapper()
    for name, camera in (
            ("Volume", ([0.0, 0.0, 0.0], [3.2, -2.4, 1.8], [0.0, 0.0, 1.0])),
            # Every ray in the plane x = 0, the border of the 2- and 4-rank boxes.
            ("VolumeBorder", ([0.0, 0.0, 0.0], [0.0, -3.6, 1.2], [1.0, 0.0, 0.0])),
            ("VolumeBelow", ([0.0, 0.0, 0.0], [-2.6, 2.2, -2.4], [0.0, 0.0, 1.0]))):
        mpi_save_view(view, args.output, name, camera=camera)
        if name == "Volume":
            rep.Shade = 1  # the shading gradients need each cell's neighbours
            mpi_save_view(view, args.output, "VolumeShaded", camera=camera)
            rep.Shade = 0
    report = lambda name: print(
        f"{name}: rank 0's piece {cells(representation.GetInputDataObject(0, 0))} cells, drew "
        f"{cells(mapper.GetInputDataObject(0, 0))} cells in the region {mapper.GetRegion()}",
        flush=True)
    report("Volume")
    # The full sphere with its azimuth seam on -x, inside rank 0's box on 2 and 4 ranks: that
    # box takes the run of cells across the seam (the grid goes on past it), not every azimuth.
    source.AzimuthRange = [math.pi, 3.0 * math.pi]
    camera = ([0.0, 0.0, 0.0], [-3.0, -1.2, 1.6], [0.0, 0.0, 1.0])
    mpi_save_view(view, args.output, "VolumeSphere", camera=camera)
    rep.Shade = 1
    mpi_save_view(view, args.output, "VolumeSphereShaded", camera=camera)
    rep.Shade = 0
    report("VolumeSphere")
    # Point data, interpolated inside the cells: the transfer table must span the whole grid's
    # range on every rank, not each rank's own.
    source.OutputCellData = 0
    source.UpdatePipeline()
    ColorBy(rep, ("POINTS", "density"))
    rep.RescaleTransferFunctionToDataRange(True)
    rep.VolumeSampleDistance = 0.03  # PREM's thinnest layer would make the automatic one tiny
    mpi_save_view(view, args.output, "VolumePoints", camera=camera)
    Hide(source, view)


def cells(data):
    return data.GetNumberOfCells() if data else 0


def mpi_main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--trk", required=True)
    parser.add_argument("--swc", required=True)
    parser.add_argument("--output", required=True)
    parser.add_argument("--bad-rank", type=int, default=None)
    parser.add_argument("--border-camera", default=None,
                        help="JSON camera along a border plane, written by a run on several ranks")
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    LoadPlugin(args.plugin)

    reader = OpenDataFile(args.trk)
    split = RedistributeDataSet(Input=reader)  # Boundary Mode: cells whole on one rank
    view = mpi_make_view()

    if args.bad_rank is not None:
        bad = mpi_record(split, args.output, "BadRadius",
                     BAD_RADIUS.format(radius=0.8, bad_rank=args.bad_rank))
        rep = mpi_show(bad, view, "Sightline Spheres", SphereRadiusArray=["POINTS", "radius"])
        mpi_save_view(view, args.output, "BadRadius", rep)
        # The same points with the constant radius, for the driver's comparison.
        rep.SphereRadiusArray = ["POINTS", ""]
        rep.SphereRadius = 0.8
        mpi_save_view(view, args.output, "GoodRadius")
        Delete(view)  # (left to exit, the view's window made Mesa report GLXBadContext)
        return 0

    points = mpi_record(split, args.output, "Spheres")
    rep = mpi_show(points, view, "Sightline Spheres", SphereRadius=0.8)
    mpi_save_view(view, args.output, "Spheres", rep)
    Hide(points, view)

    rep = mpi_show(split, view, "Sightline Tubes", TubeRadius=0.6)
    mpi_save_view(view, args.output, "Tubes", rep)
    Hide(split, view)

    # Streamlines cut where the ranks' regions meet ("Split cells"): each rank holds its side of
    # a cut link, both ending at the cut point, so the union is the same tube.
    cut = mpi_record(RedistributeDataSet(Input=reader, BoundaryMode="Split cells"), args.output,
                     "TubesSplit")
    # Drawn as chunks of 4 links (the same tubes as combined links), hidden-link culling on (a
    # sparse set: nothing hidden): the panel's properties reach each rank's mapper.
    rep = mpi_show(cut, view, "Sightline Tubes", TubeRadius=0.6, TubeLinkLayout=4, TubeChunkLinks=4,
                   TubeHiddenLinkCulling=1)
    mpi_save_view(view, args.output, "TubesSplit", rep)
    Hide(cut, view)

    ranks = ProcessIdScalars(Input=split)
    rep = Show(ranks, view)
    rep.Representation = "Sightline Tubes"
    rep.TubeRadius = 0.6
    ColorBy(rep, ("POINTS", "ProcessId"))
    lut = GetColorTransferFunction("ProcessId")
    lut.ApplyPreset("Rainbow Uniform", True)
    lut.RescaleTransferFunction(0.0, 3.0)
    mpi_save_view(view, args.output, "Ranks")
    Hide(ranks, view)

    own = mpi_record(reader, args.output, "ReaderPieces")
    rep = mpi_show(own, view, "Sightline Spheres", SphereRadius=0.8)
    mpi_save_view(view, args.output, "ReaderPieces", rep)
    Hide(own, view)

    mpi_translucent(args, view, reader, split)
    mpi_volume(args, view)

    neuron = mpi_record(OpenDataFile(args.swc), args.output, "EmptyRanks")
    rep = mpi_show(neuron, view, "Sightline Spheres", SphereRadiusArray=["POINTS", "Radius"])
    mpi_save_view(view, args.output, "EmptyRanks", rep,
                  camera=([0.0, 0.0, 0.0], [0.0, 0.0, 90.0], [0.0, 1.0, 0.0]))
    Delete(view)  # (left to exit, the view's window made Mesa report GLXBadContext)
    return 0


# No sys.exit(): pvbatch then leaves without MPI_Finalize and mpirun reports the job as failed.
# An exception still makes pvbatch exit non-zero.
mpi_main()
