#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Generalized tubes on real tractography: DIPY's minimal_bundles.zip (arcuate fasciculus,
corticospinal tract and forceps major of one subject), read with Sightline's TrackVis reader
and drawn as exact tubes (spheres at the vertices joined by tangential cone stumps), coloured
by the local fibre direction (red: left-right, green: anterior-posterior, blue:
inferior-superior).

Two images, each rendered in a VTK window (offscreen) and without OpenGL:
  - tubes_opaque_*.png: the three bundles, opaque, with an ordinary VTK outline actor;
  - tubes_translucent_*.png: the corticospinal tract opaque inside the translucent arcuate
    fasciculus and forceps major (opacity 0.3): only the outer surfaces of each translucent
    bundle are blended, where tubes overlap there are no interior surfaces.

Usage: /usr/bin/python3 render_tubes.py [FILE ...] [--output DIR] [--size W H] [--subject N]
         [--radius MM] [--opacity A]
FILE: your own .trk, .tck or .swc files instead of DIPY's bundles (SWC neurons keep their
radii); the first is drawn opaque inside the others in the translucent image.
Needs python3-dipy (for the default data file).
"""
import argparse
import os
import tempfile
import time
import zipfile

import vtk

import sightline
from sightline.view import ViewError, read_tubes

BUNDLES = ("AF_L", "CST_R", "CC_ForcepsMajor")


def find_bundles_zip():
    import dipy.data

    path = os.path.join(os.path.dirname(dipy.data.__file__), "files", "minimal_bundles.zip")
    if not os.path.exists(path):
        raise SystemExit(f"DIPY's minimal_bundles.zip is missing ({path}): apt-get install python3-dipy")
    return path


def read_file(path):
    """One .trk/.tck bundle (polylines in RAS+ mm with direction colours) or .swc neuron, read
    with Sightline's readers by sightline-view's loader; a bad file exits naming it."""
    try:
        return read_tubes(path)
    except ViewError as error:
        raise SystemExit(f"error: {error}") from None


def tube_actor(lines, radius, opacity=1.0):
    mapper = sightline.vtkSightlineTubeMapper()
    mapper.SetInputDataObject(lines)
    if lines.GetPointData().GetArray("ParentIndex"):  # an SWC neuron: a tree with its radii
        mapper.SetPredecessorArrayName("ParentIndex")
        mapper.SetRadiusArrayName("Radius")
    else:
        mapper.SetRadius(radius)
        mapper.SetColorModeToDirectScalars()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetAmbient(0.2)
    prop.SetSpecular(0.3)
    prop.SetSpecularPower(25)
    prop.SetOpacity(opacity)
    return actor


def render_both(actors, extra_actors, width, height, background, name, output):
    """Renders in a window (with the extra ordinary VTK actors) and without OpenGL; returns the
    seconds each took."""
    renderer = vtk.vtkRenderer()
    for actor in actors + extra_actors:
        renderer.AddActor(actor)
    renderer.SetBackground(background)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.SetSize(width, height)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(-1, -0.35, 0.25)  # from the left, slightly behind and above
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Zoom(1.2)
    renderer.ResetCameraClippingRange()
    start = time.perf_counter()
    window.Render()
    window_seconds = time.perf_counter() - start
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtk.vtkPNGWriter()
    writer.SetInputConnection(grab.GetOutputPort())
    writer.SetFileName(os.path.join(output, f"{name}_window.png"))
    writer.Write()

    batch = sightline.vtkSightlineImageRenderer()
    for actor in actors:
        batch.AddActor(actor)
    batch.SetActiveCamera(camera)
    batch.SetSize(width, height)
    batch.SetBackground(background)
    start = time.perf_counter()
    batch.Update()
    batch_seconds = time.perf_counter() - start
    writer = vtk.vtkPNGWriter()
    writer.SetInputConnection(batch.GetOutputPort())
    writer.SetFileName(os.path.join(output, f"{name}_gl_free.png"))
    writer.Write()
    return window_seconds, batch_seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("files", nargs="*", metavar="FILE",
                        help="your own .trk, .tck or .swc files (default: DIPY's bundles)")
    parser.add_argument("--output", default="output", help="folder for the images (default: output)")
    parser.add_argument("--size", type=int, nargs=2, default=(1600, 1000), metavar=("W", "H"))
    parser.add_argument("--subject", type=int, default=1, choices=range(1, 6))
    parser.add_argument("--radius", type=float, default=0.5, help="tube radius in mm (default 0.5)")
    parser.add_argument("--opacity", type=float, default=0.3, help="translucent bundles' opacity")
    args = parser.parse_args()
    if not 0.0 < args.opacity <= 1.0:
        raise SystemExit(f"--opacity must be in (0, 1], got {args.opacity}")
    os.makedirs(args.output, exist_ok=True)
    width, height = args.size
    background = (0.08, 0.08, 0.1)

    if args.files:  # the user's own files: the first opaque inside the others
        names = [os.path.basename(path) for path in args.files]
        if len(set(names)) != len(names):
            names = args.files
        bundles = {name: read_file(path) for name, path in zip(names, args.files)}
        source = ", ".join(names)
    else:
        names = list(BUNDLES)
        with tempfile.TemporaryDirectory() as folder:
            with zipfile.ZipFile(find_bundles_zip()) as archive:
                archive.extractall(folder)
            bundles = {name: read_file(os.path.join(folder, f"sub_{args.subject}", f"{name}.trk"))
                       for name in BUNDLES}
        source = f"subject {args.subject}: {', '.join(BUNDLES)}"

    # Opaque: every bundle, plus an ordinary VTK outline actor in the window.
    opaque = [tube_actor(bundles[name], args.radius) for name in names]
    append = vtk.vtkAppendPolyData()
    for name in names:
        append.AddInputData(bundles[name])
    outline = vtk.vtkOutlineFilter()
    outline.SetInputConnection(append.GetOutputPort())
    outline_mapper = vtk.vtkPolyDataMapper()
    outline_mapper.SetInputConnection(outline.GetOutputPort())
    outline_actor = vtk.vtkActor()
    outline_actor.SetMapper(outline_mapper)
    outline_actor.GetProperty().SetColor(0.7, 0.7, 0.7)
    seconds = render_both(opaque, [outline_actor], width, height, background, "tubes_opaque", args.output)

    # Translucent: the corticospinal tract (or the first file) opaque inside the others (a
    # single file is drawn translucent on its own).
    core = "CST_R" if not args.files else names[0]
    mixed = [tube_actor(bundles[name], args.radius,
                        1.0 if name == core and len(names) > 1 else args.opacity)
             for name in [core] + [name for name in names if name != core]]
    translucent_seconds = render_both(mixed, [outline_actor], width, height, background,
                                      "tubes_translucent", args.output)

    links = sum(actor.GetMapper().GetNumberOfLinks() for actor in opaque)
    lines = sum(bundles[name].GetNumberOfLines() for name in names)
    print(f"tubes: {lines} streamlines, {links} control points ({source})")
    print(f"opaque: window {seconds[0] * 1e3:.1f} ms (first render incl. BVH and GL setup), GL-free {seconds[1] * 1e3:.1f} ms")
    print(f"translucent (opacity {args.opacity}): window {translucent_seconds[0] * 1e3:.1f} ms, GL-free {translucent_seconds[1] * 1e3:.1f} ms")
    print(f"wrote {args.output}/tubes_opaque_window.png, tubes_opaque_gl_free.png, "
          f"tubes_translucent_window.png, tubes_translucent_gl_free.png")


if __name__ == "__main__":
    main()
