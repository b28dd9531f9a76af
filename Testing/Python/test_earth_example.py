# SPDX-License-Identifier: BSD-3-Clause
"""The Earth example's scene: the graticule shows only what lies in front of the globe.

Meridians on the far side used to show through the translucent limb, most visibly at the
south pole of the cut-away globe, where a dozen of them converge over almost no material and
read as light streaks with a dark patch around them. The reference for what should be visible
is independent of the example's clipping: the whole graticule drawn with an opaque sphere in
front of its far half (depth test). Every pixel the graticule changes in the example's window
must lie on (or next to) a line of that reference.
"""
import math
import os
import sys
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
import vtk

import sightline

sys.path.insert(0, os.path.join(os.environ["SIGHTLINE_SOURCE_DIR"], "Examples", "Python"))
import render_earth  # noqa: E402

SIZE = (320, 260)
BACKGROUND = (0.02, 0.02, 0.05)
RADIUS = render_earth.EARTH_KM


def earth_volume():
    source = sightline.vtkSightlineSphericalFieldSource()
    source.SetFieldToPREMDensity()
    source.SetRadiusRange(render_earth.INNER_CORE_KM, RADIUS)
    source.SetRadialResolution(30)
    source.SetPolarResolution(24)
    source.SetAzimuthalResolution(27)
    source.SetAzimuthRange(0.0, 1.5 * math.pi)  # the example's cut-away quarter
    mapper = sightline.vtkSightlineSphericalVolumeMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    color, opacity = render_earth.transfer_functions()
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(400.0)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    return volume


def example_camera():
    camera = vtk.vtkCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(2.4 * RADIUS, -2.9 * RADIUS, 1.5 * RADIUS)
    camera.SetViewUp(0, 0, 1)
    camera.SetClippingRange(0.5 * RADIUS, 8.0 * RADIUS)
    return camera


def render(props, camera):
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(*BACKGROUND)
    renderer.SetActiveCamera(camera)
    for prop in props:
        if isinstance(prop, vtk.vtkVolume):
            renderer.AddVolume(prop)
        else:
            renderer.AddActor(prop)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.SetSize(*SIZE)
    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    image = grab.GetOutput()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).astype(int)
    window.Finalize()
    return pixels.reshape(SIZE[1], SIZE[0], -1)[:, :, :3]


def full_graticule_actor(radius):
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(render_earth.graticule(radius))
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetLineWidth(1.5)
    actor.GetProperty().LightingOff()
    return actor


def occluder(radius):
    """An opaque sphere in the background colour: hides what lies behind the globe."""
    sphere = vtk.vtkSphereSource()
    sphere.SetRadius(radius)
    sphere.SetThetaResolution(180)
    sphere.SetPhiResolution(90)
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputConnection(sphere.GetOutputPort())
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*BACKGROUND)
    actor.GetProperty().LightingOff()
    return actor


def dilate(mask, steps):
    out = mask.copy()
    for _ in range(steps):
        grown = out.copy()
        grown[1:, :] |= out[:-1, :]
        grown[:-1, :] |= out[1:, :]
        grown[:, 1:] |= out[:, :-1]
        grown[:, :-1] |= out[:, 1:]
        out = grown
    return out


class EarthGraticuleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.volume = earth_volume()
        cls.camera = example_camera()
        cls.volume_only = render([cls.volume], cls.camera)
        # What the graticule may show: its lines with the globe (radius R) occluding the rest.
        background = np.array([round(255 * c) for c in BACKGROUND])
        reference = render([occluder(RADIUS), full_graticule_actor(RADIUS * 1.003)], cls.camera)
        cls.visible_lines = dilate(np.abs(reference - background).max(axis=2) > 24, 2)

    def changed_by(self, graticule_actor):
        with_lines = render([self.volume, graticule_actor], self.camera)
        return np.abs(with_lines - self.volume_only).max(axis=2) > 12

    def test_graticule_shows_only_the_side_facing_the_camera(self):
        changed = self.changed_by(render_earth.front_graticule(self.camera, RADIUS * 1.003))
        stray = changed & ~self.visible_lines
        self.assertGreater(changed.sum(), 500, "the graticule should be visible")
        self.assertEqual(stray.sum(), 0,
                         f"{stray.sum()} pixels show graticule lines from behind the globe")

    def test_the_check_sees_lines_from_behind(self):
        # The scene as it was: the whole graticule, far side included, shows through the limb.
        changed = self.changed_by(full_graticule_actor(RADIUS * 1.003))
        stray = changed & ~self.visible_lines
        self.assertGreater(stray.sum(), 50)


if __name__ == "__main__":
    unittest.main()
