#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""A layered Earth ray-cast natively on its spherical grid.

The density of the Preliminary Reference Earth Model (PREM: A. M. Dziewonski and D. L.
Anderson, Physics of the Earth and Planetary Interiors 25 (1981) 297-356) on a non-uniform
(r, theta, phi) grid whose radial breakpoints include every PREM layer boundary, with a
degree-2 lateral perturbation of the mantle density (sin^2(theta) cos(2 phi), 5 %), the kind
of pattern seismic tomography images. A quarter of the globe is cut away (the grid is a
270-degree wedge), the mantle and outer core are a shell from the inner-core boundary out,
and the inner core is an opaque sphere inside the volume, and a latitude/longitude graticule
of ordinary VTK lines lies just above the surface on the side facing the camera.

vtkSightlineSphericalVolumeMapper traverses every pixel's ray exactly through the grid's
cells (spheres, cones and half-planes), so layer boundaries stay sharp at any zoom, with no
resampling to a Cartesian image.

Two images: earth_window.png (a VTK window, offscreen) and earth_gl_free.png (the same scene
through vtkSightlineImageRenderer, no OpenGL: the inner core is an exact Sightline sphere in
both, the graticule lines are OpenGL lines and only in the window).

Usage: /usr/bin/python3 render_earth.py [FILE.vtr] [--output DIR] [--size W H]
         [--resolution NR NTHETA NPHI] [--perturbation A] [--shade] [--interactive]
