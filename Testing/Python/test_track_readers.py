# SPDX-License-Identifier: BSD-3-Clause
"""The streamline readers against nibabel, the independent reference, on real files that ship
with Debian: nibabel's standard.trk (voxel order RAS), standard.LPS.trk (LPS: flipped axes) and
standard.tck, and DIPY's minimal_bundles.zip (TrackVis bundles of five subjects). Every point
must agree in RAS mm, every streamline's length too; and an SWC file reads from Python and its
neuron renders with the tube mapper."""
import os
import tempfile
import unittest
import zipfile

import numpy as np
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

import sightline

NIBABEL_DATA = "/usr/lib/python3/dist-packages/nibabel/tests/data"
BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"
HERE = os.path.dirname(os.path.abspath(__file__))


def read(path):
    reader = (sightline.vtkSightlineTCKReader() if path.endswith(".tck")
              else sightline.vtkSightlineTrackVisReader())
    reader.SetFileName(path)
    reader.Update()
    output = reader.GetOutput()
    points = vtk_to_numpy(output.GetPoints().GetData()).astype(float)
    lengths = [output.GetCell(i).GetNumberOfPoints() for i in range(output.GetNumberOfCells())]
    return points, lengths


class TrackReaders(unittest.TestCase):
    def compare(self, path):
        import nibabel as nib
        reference = nib.streamlines.load(path).streamlines
        points, lengths = read(path)
        self.assertEqual(lengths, [len(s) for s in reference], path)
        expected = np.concatenate(list(reference)).astype(float)
        self.assertEqual(points.shape, expected.shape)
        # float32 in the files: agreement to rounding.
        self.assertLess(np.abs(points - expected).max(), 1e-4 * (1 + np.abs(expected).max()), path)

    def test_nibabel_standard_files(self):
        for name in ("standard.trk", "standard.LPS.trk", "standard.tck"):
            path = os.path.join(NIBABEL_DATA, name)
            if not os.path.exists(path):
                self.skipTest(f"{path} missing (Debian package python3-nibabel)")
            self.compare(path)

    def test_track_scalars_from_mrtrix3_tcksample(self):
        """A .tsf written by MRtrix3's tcksample (a linear field sampled at nibabel's
        standard.tck: trilinear interpolation gives it exactly) attaches to the right points,
        whole and in pieces; a .tsf of other tracks is a named error."""
        import subprocess
        import nibabel as nib
        tck = os.path.join(NIBABEL_DATA, "standard.tck")
        gradient = np.array([1.0, 2.0, -0.5])
        points = np.concatenate(list(nib.streamlines.load(tck).streamlines))
        low, high = np.floor(points.min(0)) - 3, np.ceil(points.max(0)) + 3
        shape = (high - low).astype(int) + 1
        grid = np.indices(shape).reshape(3, -1).T + low
        affine = np.eye(4)
        affine[:3, 3] = low
        with tempfile.TemporaryDirectory() as folder:
            image = os.path.join(folder, "linear.nii")
            nib.save(nib.Nifti1Image((grid @ gradient).reshape(shape).astype(np.float32),
                                     affine), image)
            tsf = os.path.join(folder, "linear.tsf")
            subprocess.run(["tcksample", "-quiet", "-force", tck, image, tsf], check=True)
            for piece, pieces in ((0, 1), (1, 3), (2, 3)):
                reader = sightline.vtkSightlineTCKReader()
                reader.SetFileName(tck)
                reader.SetScalarFileName(tsf)
                reader.UpdatePiece(piece, pieces, 0)
                output = reader.GetOutput()
                values = vtk_to_numpy(output.GetPointData().GetArray("linear"))
                xyz = vtk_to_numpy(output.GetPoints().GetData()).astype(float)
                self.assertEqual(len(values), len(xyz))
                self.assertGreater(len(values), 0)
                self.assertLess(np.abs(values - xyz @ gradient).max(),
                                1e-5 * (1 + np.abs(values).max()), (piece, pieces))
            # The scalars of other tracks (the first two dropped): a count that disagrees.
            other = os.path.join(folder, "other.tck")
            tracks = nib.streamlines.load(tck).streamlines
            nib.streamlines.save(nib.streamlines.Tractogram(tracks[2:], affine_to_rasmm=np.eye(4)),
                                 other)
            wrong = os.path.join(folder, "wrong.tsf")
            subprocess.run(["tcksample", "-quiet", "-force", other, image, wrong], check=True)
            reader = sightline.vtkSightlineTCKReader()
            reader.SetFileName(tck)
            reader.SetScalarFileName(wrong)
            errors = []

            @vtk.calldata_type(vtk.VTK_STRING)
            def on_error(caller, event, message):
                errors.append(message)
            reader.AddObserver(vtk.vtkCommand.ErrorEvent, on_error)
            reader.Update()
            self.assertTrue(errors)
            self.assertIn("track scalar file", errors[0])
            self.assertRegex(errors[0], r"track \d+ has \d+ values but \d+ points|ends after")

    def test_dipy_bundles(self):
        if not os.path.exists(BUNDLES):
            self.skipTest(f"{BUNDLES} missing (Debian package python3-dipy)")
        with tempfile.TemporaryDirectory() as folder:
            with zipfile.ZipFile(BUNDLES) as archive:
                archive.extractall(folder)
            for subject in (1, 3):
                for bundle in ("AF_L", "CST_R", "CC_ForcepsMajor"):
                    self.compare(os.path.join(folder, f"sub_{subject}", f"{bundle}.trk"))

    def test_swc_from_python(self):
        reader = sightline.vtkSightlineSWCReader()
        reader.SetFileName(os.path.join(HERE, os.pardir, "Data", "SWC", "neuron_three_point_soma.swc"))
        reader.Update()
        output = reader.GetOutput()
        self.assertEqual(output.GetNumberOfPoints(), 12)
        parents = vtk_to_numpy(output.GetPointData().GetArray("ParentIndex"))
        self.assertEqual(list(parents[:4]), [-1, 0, 0, 0])
        self.assertEqual(reader.GetNumberOfBranchPoints(), 3)

    def test_tube_mapper_draws_the_neuron_without_opengl(self):
        import vtk
        reader = sightline.vtkSightlineSWCReader()
        reader.SetFileName(os.path.join(HERE, os.pardir, "Data", "SWC", "neuron_three_point_soma.swc"))
        tubes = sightline.vtkSightlineTubeMapper()
        tubes.SetInputConnection(reader.GetOutputPort())
        tubes.SetRadiusArrayName("Radius")
        tubes.SetPredecessorArrayName("ParentIndex")
        actor = vtk.vtkActor()
        actor.SetMapper(tubes)
        camera = vtk.vtkCamera()
        camera.SetFocalPoint(-2, 2, 0)
        camera.SetPosition(-2, -20, 45)
        batch = sightline.vtkSightlineImageRenderer()
        batch.AddActor(actor)
        batch.SetActiveCamera(camera)
        batch.SetSize(160, 120)
        batch.Update()
        rgba = vtk_to_numpy(batch.GetOutput().GetPointData().GetScalars())
        self.assertEqual(tubes.GetNumberOfLinks(), 12)
        # What the mapper holds for tracing: 20 bytes per link (a point, a radius, a
        # predecessor) and more for bookkeeping, plus a BVH Embree allocated.
        self.assertGreaterEqual(tubes.GetGeometryMemoryBytes(), 20 * 12)
        self.assertLess(tubes.GetGeometryMemoryBytes(), 64 * 12)
        self.assertGreater(tubes.GetBVHMemoryBytes(), 0)
        covered = (rgba[:, :3].sum(axis=1) > 0).sum() # the background is black
        self.assertGreater(covered, 1500)
        self.assertLess(covered, 0.5 * len(rgba))

        # Translucent: the same silhouette, and over the black background every pixel dimmer
        # than opaque: a front surface of opacity 0.4 and what shows through it.
        actor.GetProperty().SetOpacity(0.4)
        batch.Modified()
        batch.Update()
        translucent = vtk_to_numpy(batch.GetOutput().GetPointData().GetScalars())
        inside = rgba[:, :3].sum(axis=1) > 0
        # (the union path and the first-hit path may disagree on a grazing silhouette pixel)
        self.assertLessEqual(abs((translucent[:, :3].sum(axis=1) > 0).sum() - covered), 0.002 * covered)
        ratio = translucent[inside, :3].sum(axis=1) / rgba[inside, :3].sum(axis=1)
        self.assertLess(np.percentile(ratio, 99), 1.0)
        self.assertTrue(0.3 < np.median(ratio) < 0.9, np.median(ratio))

if __name__ == "__main__":
    unittest.main()
