# SPDX-License-Identifier: BSD-3-Clause
"""vtkSightlineSHGlyphMapper from Python, on real data (DIPY's small_64D CSD fit written by the
SHData fixture into $SIGHTLINE_SH_DATA_DIR): import next to vtk, window and GL-free images
agree, DIPY's and MRtrix3's bases give the same picture, bad input is reported and not fatal,
and both SH examples run end to end."""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
import vtk

import sightline
from sightline import nifti

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.normpath(os.path.join(HERE, os.pardir, os.pardir, "Examples", "Python"))
DIPY_FILE = "small_64D_sh_descoteaux07.nii.gz"
MRTRIX_FILE = "small_64D_sh_tournier07.nii.gz"
FA_FILE = "small_64D_fa.nii.gz"
UNCERTAINTY_FILE = "small_64D_sh_uncertainty_descoteaux07.nii.gz"


def data_file(name):
    folder = os.environ.get("SIGHTLINE_SH_DATA_DIR")
    if not folder:
        raise unittest.SkipTest("SIGHTLINE_SH_DATA_DIR is not set (ctest's SHData fixture "
                                "sets it; or run scripts/make_sh_data.py DIR)")
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        raise AssertionError(f"{path} is missing: did the SHData.Generate fixture run?")
    return path


def read_sh(name):
    reader = vtk.vtkNIFTIImageReader()
    reader.SetFileName(data_file(name))
    reader.TimeAsVectorOn()
    reader.Update()
    return reader


def glyph_actor(reader, configure=None):
    mapper = sightline.vtkSightlineSHGlyphMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetDataToWorldMatrix(nifti.data_to_world(reader))
    mapper.SetBasisToDIPY()
    mapper.SetSliceOrientationToAxial()
    if configure:
        configure(mapper)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetAmbient(0.15)
    actor.GetProperty().SetSpecular(0.4)
    actor.GetProperty().SetSpecularPower(40)
    return actor, mapper


def oblique_camera(mapper):
    """Looks at the glyphs' bounds obliquely from above (fixed, so that two renders match)."""
    bounds = mapper.GetBounds()
    centre = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
    camera = vtk.vtkCamera()
    camera.SetFocalPoint(*centre)
    camera.SetPosition(centre[0], centre[1] - 28.0, centre[2] + 32.0)
    camera.SetViewUp(0, 1, 0)
    camera.OrthogonalizeViewUp()
    camera.SetViewAngle(30)
    camera.SetClippingRange(10, 100)
    return camera


def oblique_light(mapper):
    bounds = mapper.GetBounds()
    centre = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
    light = vtk.vtkLight()
    light.SetLightTypeToSceneLight()
    light.SetFocalPoint(*centre)
    light.SetPosition(centre[0] - 40, centre[1] + 30, centre[2] + 60)
    return light


def render_gl_free(actor, camera, width, height, light=None):
    batch = sightline.vtkSightlineImageRenderer()
    batch.AddActor(actor)
    if light is not None:
        batch.AddLight(light)
    batch.SetActiveCamera(camera)
    batch.SetSize(width, height)
    batch.Update()
    image = batch.GetOutput()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, 4)[:, :, :3]


def read_png(path):
    reader = vtk.vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    scalars = image.GetPointData().GetScalars()
    return vtk_to_numpy(scalars).reshape(height, width, scalars.GetNumberOfComponents())


def run_example(test, script, *arguments):
    command = [sys.executable, os.path.join(EXAMPLES, script), *arguments]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True, timeout=600)
    test.assertEqual(result.returncode, 0, f"{' '.join(command)} failed:\n{result.stdout[-4000:]}")
    return result.stdout


