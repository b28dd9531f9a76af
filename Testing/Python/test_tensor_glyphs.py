# SPDX-License-Identifier: BSD-3-Clause
"""vtkSightlineTensorGlyphMapper from Python: numpy tensors in every layout give one glyph,
copper's largest longitudinal modulus comes out analytically, bad input is reported, and the
tensor example runs on the copper polycrystal and on real tensors of the TensorData fixture
($SIGHTLINE_TENSOR_DATA_DIR)."""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.normpath(os.path.join(HERE, os.pardir, os.pardir, "Examples", "Python",
                                        "render_tensor_glyphs.py"))
C11, C12, C44 = 168.4, 121.4, 75.4  # copper, GPa (Kittel)
PAIRS = {(0, 0): 0, (1, 1): 1, (2, 2): 2, (1, 2): 3, (2, 1): 3, (0, 2): 4, (2, 0): 4,
         (0, 1): 5, (1, 0): 5}


def copper_voigt():
    voigt = np.zeros((6, 6))
    voigt[:3, :3] = C12
    np.fill_diagonal(voigt[:3, :3], C11)
    voigt[3, 3] = voigt[4, 4] = voigt[5, 5] = C44
    return voigt


def full_from_voigt(voigt):
    full = np.empty((3, 3, 3, 3))
    for i, j, k, l in np.ndindex(3, 3, 3, 3):
        full[i, j, k, l] = voigt[PAIRS[i, j], PAIRS[k, l]]
    return full


def unique_components(full):
    """Mean over index permutations, in Sightline's order (x exponent descending, then y)."""
    order = full.ndim
    sums, counts = {}, {}
    for index in np.ndindex(*full.shape):
        key = (index.count(0), index.count(1))
        sums[key] = sums.get(key, 0.0) + full[index]
        counts[key] = counts.get(key, 0) + 1
    return [sums[a, b] / counts[a, b] for a in range(order, -1, -1) for b in range(order - a, -1, -1)]


def single_point(values):
    poly = vtk.vtkPolyData()
    points = vtk.vtkPoints()
    points.InsertNextPoint(0, 0, 0)
    poly.SetPoints(points)
    array = numpy_to_vtk(np.asarray([values], dtype=float), deep=1)
    array.SetName("T")
    poly.GetPointData().AddArray(array)
    return poly


def render(values, configure=None, size=160):
    mapper = sightline.vtkSightlineTensorGlyphMapper()
    mapper.SetInputDataObject(single_point(values))
    mapper.SetTensorArrayName("T")
    if configure:
        configure(mapper)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    camera = vtk.vtkCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(3, -4, 5)
    camera.SetViewUp(0, 0, 1)
    camera.ParallelProjectionOn()
    camera.SetParallelScale(1.15)
    batch = sightline.vtkSightlineImageRenderer()
    batch.AddActor(actor)
    batch.SetActiveCamera(camera)
    batch.SetSize(size, size)
    batch.Update()
    pixels = vtk_to_numpy(batch.GetOutput().GetPointData().GetScalars())
    return mapper, pixels.reshape(size, size, -1)[:, :, :3].astype(int)


class TensorGlyphs(unittest.TestCase):
    def test_every_layout_gives_the_same_copper_glyph(self):
        voigt = copper_voigt()
        full = full_from_voigt(voigt)
        _, from_voigt = render(voigt.reshape(36))
        _, from_full = render(full.transpose(3, 2, 1, 0).reshape(81))
        _, from_unique = render(unique_components(full), lambda m: m.SetTensorLayoutToSymmetricUnique())
        self.assertGreater((from_voigt.sum(axis=2) > 0).sum(), 5000)
        self.assertLessEqual(np.abs(from_voigt - from_full).max(), 1)
        self.assertLessEqual(np.abs(from_voigt - from_unique).max(), 1)

    def test_copper_largest_modulus_is_along_111(self):
        mapper, _ = render(copper_voigt().reshape(36), lambda m: m.SetColoringToRadius())
        self.assertEqual(mapper.GetTensorOrder(), 4)
        self.assertAlmostEqual(mapper.GetLastRadiusRange()[1], (C11 + 2 * C12 + 4 * C44) / 3, places=2)
        self.assertIn("TensorOrder: 4", str(mapper))

    def test_tensor_and_sh_mappers_are_siblings(self):
        # Both share vtkSightlineGlyphMapper; the tensor mapper has no SH-only settings.
        tensor = sightline.vtkSightlineTensorGlyphMapper()
        sh = sightline.vtkSightlineSHGlyphMapper()
        for mapper in (tensor, sh):
            self.assertTrue(mapper.IsA("vtkSightlineGlyphMapper"))
        self.assertFalse(tensor.IsA("vtkSightlineSHGlyphMapper"))
        for name in ("SetBasis", "SetLegacyBasis", "SetCoefficientArrayName",
                     "SetUncertaintyArrayName"):
            self.assertFalse(hasattr(tensor, name), name)
            self.assertTrue(hasattr(sh, name), name)
        for name in ("SetSliceOrientationToAxial", "SetMaskArrayName", "SetIntersectionMethodToMarching",
                     "GetLastComputedBoxes", "GetMemoryBytes"):
            self.assertTrue(hasattr(tensor, name) and hasattr(sh, name), name)

    def test_bad_component_count_is_reported(self):
        errors = []
        def configure(mapper):
            mapper.AddObserver("ErrorEvent", lambda caller, event: errors.append(event))
        _, pixels = render([1.0] * 7, configure)
        self.assertTrue(errors, "no error for 7 components")
        self.assertEqual(pixels.sum(), 0)

    def test_example_runs(self):
        env = dict(os.environ)
        with tempfile.TemporaryDirectory() as out:
            runs = [["--gl-free", "--size", "200", "150", "--grains", "2"],
                    ["--gl-free", "--size", "200", "150", "--grains", "2", "--method", "affine"]]
            folder = os.environ.get("SIGHTLINE_TENSOR_DATA_DIR")
            if folder:
                runs.append(["--gl-free", "--size", "200", "200", "--layout", "unique",
                             "--shape", "ellipsoid",
                             "--tensor", os.path.join(folder, "small_64D_dti.nii.gz")])
                runs.append(["--gl-free", "--size", "200", "200", "--layout", "unique",
                             "--tensor", os.path.join(folder, "small_64D_gdti6.nii.gz")])
            for arguments in runs:
                result = subprocess.run([sys.executable, EXAMPLE, "--output", out] + arguments,
                                        env=env, capture_output=True, text=True, timeout=300)
                self.assertEqual(result.returncode, 0, result.stderr)
                path = result.stdout.split(":")[0]
                reader = vtk.vtkPNGReader()
                reader.SetFileName(path)
                reader.Update()
                pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
                self.assertGreater((pixels[:, :3].sum(axis=1) > 0).sum(), 500, arguments)


if __name__ == "__main__":
    unittest.main()
