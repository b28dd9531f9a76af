#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Sightline's main job on real data: the tractography bundles DIPY ships
(minimal_bundles.zip: arcuate fasciculus, corticospinal tract and forceps major of five
subjects), every streamline vertex drawn as an exact ray-traced sphere coloured by the local
fibre direction (red: left-right, green: anterior-posterior, blue: inferior-superior).

It renders twice:
  - in a VTK render window (offscreen), composited with an ordinary VTK outline actor;
  - without OpenGL through vtkSightlineImageRenderer, the batch path;
and writes both PNGs to the output folder.

Usage: /usr/bin/python3 render_tractography.py [FILE ...] [--output DIR] [--size W H]
         [--subject N] [--radius MM]
FILE: your own .trk (TrackVis) or .tck (MRtrix3) files instead of DIPY's bundles.
Needs python3-dipy (for the default data file).
"""
import argparse
import os
import tempfile
import time
import zipfile

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline
from sightline.view import ViewError, lower_extension, read_tubes

BUNDLES = ("AF_L", "CST_R", "CC_ForcepsMajor")


def find_bundles_zip():
    import dipy.data

    path = os.path.join(os.path.dirname(dipy.data.__file__), "files", "minimal_bundles.zip")
    if not os.path.exists(path):
        raise SystemExit(f"DIPY's minimal_bundles.zip is missing ({path}): apt-get install python3-dipy")
    return path


def load_streamlines(paths):
    """Vertices (RAS+ mm) and direction colours of every streamline of the .trk/.tck files,
    read with Sightline's readers by sightline-view's loader; a bad file exits naming it."""
    vertices, colors = [], []
    for path in paths:
        if lower_extension(path) not in (".trk", ".tck"):
            raise SystemExit(f"error: {path}: not a .trk or .tck streamline file")
        try:
            lines = read_tubes(path)
        except ViewError as error:
            raise SystemExit(f"error: {error}") from None
        vertices.append(vtk_to_numpy(lines.GetPoints().GetData()).astype(np.float64))
        colors.append(vtk_to_numpy(lines.GetPointData().GetScalars()))
    return np.concatenate(vertices), np.concatenate(colors)


def bundle_files(folder, subject):
    with zipfile.ZipFile(find_bundles_zip()) as archive:
        archive.extractall(folder)
    return [os.path.join(folder, f"sub_{subject}", f"{bundle}.trk") for bundle in BUNDLES]


def make_sphere_cloud(vertices, direction_colors, radius):
    points = vtk.vtkPoints()
    points.SetData(numpy_to_vtk(vertices, deep=True))
    cloud = vtk.vtkPolyData()
    cloud.SetPoints(points)
    colors = numpy_to_vtk(direction_colors, deep=True)
    colors.SetName("direction")
    cloud.GetPointData().SetScalars(colors)
    radii = numpy_to_vtk(np.full(len(vertices), radius), deep=True)
    radii.SetName("radius")
    cloud.GetPointData().AddArray(radii)
    return cloud


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("files", nargs="*", metavar="FILE",
                        help="your own .trk or .tck files (default: DIPY's bundles)")
    parser.add_argument("--output", default="output", help="folder for the images (default: output)")
    parser.add_argument("--size", type=int, nargs=2, default=(1600, 1000), metavar=("W", "H"))
    parser.add_argument("--subject", type=int, default=1, choices=range(1, 6))
    parser.add_argument("--radius", type=float, default=1.2, help="sphere radius in mm")
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    width, height = args.size

    if args.files:
        vertices, colors = load_streamlines(args.files)
        source = ", ".join(os.path.basename(path) for path in args.files)
    else:
        with tempfile.TemporaryDirectory() as folder:
            vertices, colors = load_streamlines(bundle_files(folder, args.subject))
        source = f"subject {args.subject}: {', '.join(BUNDLES)}"
    cloud = make_sphere_cloud(vertices, colors, args.radius)

    mapper = sightline.vtkSightlineSphereMapper()
    mapper.SetInputDataObject(cloud)
    mapper.SetRadiusArrayName("radius")
    mapper.SetColorModeToDirectScalars()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetAmbient(0.15)
    actor.GetProperty().SetSpecular(0.3)
    actor.GetProperty().SetSpecularPower(25)

    # An ordinary VTK actor in the same window: the bounding box of the streamlines.
    outline = vtk.vtkOutlineFilter()
    outline.SetInputData(cloud)
    outline_mapper = vtk.vtkPolyDataMapper()
    outline_mapper.SetInputConnection(outline.GetOutputPort())
    outline_actor = vtk.vtkActor()
    outline_actor.SetMapper(outline_mapper)
    outline_actor.GetProperty().SetColor(0.7, 0.7, 0.7)

    renderer = vtk.vtkRenderer()
    renderer.AddActor(actor)
    renderer.AddActor(outline_actor)
    renderer.SetBackground(0.08, 0.08, 0.1)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(width, height)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(-1, -0.35, 0.25)  # from the left, slightly behind and above
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Zoom(1.15)
    renderer.ResetCameraClippingRange()

    start = time.perf_counter()
    window.Render()
    window_seconds = time.perf_counter() - start
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtk.vtkPNGWriter()
    writer.SetInputConnection(grab.GetOutputPort())
    window_png = os.path.join(args.output, "tractography_window.png")
    writer.SetFileName(window_png)
    writer.Write()

    batch = sightline.vtkSightlineImageRenderer()
    batch.AddActor(actor)
    batch.SetActiveCamera(camera)
    batch.SetSize(width, height)
    batch.SetBackground(renderer.GetBackground())
    start = time.perf_counter()
    batch.Update()
    batch_seconds = time.perf_counter() - start
    batch_png = os.path.join(args.output, "tractography_gl_free.png")
    writer = vtk.vtkPNGWriter()
    writer.SetInputConnection(batch.GetOutputPort())
    writer.SetFileName(batch_png)
    writer.Write()

    print(f"spheres: {mapper.GetNumberOfPrimitives()} ({source})")
    print(f"BVH build: {mapper.GetLastBuildSeconds() * 1e3:.1f} ms")
    print(f"window frame ({width}x{height}, first render incl. BVH and GL setup): {window_seconds * 1e3:.1f} ms")
    print(f"GL-free frame: {batch_seconds * 1e3:.1f} ms (ray tracing {mapper.GetLastFrameSeconds() * 1e3:.1f} ms)")
    print(f"wrote {window_png} and {batch_png}")


if __name__ == "__main__":
    main()
