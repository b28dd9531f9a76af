# SPDX-License-Identifier: BSD-3-Clause
"""sightline.pyvista: the `plotter.sightline` component in PyVista plotters.

Run with PyVista over Debian's VTK (scripts/pyvista-env.sh). Every scene is seen along -z with
a parallel projection and lighting off, so what the screenshot holds has an exact reference:
discs and bands of the primitives' radii in pixels, matplotlib's colour maps, and the
transmittance of a homogeneous ball. Depth is checked by sinking primitives under an ordinary
PyVista plane: only the part above it may show.
"""
import math
import os
import tempfile
import unittest

import matplotlib
import numpy as np
import pyvista as pv
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

import sightline
import sightline.pyvista
from sightline.pyvista import SightlineError, SightlinePlotterComponent

WIDTH, HEIGHT = 400, 300
HALF_HEIGHT = 6.0  # world units from the centre to the top edge
PIXEL = 2.0 * HALF_HEIGHT / HEIGHT  # world units per pixel


def plotter():
    p = pv.Plotter(off_screen=True, window_size=(WIDTH, HEIGHT))
    p.set_background("black")
    return p


def look_down(p, centre=(0.0, 0.0, 0.0)):
    """A parallel camera along -z, HALF_HEIGHT world units from the centre to the top."""
    camera = p.camera
    camera.SetFocalPoint(*centre)
    camera.SetPosition(centre[0], centre[1], centre[2] + 50.0)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.ParallelProjectionOn()
    camera.SetParallelScale(HALF_HEIGHT)
    camera.SetClippingRange(1.0, 100.0)
    p.camera_set = True


def pixels_of(image, rgb, tolerance=3):
    return np.all(np.abs(image.astype(int) - np.array(rgb, dtype=int)) <= tolerance, axis=2)


def centre_pixel(image, x, y):
    """The pixel at world (x, y) under look_down (screenshots have row 0 at the top)."""
    column = int(round(WIDTH / 2 + x / PIXEL - 0.5))
    row = int(round(HEIGHT / 2 - y / PIXEL - 0.5))
    return image[row, column].astype(int)


class Component(unittest.TestCase):
    @unittest.skipUnless(os.environ.get("SIGHTLINE_EXPECT_WINDOW"),
                         "SIGHTLINE_EXPECT_WINDOW names the window an offscreen run must get")
    def test_the_offscreen_window_is_the_one_asked_for_on_llvmpipe(self):
        # Offscreen runs (VTK >= 9.4: VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow or
        # vtkOSOpenGLRenderWindow, DISPLAY unset) must not fall back to another window.
        self.assertNotIn("DISPLAY", os.environ)
        p = plotter()
        p.sightline.add_spheres(np.zeros((1, 3)), radius=1.0)
        p.screenshot(return_img=True)
        self.assertEqual(p.ren_win.GetClassName(), os.environ["SIGHTLINE_EXPECT_WINDOW"])
        self.assertIn("llvmpipe", p.ren_win.ReportCapabilities())
        p.close()

    def test_every_plotter_has_one_cached_component(self):
        first, second = plotter(), plotter()
        self.assertIsInstance(first.sightline, SightlinePlotterComponent)
        self.assertIs(first.sightline, first.sightline)
        self.assertIsNot(first.sightline, second.sightline)
        first.close()
        second.close()

    def test_the_actor_holds_the_sightline_mapper(self):
        p = plotter()
        actor = p.sightline.add_spheres(np.zeros((1, 3)), radius=1.0)
        self.assertIsInstance(actor.GetMapper(), sightline.vtkSightlineSphereMapper)
        self.assertIn(actor, list(p.renderer.GetActors()))
        p.close()


