# SPDX-License-Identifier: BSD-3-Clause
"""Spherical-grid volumes from Python: the source and the volume mapper wrapped in the sightline
package, a projection-free check of the step function's shells through the GL-free renderer
(opacity per pixel against sphere chords), numpy input with degrees and latitude, and errors."""
import math
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
import vtk

import sightline


def parallel_camera(scale=1.1):
    camera = vtk.vtkCamera()
    camera.SetPosition(0, 0, 10)
    camera.SetFocalPoint(0, 0, 0)
    camera.ParallelProjectionOn()
    camera.SetParallelScale(scale)
    camera.SetClippingRange(6, 14)
    return camera


def volume_of(mapper, opacity_of_value, unit=1.0):
    color = vtk.vtkColorTransferFunction()
    color.AddRGBPoint(0.0, 1.0, 1.0, 1.0)
    opacity = vtk.vtkPiecewiseFunction()
    for value, alpha in opacity_of_value:
        opacity.AddPoint(value, alpha)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(unit)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    return volume


def render(volume, size=48):
    renderer = sightline.vtkSightlineImageRenderer()
    renderer.AddVolume(volume)
    renderer.SetActiveCamera(parallel_camera())
    renderer.SetSize(size, size)
    renderer.Update()
    out = renderer.GetOutput()
    rgba = vtk_to_numpy(out.GetPointData().GetScalars()).reshape(size, size, 4)
    return rgba[..., 0].astype(float) / 255.0


def chord(radius, b2):
    return 2.0 * np.sqrt(np.maximum(radius * radius - b2, 0.0))


class SphericalVolumeTest(unittest.TestCase):
    def test_step_function_shells_match_sphere_chords(self):
        # chi_0.5: value 2 inside r = 1/2, 1 out to r = 1; opacity only where the value is 2
        # (a ball of radius 1/2) or only where it is 1 (the shell).
        source = sightline.vtkSightlineSphericalFieldSource()
        source.SetRadialResolution(8)
        source.SetPolarResolution(8)
        source.SetAzimuthalResolution(16)
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputConnection(source.GetOutputPort())
        size = 48
        centres = (np.arange(size) + 0.5) / size * 2.2 - 1.1
        b2 = centres[None, :] ** 2 + centres[:, None] ** 2
        tau = -math.log(1.0 - 0.5)
        for opacity, length in (
            (((1.4, 0.0), (1.6, 0.5), (2.0, 0.5)), chord(0.5, b2)),
            (((1.0, 0.5), (1.4, 0.5), (1.6, 0.0)), chord(1.0, b2) - chord(0.5, b2)),
        ):
            image = render(volume_of(mapper, opacity))
            expected = 1.0 - np.exp(-tau * length)
            self.assertLessEqual(np.abs(image - expected).max(), 1.0 / 255 + 1e-9)

    def test_numpy_grid_in_degrees_and_latitude(self):
        r = np.linspace(0.0, 1.0, 5)
        latitude = np.linspace(-90.0, 90.0, 7)
        azimuth = np.linspace(0.0, 360.0, 13)
        grid = vtk.vtkRectilinearGrid()
        grid.SetDimensions(len(r), len(latitude), len(azimuth))
        grid.SetXCoordinates(numpy_to_vtk(r, deep=True))
        grid.SetYCoordinates(numpy_to_vtk(latitude, deep=True))
        grid.SetZCoordinates(numpy_to_vtk(azimuth, deep=True))
        values = numpy_to_vtk(np.ones(grid.GetNumberOfCells()), deep=True)
        values.SetName("ones")
        grid.GetCellData().SetScalars(values)
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputData(grid)
        mapper.SetAngleUnitsToDegrees()
        mapper.SetPolarAngleToLatitude()
        self.assertEqual(mapper.GetBounds(), (-1.0, 1.0, -1.0, 1.0, -1.0, 1.0))
        image = render(volume_of(mapper, ((0.0, 0.3), (2.0, 0.3))))
        centres = (np.arange(48) + 0.5) / 48 * 2.2 - 1.1
        b2 = centres[None, :] ** 2 + centres[:, None] ** 2
        expected = 1.0 - np.exp(math.log(0.7) * chord(1.0, b2))
        self.assertLessEqual(np.abs(image - expected).max(), 1.0 / 255 + 1e-9)
        self.assertIn("latitude", str(mapper))

    def test_errors_name_the_problem(self):
        grid = vtk.vtkRectilinearGrid()
        grid.SetDimensions(2, 2, 2)
        grid.SetXCoordinates(numpy_to_vtk(np.array([0.0, 1.0]), deep=True))
        grid.SetYCoordinates(numpy_to_vtk(np.array([0.0, 200.0]), deep=True))  # degrees, > 180
        grid.SetZCoordinates(numpy_to_vtk(np.array([0.0, 90.0]), deep=True))
        values = numpy_to_vtk(np.ones(1), deep=True)
        grid.GetCellData().SetScalars(values)
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputData(grid)
        mapper.SetAngleUnitsToDegrees()
        messages = []

        @vtk.calldata_type(vtk.VTK_STRING)
        def on_error(obj, event, message):
            messages.append(message)

        mapper.AddObserver(vtk.vtkCommand.ErrorEvent, on_error)
        image = render(volume_of(mapper, ((0.0, 0.5), (2.0, 0.5))), size=8)
        self.assertEqual(image.max(), 0.0)
        self.assertTrue(any("polar angle" in m and "degrees" in m for m in messages), messages)

        # A valid grid without scalars.
        grid.SetYCoordinates(numpy_to_vtk(np.array([0.0, 180.0]), deep=True))
        grid.GetCellData().Initialize()
        grid.Modified()
        messages.clear()
        render(volume_of(mapper, ((0.0, 0.5), (2.0, 0.5))), size=8)
        self.assertTrue(any("no scalars" in m for m in messages), messages)


if __name__ == "__main__":
    unittest.main()
