# SPDX-License-Identifier: BSD-3-Clause
"""ParaView.PvpythonImport: pvpython imports the 'sightline' package built against ParaView's VTK
(9.2 on Debian 12, 9.3 on 13) and draws with a mapper directly, without the plugin.

Three spheres of known centres and radii under a parallel camera go through
vtkSightlineSphereMapper and vtkSightlineImageRenderer (GL-free); the test asserts that the
package's classes are ParaView's VTK (the mapper is a vtkMapper from the same vtkmodules), that
every pixel inside each sphere's projected disc is hit (depth < 1, colour not background), that
pixels well outside all discs are background, and that the covered area matches the discs'.
Then the same actor in a vtkRenderWindow (ParaView's OpenGL2 under Xvfb) covers the same discs.
"""
import math
import os
import sys

import numpy as np
import vtkmodules
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkFloatArray, vtkPoints, vtkVersion
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkRenderingCore import (vtkActor, vtkCamera, vtkRenderer, vtkRenderWindow,
                                         vtkWindowToImageFilter)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

import sightline

SIZE = 200
SCALE = 2.0  # parallel scale: the view spans [-2, 2] x [-2, 2]
CENTRES = [(-1.0, -0.8, 0.0), (0.9, 0.7, 0.3), (0.8, -1.1, -0.2)]
RADII = [0.6, 0.45, 0.3]
BACKGROUND = (0.0, 0.0, 0.0)


def check(condition, message):
    if not condition:
        print(f"FAIL: {message}")
        sys.exit(1)


def cloud():
    points = vtkPoints()
    radius = vtkFloatArray()
    radius.SetName("radius")
    for centre, r in zip(CENTRES, RADII):
        points.InsertNextPoint(centre)
        radius.InsertNextValue(r)
    data = vtkPolyData()
    data.SetPoints(points)
    data.GetPointData().AddArray(radius)
    return data


def camera():
    cam = vtkCamera()
    cam.SetPosition(0, 0, 10)
    cam.SetFocalPoint(0, 0, 0)
    cam.SetViewUp(0, 1, 0)
    cam.ParallelProjectionOn()
    cam.SetParallelScale(SCALE)
    cam.SetClippingRange(5, 15)
    return cam


def disc_masks():
    """Per pixel (bottom row first): inside some disc shrunk by 2 pixels, and outside every disc
    grown by 2 pixels."""
    pixel = 2 * SCALE / SIZE
    centres = (np.arange(SIZE) + 0.5) * pixel - SCALE
    x, y = np.meshgrid(centres, centres)
    inside = np.zeros((SIZE, SIZE), bool)
    outside = np.ones((SIZE, SIZE), bool)
    for (cx, cy, _), r in zip(CENTRES, RADII):
        d = np.hypot(x - cx, y - cy)
        inside |= d < r - 2 * pixel
        outside &= d > r + 2 * pixel
    area = sum(math.pi * r * r for r in RADII) / pixel ** 2
    return inside, outside, area


def main():
    print("ParaView's VTK:", vtkVersion.GetVTKVersion(), "from", vtkmodules.__file__)
    print("sightline", sightline.__version__, "from", sightline.__file__)
    # ParaView's VTK, not Debian's: the version ParaView's CMake package names, and the modules
    # from ParaView's prefix (on Debian 13 both VTKs are 9.3, so the version alone cannot tell).
    expected = os.environ["SIGHTLINE_PARAVIEW_VTK_VERSION"]
    found = f"{vtkVersion.GetVTKMajorVersion()}.{vtkVersion.GetVTKMinorVersion()}"
    check(found == expected, f"pvpython's VTK is {found}, not ParaView's {expected}")
    prefix = os.path.realpath(os.environ["SIGHTLINE_PARAVIEW_PREFIX"])
    check(os.path.realpath(vtkmodules.__file__).startswith(prefix + os.sep),
          f"pvpython's vtkmodules are not ParaView's (from {prefix})")
    mapper = sightline.vtkSightlineSphereMapper()
    check(mapper.IsA("vtkMapper"), "the mapper is not a vtkMapper of this VTK")
    mapper.SetInputDataObject(cloud())
    mapper.SetRadiusArrayName("radius")
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(1.0, 0.5, 0.2)
    inside, outside, area = disc_masks()

    # GL-free.
    renderer = sightline.vtkSightlineImageRenderer()
    renderer.AddActor(actor)
    renderer.SetActiveCamera(camera())
    renderer.SetSize(SIZE, SIZE)
    renderer.SetBackground(*BACKGROUND)
    renderer.Update()
    image = renderer.GetOutput()
    rgba = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(SIZE, SIZE, 4)
    depth = vtk_to_numpy(image.GetPointData().GetArray("Depth")).reshape(SIZE, SIZE)
    hit = depth < 1.0
    lit = rgba[:, :, :3].max(axis=2) > 8
    print(f"image renderer: {hit.sum()} pixels hit, discs' area {area:.0f} pixels")
    check(hit[inside].all() and lit[inside].all(), "a pixel inside a sphere's disc is background")
    check(not hit[outside].any() and not lit[outside].any(), "a pixel outside every disc is hit")
    check(abs(hit.sum() - area) < 0.03 * area, "the covered area is not the discs' area")

    # In a window (ParaView's OpenGL2 render window).
    gl_renderer = vtkRenderer()
    gl_renderer.SetBackground(*BACKGROUND)
    gl_renderer.SetActiveCamera(camera())
    gl_renderer.AddActor(actor)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(SIZE, SIZE)
    window.AddRenderer(gl_renderer)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    pixels = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).reshape(SIZE, SIZE, -1)
    lit = pixels[:, :, :3].max(axis=2) > 8
    print(f"render window ({window.GetClassName()}): {lit.sum()} pixels lit")
    check(lit[inside].all(), "window: a pixel inside a sphere's disc is background")
    check(not lit[outside].any(), "window: a pixel outside every disc is lit")
    window.Finalize()
    print("ok")


if __name__ == "__main__":
    main()