(FILE.vtr: your own spherical grid instead of PREM, coloured over its value range;
--interactive opens the window on a display afterwards; the mapper traces every second pixel
while the view is dragged.)
"""
import argparse
import math
import os
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

import sightline
from sightline.view import ViewError, angles_in_degrees, ramp_volume_property, read_grid

INNER_CORE_KM = 1221.5
EARTH_KM = 6371.0


def transfer_functions():
    """Colour and opacity by density (g/cm^3): crust and mantle warm, core cool."""
    color = vtk.vtkColorTransferFunction()
    for density, rgb in (
        (1.0, (0.55, 0.75, 0.95)),   # ocean
        (2.6, (0.55, 0.45, 0.35)),   # crust
        (3.3, (0.95, 0.85, 0.45)),   # upper mantle
        (4.0, (0.98, 0.62, 0.25)),   # transition zone
        (4.5, (0.90, 0.35, 0.15)),   # top of the lower mantle
        (5.6, (0.60, 0.10, 0.15)),   # base of the mantle
        (9.9, (0.25, 0.45, 0.85)),   # outer core
        (12.2, (0.55, 0.80, 1.00)),
    ):
        color.AddRGBPoint(density, *rgb)
    opacity = vtk.vtkPiecewiseFunction()
    opacity.AddPoint(1.0, 0.0)
    opacity.AddPoint(2.5, 0.15)
    opacity.AddPoint(3.3, 0.35)
    opacity.AddPoint(5.6, 0.55)
    opacity.AddPoint(9.9, 0.06)
    opacity.AddPoint(12.2, 0.10)
    return color, opacity


def graticule(radius, step_degrees=30):
    """Parallels and meridians as polylines on a sphere (vtkSightlineGraticuleSource)."""
    source = sightline.vtkSightlineGraticuleSource()
    source.SetRadius(radius)
    source.SetStep(step_degrees)
    source.Update()
    return source.GetOutput()


def front_graticule(camera, radius, color=(0.85, 0.9, 1.0)):
    """The graticule as an actor that shows only the hemisphere cap the camera can see.

    Lines on the far side would otherwise show through the translucent limb, where little
    material lies in front of them: near a pole a dozen meridians converge there and read as
    light streaks on the globe. A clipping plane keeps the cap in front of the silhouette,
    p . c > radius^2 / |c| for a camera at c (perspective), or p . c > 0 (parallel), and follows
    the camera as it moves."""
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(graticule(radius))
    plane = vtk.vtkPlane()
    mapper.AddClippingPlane(plane)

    def follow(*_):
        position = camera.GetPosition()
        distance = math.sqrt(sum(x * x for x in position))
        normal = [x / distance for x in position]
        offset = 0.0 if camera.GetParallelProjection() else radius * radius / distance
        plane.SetNormal(*normal)
        plane.SetOrigin(*(offset * n for n in normal))

    follow()
    camera.AddObserver(vtk.vtkCommand.ModifiedEvent, follow)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    actor.GetProperty().SetLineWidth(1.5)
    actor.GetProperty().LightingOff()
    return actor


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", nargs="?", metavar="FILE.vtr",
                        help="your own spherical grid: a VTK XML rectilinear grid whose x, y, z "
                             "are r, the polar angle (colatitude) and the azimuth, in radians or "
                             "degrees (default: the PREM Earth from the field source)")
    parser.add_argument("--output", default="output")
    parser.add_argument("--size", type=int, nargs=2, default=(1200, 1000))
    parser.add_argument("--resolution", type=int, nargs=3, default=(120, 90, 180),
                        help="cells along r, theta, phi (the whole sphere's share for phi)")
    parser.add_argument("--perturbation", type=float, default=0.05)
    parser.add_argument("--shade", action="store_true", help="gradient shading of the cells")
    parser.add_argument("--interactive", action="store_true",
                        help="then open the window and let the view be rotated (needs a display)")
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)

    if args.file:
        # The user's own spherical grid (r, theta, phi), read by sightline-view's loader.
        try:
            grid, scalars, _ = read_grid(args.file)
        except ViewError as error:
            raise SystemExit(f"error: {error}") from None
        degrees = angles_in_degrees(grid)
        radii = vtk_to_numpy(grid.GetXCoordinates())
        outer = float(np.abs(radii).max())
        print(f"earth: {grid.GetNumberOfCells()} cells of '{scalars.GetName()}' from {args.file} "
              f"(angles in {'degrees' if degrees else 'radians'})")
    else:
        source = sightline.vtkSightlineSphericalFieldSource()
        source.SetFieldToPREMDensity()
        # The field is PREM with RadiusRange[1] as the Earth's radius: kilometres here.
        source.SetRadiusRange(INNER_CORE_KM, EARTH_KM)
        nr, nt, nphi = args.resolution
        source.SetRadialResolution(nr)
        source.SetPolarResolution(nt)
        source.SetAzimuthalResolution(nphi * 3 // 4)
        source.SetAzimuthRange(0.0, 1.5 * math.pi)  # a quarter cut away
        source.SetPerturbationAmplitude(args.perturbation)
        start = time.perf_counter()
        source.Update()
        grid, degrees, outer = source.GetOutput(), False, EARTH_KM
        print(f"earth: {grid.GetNumberOfCells()} cells, {grid.GetDimensions()[0] - 1} shells "
              f"(PREM boundaries included), sampled in {time.perf_counter() - start:.2f} s")

    mapper = sightline.vtkSightlineSphericalVolumeMapper()
    mapper.SetInputDataObject(grid)
    if degrees:
        mapper.SetAngleUnitsToDegrees()
    if args.file:  # a colour ramp over the data's range
        prop = ramp_volume_property(*scalars.GetRange())
        prop.SetScalarOpacityUnitDistance(outer / 16.0)
    else:
        color, opacity = transfer_functions()
        prop = vtk.vtkVolumeProperty()
        prop.SetColor(color)
        prop.SetScalarOpacity(opacity)
        prop.SetScalarOpacityUnitDistance(400.0)  # km
    if args.shade:
        prop.ShadeOn()
        prop.SetAmbient(0.4)
        prop.SetDiffuse(0.7)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    # The inner core: an exact Sightline sphere, so the GL-free image has it too.
    core_points = vtk.vtkPolyData()
    core_points.SetPoints(vtk.vtkPoints())
    core_points.GetPoints().InsertNextPoint(0, 0, 0)
    core_radius = vtk.vtkDoubleArray()
    core_radius.SetName("radius")
    core_radius.InsertNextValue(INNER_CORE_KM)
    core_points.GetPointData().AddArray(core_radius)
    core_mapper = sightline.vtkSightlineSphereMapper()
    core_mapper.SetInputDataObject(core_points)
    core_mapper.SetRadiusArrayName("radius")
    core = vtk.vtkActor()
    core.SetMapper(core_mapper)
    core.GetProperty().SetColor(0.95, 0.95, 0.85)
    core.GetProperty().SetSpecular(0.3)

    renderer = vtk.vtkRenderer()
    renderer.SetBackground(0.02, 0.02, 0.05)
    if not args.file:  # PREM's inner core; a user's grid is drawn on its own
        renderer.AddActor(core)
    renderer.AddVolume(volume)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(2.4 * outer, -2.9 * outer, 1.5 * outer)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    camera.Dolly(1.25)
    renderer.ResetCameraClippingRange()
    lines = front_graticule(camera, outer * 1.003)
    renderer.AddActor(lines)

    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(*args.size)
    start = time.perf_counter()
    window.Render()
    print(f"window: {time.perf_counter() - start:.2f} s first frame (ray casting "
          f"{mapper.GetLastFrameSeconds():.2f} s, {mapper.GetLastCellsVisited()} cell segments)")
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(os.path.join(args.output, "earth_window.png"))
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()

    image = sightline.vtkSightlineImageRenderer()
    if not args.file:
        image.AddActor(core)
    image.AddVolume(volume)
    image.SetActiveCamera(camera)
    image.SetSize(*args.size)
    image.SetBackground(*renderer.GetBackground())
    start = time.perf_counter()
    image.Update()
    print(f"gl-free: {time.perf_counter() - start:.2f} s")
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(os.path.join(args.output, "earth_gl_free.png"))
    writer.SetInputConnection(image.GetOutputPort())
    writer.Write()
    print("wrote", os.path.join(args.output, "earth_window.png"), "and earth_gl_free.png")
    if args.interactive:
        window.SetOffScreenRendering(0)
        interactor = vtk.vtkRenderWindowInteractor()
        interactor.SetRenderWindow(window)
        interactor.SetInteractorStyle(vtk.vtkInteractorStyleTrackballCamera())
        window.Render()
        interactor.Start()


if __name__ == "__main__":
    main()
