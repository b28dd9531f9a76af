# SPDX-License-Identifier: BSD-3-Clause
"""The sightline Python package as a VTK user meets it: import next to vtk, render spheres
without a window and in one, check geometry against closed form, and get clear errors."""
import math
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
import vtk

import sightline


def sphere_cloud(centers, radii=None):
    points = vtk.vtkPoints()
    points.SetData(numpy_to_vtk(np.asarray(centers, dtype=np.float64), deep=True))
    cloud = vtk.vtkPolyData()
    cloud.SetPoints(points)
    if radii is not None:
        array = numpy_to_vtk(np.asarray(radii, dtype=np.float64), deep=True)
        array.SetName("radius")
        cloud.GetPointData().AddArray(array)
    return cloud


def parallel_camera(scale=2.0):
    camera = vtk.vtkCamera()
    camera.SetPosition(0, 0, 10)
    camera.SetFocalPoint(0, 0, 0)
    camera.ParallelProjectionOn()
    camera.SetParallelScale(scale)
    camera.SetClippingRange(6, 14)
    return camera


def render_without_gl(actor, camera, width, height):
    renderer = sightline.vtkSightlineImageRenderer()
    renderer.AddActor(actor)
    renderer.SetActiveCamera(camera)
    renderer.SetSize(width, height)
    renderer.Update()
    image = renderer.GetOutput()
    rgba = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, 4)
    depth = vtk_to_numpy(image.GetPointData().GetArray("Depth")).reshape(height, width)
    return rgba, depth


class SpheresTest(unittest.TestCase):
    def test_package_wraps_the_classes(self):
        mapper = sightline.vtkSightlineSphereMapper()
        self.assertTrue(mapper.IsA("vtkMapper"))
        self.assertIn("Radius", str(mapper))  # PrintSelf
        self.assertTrue(hasattr(sightline, "__version__"))

    def test_silhouette_and_depth_match_closed_form(self):
        mapper = sightline.vtkSightlineSphereMapper()
        mapper.SetInputDataObject(sphere_cloud([[0.5, -0.25, 0.0]], [0.8]))
        mapper.SetRadiusArrayName("radius")
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        size = 301
        rgba, depth = render_without_gl(actor, parallel_camera(), size, size)
        covered = depth < 1.0
        pixel = 4.0 / size
        disc = math.pi * 0.8**2 / pixel**2
        self.assertAlmostEqual(covered.sum(), disc, delta=0.25 * 2 * math.pi * 0.8 / pixel)
        # Depth of every covered pixel from the sphere's equation: z = sqrt(r^2 - d^2),
        # window depth of a parallel camera is (distance - near) / (far - near).
        ys, xs = np.nonzero(covered)
        wx = (xs + 0.5) * pixel - 2.0 - 0.5
        wy = (ys + 0.5) * pixel - 2.0 + 0.25
        z = np.sqrt(np.maximum(0.8**2 - wx**2 - wy**2, 0.0))
        expected = ((10.0 - z) - 6.0) / 8.0
        self.assertLess(np.abs(depth[covered] - expected).max(), 1e-5)
        # The background is opaque black, as a window's.
        self.assertTrue((rgba[~covered][:, :3] == 0).all())

    def test_window_matches_gl_free_image(self):
        mapper = sightline.vtkSightlineSphereMapper()
        mapper.SetInputDataObject(sphere_cloud([[0, 0, 0], [1.2, 0.4, -0.3]], [0.9, 0.5]))
        mapper.SetRadiusArrayName("radius")
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().SetColor(0.9, 0.5, 0.2)
        renderer = vtk.vtkRenderer()
        renderer.AddActor(actor)
        window = vtk.vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.AddRenderer(renderer)
        window.SetSize(200, 150)
        renderer.ResetCamera()
        window.Render()
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.Update()
        shown = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).reshape(150, 200, 3)
        rgba, _ = render_without_gl(actor, renderer.GetActiveCamera(), 200, 150)
        difference = np.abs(shown.astype(int) - rgba[:, :, :3].astype(int)).max()
        self.assertLessEqual(difference, 1)
        self.assertGreater((shown.sum(axis=2) > 0).sum(), 1000)

    def test_bad_input_is_reported(self):
        messages = []
        mapper = sightline.vtkSightlineSphereMapper()
        mapper.AddObserver("ErrorEvent", lambda obj, event: messages.append(event))
        mapper.AddObserver("WarningEvent", lambda obj, event: messages.append(event))
        mapper.SetInputDataObject(sphere_cloud([[0, 0, 0], [float("nan"), 0, 0]], [1.0, 1.0]))
        mapper.SetRadiusArrayName("radius")
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        rgba, depth = render_without_gl(actor, parallel_camera(), 64, 64)
        self.assertEqual(mapper.GetNumberOfPrimitives(), 1)
        self.assertTrue(messages, "a warning names the NaN point")
        self.assertTrue((depth < 1).any(), "the valid sphere still renders")


if __name__ == "__main__":
    unittest.main()