class Images(unittest.TestCase):
    def test_spheres_under_an_ordinary_plane_show_their_exact_caps(self):
        # Spheres of radius r centred 0.5 r below an opaque PyVista plane: only a cap shows,
        # a disc of radius r sqrt(1 - 1/4); the plane hides the rest through the depth buffer.
        radius = 1.5
        centres = np.array([[-3.0, 0.0, -0.5 * radius], [3.0, 0.0, -0.5 * radius]])
        p = plotter()
        p.sightline.add_spheres(centres, radius=radius, color="red", lighting=False)
        p.add_mesh(pv.Plane(center=(0, 0, 0), i_size=20, j_size=20), color="white",
                   lighting=False)
        look_down(p)
        image = p.screenshot(return_img=True)
        p.close()
        red = pixels_of(image, (255, 0, 0)).sum()
        cap = math.pi * (radius * math.sqrt(0.75) / PIXEL) ** 2
        self.assertAlmostEqual(red / (2 * cap), 1.0, delta=0.03)
        self.assertGreater(pixels_of(image, (255, 255, 255)).sum(), 0.5 * WIDTH * HEIGHT)

    def test_scalars_are_coloured_by_pyvistas_colour_map_with_its_scalar_bar(self):
        values = np.array([0.0, 0.25, 0.5, 1.0])
        points = pv.PolyData(np.array([[-4.5, 0, 0], [-1.5, 0, 0], [1.5, 0, 0], [4.5, 0, 0.0]]))
        p = plotter()
        p.sightline.add_spheres(points, radius=1.0, scalars=values, cmap="viridis",
                                lighting=False, scalar_bar_args={"title": "value"})
        look_down(p)
        image = p.screenshot(return_img=True)
        self.assertNotIn("Data", points.point_data.keys())  # the caller's dataset is untouched
        self.assertIn("value", p.scalar_bars.keys())
        bar = p.scalar_bars["value"]
        self.assertEqual(tuple(bar.GetLookupTable().GetRange()), (0.0, 1.0))
        p.close()
        viridis = matplotlib.colormaps["viridis"]
        for value, point in zip(values, points.points):
            expected = np.round(np.array(viridis(value)[:3]) * 255)
            got = centre_pixel(image, point[0], point[1])
            # PyVista's table has 256 entries: a step is under 2/255 in viridis.
            self.assertLessEqual(np.abs(got - expected).max(), 3, f"value {value}: {got}")

    def test_a_straight_tube_is_a_band_of_its_diameter_with_round_ends(self):
        radius, length = 0.6, 8.0
        line = pv.Line((-length / 2, 0, 0), (length / 2, 0, 0), resolution=4)
        p = plotter()
        p.sightline.add_tubes(line, radius=radius, color="lime", lighting=False)
        look_down(p)
        image = p.screenshot(return_img=True)
        p.close()
        covered = pixels_of(image, (0, 255, 0))
        column = covered[:, WIDTH // 2]
        self.assertAlmostEqual(column.sum(), 2 * radius / PIXEL, delta=1.0)
        area = (2 * radius * length + math.pi * radius ** 2) / PIXEL ** 2
        self.assertAlmostEqual(covered.sum() / area, 1.0, delta=0.02)

    def test_crossing_translucent_tubes_blend_once_over_an_ordinary_plane(self):
        # Two crossing tubes at opacity 0.5 are one translucent union: a ray crosses its surface
        # twice (in and out), where they cross exactly as where one tube covers the plane, so
        # a quarter of the white plane shows through: (1, 0.25, 0.25) everywhere on the tubes.
        p = plotter()
        lines = pv.Line((-4, 0, 0.5), (4, 0, 0.5)).merge(pv.Line((0, -4, 0.5), (0, 4, 0.5)))
        p.sightline.add_tubes(lines, radius=0.5, color="red", opacity=0.5, lighting=False)
        p.add_mesh(pv.Plane(center=(0, 0, -1), i_size=20, j_size=20), color="white",
                   lighting=False)
        look_down(p)
        shot = p.screenshot(return_img=True)
        p.close()
        blend = np.array([255, 0.25 * 255, 0.25 * 255])
        for x, y in ((0.0, 0.0), (2.5, 0.0), (0.0, -2.5)):
            self.assertLessEqual(np.abs(centre_pixel(shot, x, y) - blend).max(), 3, (x, y))
        self.assertLessEqual(np.abs(centre_pixel(shot, 2.5, 2.5) - 255).max(), 1)

    def test_selection_names_the_sphere_under_a_pixel(self):
        centres = np.array([[-3.0, 0.0, 0.0], [0.0, 2.0, 0.0], [3.0, -1.0, 0.0]])
        p = plotter()
        actor = p.sightline.add_spheres(centres, radius=0.8, color="white")
        look_down(p)
        p.screenshot(return_img=True)
        selector = vtk.vtkHardwareSelector()
        selector.SetRenderer(p.renderer)
        selector.SetFieldAssociation(vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS)
        for index, (x, y, _) in enumerate(centres):
            column = int(round(WIDTH / 2 + x / PIXEL))
            row = int(round(HEIGHT / 2 + y / PIXEL))  # display rows count from the bottom
            selector.SetArea(column, row, column, row)
            selection = selector.Select()
            self.assertEqual(selection.GetNumberOfNodes(), 1, index)
            node = selection.GetNode(0)
            self.assertIs(node.GetProperties().Get(vtk.vtkSelectionNode.PROP()), actor)
            self.assertEqual(list(vtk_to_numpy(node.GetSelectionList())), [index])
        p.close()

    def test_order_zero_sh_glyphs_are_spheres_of_the_scale(self):
        # A constant ODF has one lobe everywhere: normalised to its largest amplitude it is a
        # sphere of radius scale x half the voxel spacing.
        spacing, scale = 3.0, 0.9
        image = pv.ImageData(dimensions=(3, 1, 1), spacing=(spacing, 1, 1), origin=(-3, 0, 0))
        coefficients = np.zeros((3, 15))
        coefficients[:, 0] = [1.0, 2.0, 0.3]
        image.point_data["odf"] = coefficients
        p = plotter()
        p.sightline.add_sh_glyphs(image, coefficients="odf", scale=scale, color="yellow",
                                  lighting=False)
        look_down(p)
        shot = p.screenshot(return_img=True)
        p.close()
        disc = math.pi * (scale * spacing / 2 / PIXEL) ** 2
        self.assertAlmostEqual(pixels_of(shot, (255, 255, 0)).sum() / (3 * disc), 1.0, delta=0.03)

    def test_tensor_ellipsoids_have_the_eigenvalue_semi_axes(self):
        # diag(3, 1, 1) in VTK's symmetric layout: semi-axes scale/2 and scale/6 voxels.
        image = pv.ImageData(dimensions=(1, 1, 1), spacing=(4, 4, 4))
        image.point_data["tensor"] = np.array([[3.0, 1.0, 1.0, 0.0, 0.0, 0.0]])
        scale = 2.0
        p = plotter()
        p.sightline.add_tensor_glyphs(image, tensors="tensor", layout="vtk_symmetric",
                                      shape="ellipsoid", scale=scale, color="cyan",
                                      lighting=False)
        look_down(p)
        shot = p.screenshot(return_img=True)
        p.close()
        covered = pixels_of(shot, (0, 255, 255))
        a, b = scale * 4 / 2, scale * 4 / 2 / 3
        self.assertAlmostEqual(covered.sum() / (math.pi * a * b / PIXEL ** 2), 1.0, delta=0.03)
        rows, columns = np.nonzero(covered)
        self.assertAlmostEqual((columns.max() - columns.min() + 1) * PIXEL, 2 * a, delta=2 * PIXEL)
        self.assertAlmostEqual((rows.max() - rows.min() + 1) * PIXEL, 2 * b, delta=2 * PIXEL)

    def test_a_homogeneous_ball_lets_through_its_exact_transmittance(self):
        # A ball of radius R on an (r, theta, phi) grid, value 1 everywhere, opacity 0.5 per
        # unit distance R: through the centre (chord 2R) 1/4 of the background is left, so the
        # pixel is (1 - 1/4) of the colour map's top colour over black.
        radius = 4.0
        grid = pv.RectilinearGrid(np.linspace(0, radius, 5), np.linspace(0, math.pi, 9),
                                  np.linspace(0, 2 * math.pi, 17))
        grid.point_data["density"] = np.ones(grid.n_points)
        p = plotter()
        volume = p.sightline.add_spherical_volume(grid, cmap="gray", clim=(0.0, 1.0),
                                                  opacity=[0.0, 0.5], unit_distance=radius,
                                                  show_scalar_bar=False)
        self.assertIsInstance(volume.GetMapper(), sightline.vtkSightlineSphericalVolumeMapper)
        look_down(p)
        shot = p.screenshot(return_img=True)
        p.close()
        self.assertLessEqual(np.abs(centre_pixel(shot, 0, 0) - 0.75 * 255).max(), 3)
        # Off centre, the chord is 2 sqrt(R^2 - d^2).
        d = 0.6 * radius
        chord = 2 * math.sqrt(radius ** 2 - d ** 2)
        expected = (1 - 0.5 ** (chord / radius)) * 255
        self.assertLessEqual(np.abs(centre_pixel(shot, d, 0) - expected).max(), 3)
        lit = shot.max(axis=2) > 0
        self.assertAlmostEqual(lit.sum() / (math.pi * (radius / PIXEL) ** 2), 1.0, delta=0.03)

    def test_screenshots_write_what_the_window_shows(self):
        path = os.path.join(os.environ.get("SIGHTLINE_TEST_TEMP_DIR", tempfile.gettempdir()),
                            "pyvista_tubes.png")
        p = plotter()
        p.sightline.add_tubes(pv.Spline(np.array([[-4, -2, 0], [0, 2, 0], [4, -2, 0.0]]), 20),
                              radius=0.5, scalars="arc_length", cmap="plasma")
        look_down(p)
        shot = p.screenshot(path, return_img=True)
        p.close()
        written = pv.read(path)
        pixels = np.asarray(written.point_data[written.point_data.keys()[0]])
        self.assertEqual(pixels.shape[0], WIDTH * HEIGHT)
        self.assertGreater((shot.max(axis=2) > 0).mean(), 0.03)


class Errors(unittest.TestCase):
    def setUp(self):
        self.p = plotter()

    def tearDown(self):
        self.p.close()

    def test_bad_input_is_named(self):
        image = pv.ImageData(dimensions=(2, 2, 2))
        image.point_data["odf"] = np.ones((8, 6))
        cases = [
            (lambda: self.p.sightline.add_tubes(image), "vtkPolyData"),
            (lambda: self.p.sightline.add_tubes(pv.PolyData(np.zeros((3, 3)))), "no lines"),
            (lambda: self.p.sightline.add_spheres(np.zeros((2, 3)), scalars="speed"),
             "no array 'speed'"),
            (lambda: self.p.sightline.add_spheres(np.zeros((2, 3)), scalars=[1, 2, 3]),
             "3 scalars for 2 points"),
            (lambda: self.p.sightline.add_sh_glyphs(image, coefficients="odf", basis="mrtrix"),
             "basis 'mrtrix'"),
            (lambda: self.p.sightline.add_sh_glyphs(image, coefficients="fod"), "no array 'fod'"),
            (lambda: self.p.sightline.add_tensor_glyphs(image, shape="cube"), "shape 'cube'"),
            (lambda: self.p.sightline.add_sh_glyphs(image, normalization="unit"),
             "normalization 'unit'"),
            (lambda: self.p.sightline.add_spherical_volume(image), "vtkRectilinearGrid"),
            (lambda: self.p.sightline.add_spherical_volume(pv.RectilinearGrid(
                np.arange(3.0), np.arange(3.0), np.arange(3.0))), "no active scalars"),
            (lambda: self.p.sightline.add_spheres(None), "no dataset"),
        ]
        for call, message in cases:
            with self.subTest(message=message):
                with self.assertRaises(SightlineError) as raised:
                    call()
                self.assertIn(message, str(raised.exception))
        self.assertEqual(self.p.renderer.GetActors().GetNumberOfItems(), 0)


if __name__ == "__main__":
    unittest.main()