class SHGlyphsTest(unittest.TestCase):
    def test_package_wraps_the_glyph_mapper(self):
        mapper = sightline.vtkSightlineSHGlyphMapper()
        self.assertTrue(mapper.IsA("vtkMapper"))
        self.assertTrue(mapper.IsA("vtkSightlineMapper"))
        self.assertIn("Basis", str(mapper))  # PrintSelf
        mapper.SetBasisToMRtrix3()
        self.assertEqual(mapper.GetBasisAsString(), "tournier07")
        self.assertFalse(mapper.GetLegacyBasis())
        mapper.SetBasisToDIPY()
        self.assertEqual(mapper.GetBasisAsString(), "descoteaux07")
        self.assertTrue(mapper.GetLegacyBasis())

    def test_window_matches_gl_free_image(self):
        reader = read_sh(DIPY_FILE)
        actor, mapper = glyph_actor(reader, lambda m: m.SetShadowModeToHard())
        width, height = 240, 180
        camera = oblique_camera(mapper)
        light = oblique_light(mapper)
        renderer = vtk.vtkRenderer()
        renderer.AddActor(actor)
        renderer.AddLight(light)
        renderer.SetActiveCamera(camera)
        window = vtk.vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetMultiSamples(0)
        window.AddRenderer(renderer)
        window.SetSize(width, height)
        window.Render()
        self.assertGreater(mapper.GetNumberOfPrimitives(), 0)
        self.assertEqual(mapper.GetSliceAxis(), 2)
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(window)
        grab.ReadFrontBufferOff()
        grab.Update()
        shown = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())
        shown = shown.reshape(height, width, -1)[:, :, :3]
        rgb = render_gl_free(actor, camera, width, height, light)
        self.assertGreater((shown.sum(axis=2) > 0).sum(), 0.05 * width * height)
        difference = np.abs(shown.astype(int) - rgb.astype(int)).max(axis=2)
        ys, xs = np.nonzero(difference > 1)
        covered = int((shown.sum(axis=2) > 0).sum())
        # Both paths run vtkSightlineMapper::RayTrace, but the window's projection matrix can
        # differ from the GL-free one in the last bits; a ray that grazes a lobe's tip may then
        # hit a sliver in one image only (seen: 1 pixel of 3352 at 240x180). Allow 0.1 %.
        self.assertLessEqual(len(xs), max(1, covered // 1000),
                             f"{len(xs)} pixels differ by more than 1 level, e.g. (x, y) = "
                             f"{list(zip(xs.tolist(), ys.tolist()))[:5]}: window "
                             f"{shown[ys, xs].tolist()[:5]}, GL-free {rgb[ys, xs].tolist()[:5]}")

    def test_mrtrix3_basis_gives_the_dipy_picture(self):
        width, height = 240, 180
        dipy_actor, dipy_mapper = glyph_actor(read_sh(DIPY_FILE), lambda m: m.SetBasisToDIPY())
        mrtrix_actor, mrtrix_mapper = glyph_actor(read_sh(MRTRIX_FILE),
                                                  lambda m: m.SetBasisToMRtrix3())
        camera = oblique_camera(dipy_mapper)
        dipy = render_gl_free(dipy_actor, camera, width, height).astype(int)
        mrtrix = render_gl_free(mrtrix_actor, camera, width, height).astype(int)
        self.assertEqual(dipy_mapper.GetNumberOfPrimitives(), mrtrix_mapper.GetNumberOfPrimitives())
        self.assertGreater(dipy_mapper.GetNumberOfPrimitives(), 0)
        difference = np.abs(dipy - mrtrix).max(axis=2)
        self.assertGreater((dipy.sum(axis=2) > 0).sum(), 0.05 * width * height)
        self.assertLessEqual((difference > 2).mean(), 0.005,
                             f"largest difference {difference.max()}")
        # The wrong basis is not the same picture (the comparison can fail).
        wrong_actor, _ = glyph_actor(read_sh(MRTRIX_FILE), lambda m: m.SetBasisToDIPY())
        wrong = render_gl_free(wrong_actor, camera, width, height).astype(int)
        self.assertGreater((np.abs(dipy - wrong).max(axis=2) > 2).mean(), 0.01)

    def test_bad_input_is_reported_not_fatal(self):
        messages = []

        @vtk.calldata_type(vtk.VTK_STRING)
        def record(_caller, event, text):
            messages.append((event, text))

        # 7 components: no SH order has that many coefficients.
        points = vtk.vtkPoints()
        points.InsertNextPoint(0, 0, 0)
        points.InsertNextPoint(3, 0, 0)
        cloud = vtk.vtkPolyData()
        cloud.SetPoints(points)
        array = numpy_to_vtk(np.ones((2, 7)), deep=True)
        array.SetName("odd_coefficients")
        cloud.GetPointData().AddArray(array)
        mapper = sightline.vtkSightlineSHGlyphMapper()
        mapper.AddObserver("ErrorEvent", record)
        mapper.AddObserver("WarningEvent", record)
        mapper.SetInputDataObject(cloud)
        mapper.SetCoefficientArrayName("odd_coefficients")
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        camera = vtk.vtkCamera()
        camera.SetPosition(1.5, 0, 10)
        camera.SetFocalPoint(1.5, 0, 0)
        rgb = render_gl_free(actor, camera, 64, 64)
        errors = [text for event, text in messages if event == "ErrorEvent"]
        self.assertTrue(errors, "an ErrorEvent reports the component count")
        self.assertTrue(any("odd_coefficients" in text for text in errors), errors)
        self.assertEqual(mapper.GetNumberOfPrimitives(), 0)
        self.assertFalse(rgb.any(), "nothing is drawn")

        # An unknown basis name is refused and leaves the basis alone.
        messages.clear()
        mapper.SetBasisToMRtrix3()
        self.assertFalse(mapper.SetBasisByName("bogus"))
        self.assertEqual(mapper.GetBasisAsString(), "tournier07")
        self.assertTrue(mapper.SetBasisByName("descoteaux07"))
        self.assertEqual(mapper.GetBasisAsString(), "descoteaux07")

        # The same mapper still works once the input is fixed.
        reader = read_sh(DIPY_FILE)  # kept: an output port does not own its algorithm
        mapper.SetInputConnection(reader.GetOutputPort())
        mapper.SetCoefficientArrayName(None)
        mapper.SetSliceOrientationToAxial()
        rgb = render_gl_free(actor, oblique_camera(mapper), 64, 64)
        self.assertGreater(mapper.GetNumberOfPrimitives(), 0)
        self.assertTrue(rgb.any())

    def assert_not_blank(self, path):
        self.assertTrue(os.path.exists(path), path)
        pixels = read_png(path)[:, :, :3].astype(int)
        background = pixels[0, 0]
        differs = (np.abs(pixels - background).max(axis=2) > 8).mean()
        self.assertGreater(differs, 0.05, f"{path} is (nearly) blank")

    def test_render_example_runs(self):
        with tempfile.TemporaryDirectory(dir=os.environ.get("SIGHTLINE_TEST_TEMP_DIR")) as out:
            common = ["--sh", data_file(DIPY_FILE), "--anatomy", data_file(FA_FILE),
                      "--size", "200", "125", "--output", out]
            log = run_example(self, "render_sh_glyphs.py", *common, "--shadows", "hard")
            self.assertIn("glyphs:", log)
            self.assert_not_blank(os.path.join(out, "sh_glyphs_axial_4.png"))
            log = run_example(self, "render_sh_glyphs.py", *common, "--gl-free", "--slice",
                              "coronal", "--basis", "dipy", "--sh-frame", "voxel")
            self.assertIn("not drawn", log)  # says that the image slice is missing
            self.assert_not_blank(os.path.join(out, "sh_glyphs_coronal_4_gl_free.png"))
            log = run_example(self, "render_sh_glyphs.py", "--sh", data_file(MRTRIX_FILE),
                              "--basis", "mrtrix3", "--anatomy", "none", "--size", "200", "125",
                              "--index", "6", "--output", out)
            self.assert_not_blank(os.path.join(out, "sh_glyphs_axial_6.png"))

    def test_interactive_example_runs_its_key_sequence(self):
        with tempfile.TemporaryDirectory(dir=os.environ.get("SIGHTLINE_TEST_TEMP_DIR")) as out:
            log = run_example(self, "interactive_sh_glyphs.py", "--test",
                              "--sh", data_file(DIPY_FILE), "--anatomy", data_file(FA_FILE),
                              "--uncertainty", data_file(UNCERTAINTY_FILE),
                              "--size", "200", "125", "--output", out)
            for expected in ("[h]", "shadows hard", "negative lobes hide", "uncertainty off",
                             "coronal slice", "sagittal slice"):
                self.assertIn(expected, log)
            self.assert_not_blank(os.path.join(out, "interactive_sh_glyphs_test.png"))


if __name__ == "__main__":
    unittest.main()
