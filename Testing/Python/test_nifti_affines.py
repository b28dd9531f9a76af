# SPDX-License-Identifier: BSD-3-Clause
"""sightline.nifti against nibabel, the reference for NIfTI affines: the affine it picks must
equal nibabel's Nifti1Header.get_best_affine() (sform when sform_code > 0, else qform, else the
base affine), on files constructed here for each case (with and without qfac -1, which makes
vtkNIFTIImageReader reverse the slices) and on real files shipped with Debian (DIPY's sform-only
func_coef.nii.gz, nibabel's test images, and the SHData fixture's small_64D files when given).
The VTK-side matrix must put each voxel where nibabel's affine puts it: a marker voxel is
found in VTK's image and mapped through data_to_world."""
import glob
import os
import tempfile
import unittest

import nibabel as nib
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

from sightline import nifti

DIPY_FILES = "/usr/lib/python3/dist-packages/dipy/data/files"
NIBABEL_DATA = "/usr/lib/python3/dist-packages/nibabel/tests/data"
SH_DATA = os.environ.get("SIGHTLINE_SH_DATA_DIR", "")


def rotation(angles):
    """A rotation from three angles (about x, then y, then z)."""
    result = np.eye(3)
    for axis, angle in enumerate(angles):
        c, s = np.cos(angle), np.sin(angle)
        turn = np.eye(3)
        i, j = [k for k in range(3) if k != axis]
        turn[i, i], turn[i, j], turn[j, i], turn[j, j] = c, -s, s, c
        result = turn @ result
    return result


def make_affine(flip):
    affine = np.eye(4)
    affine[:3, :3] = rotation((0.3, -0.5, 1.1)) @ np.diag([1.5, 2.0, 2.5])
    if flip:  # negative determinant: qfac -1
        affine[:3, 2] *= -1
    affine[:3, 3] = [-40.0, 12.5, 7.0]
    return affine


class NiftiAffines(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.TemporaryDirectory()
        self.addCleanup(self.folder.cleanup)

    def check_file(self, path, expect_source=None):
        """best_affine equals nibabel's; data_to_world puts a VTK voxel where nibabel's affine
        puts the same file voxel. Returns the source."""
        image = nib.load(path)
        reader = nifti.read(path, as_vector=True)
        affine, source = nifti.best_affine(reader.GetNIFTIHeader())
        np.testing.assert_allclose(affine, image.header.get_best_affine(), atol=1e-4,
                                   err_msg=f"{path} ({source})")
        if expect_source:
            self.assertEqual(source, expect_source, path)
        # Every VTK voxel's world position against nibabel's for its file index: VTK's points
        # are x fastest; the reader reverses k when qfac is -1, so find indices by value.
        vtk_image = reader.GetOutput()
        dims = vtk_image.GetDimensions()
        to_world = nifti.data_to_world(reader, as_vtk=False)
        ijk = np.stack(np.meshgrid(*[np.arange(d) for d in dims], indexing="ij"), -1)
        data = np.array(vtk_image.GetOrigin()) + ijk * np.array(vtk_image.GetSpacing())
        world_vtk = data.reshape(-1, 3) @ to_world[:3, :3].T + to_world[:3, 3]
        # The file index of each VTK voxel, from the reader's slice order.
        file_k = ijk[..., 2] if reader.GetQFac() > 0 else dims[2] - 1 - ijk[..., 2]
        file_ijk = np.stack([ijk[..., 0], ijk[..., 1], file_k], -1).reshape(-1, 3)
        reference = image.header.get_best_affine()
        world_nib = file_ijk @ reference[:3, :3].T + reference[:3, 3]
        np.testing.assert_allclose(world_vtk, world_nib, atol=1e-3, err_msg=path)
        # ... and the reader really put those file voxels there (values match).
        values = np.asarray(image.dataobj.get_unscaled())  # VTK leaves scl_slope to the user
        values = values.reshape(values.shape[:3] + (-1,))
        vtk_values = vtk_to_numpy(vtk_image.GetPointData().GetScalars()).reshape(
            dims[2], dims[1], dims[0], -1).transpose(2, 1, 0, 3)
        flat = vtk_values.reshape(-1, vtk_values.shape[-1])
        expected = values[file_ijk[:, 0], file_ijk[:, 1], file_ijk[:, 2]]
        np.testing.assert_allclose(flat, expected, rtol=1e-5, err_msg=path)
        return source

    def write(self, name, qform, sform, flip=False, shape=(5, 6, 7, 3)):
        rng = np.random.default_rng(len(name))
        data = rng.normal(size=shape).astype(np.float32)
        affine = make_affine(flip)
        image = nib.Nifti1Image(data, affine)
        image.set_qform(affine if qform else None, code=1 if qform else 0)
        image.set_sform(affine if sform else None,
                        code=2 if sform else 0)
        if not qform:
            # nibabel keeps pixdim[0] as qfac: -1 when the affine flips, as other writers do.
            image.header["pixdim"][0] = -1.0 if flip else 1.0
        path = os.path.join(self.folder.name, name)
        nib.save(image, path)
        header = nib.load(path).header
        self.assertEqual((int(header["qform_code"]), int(header["sform_code"])),
                         (1 if qform else 0, 2 if sform else 0))
        return path

    def test_sform_only(self):
        for flip in (False, True):
            self.check_file(self.write(f"sform{flip}.nii.gz", False, True, flip), "sform")

    def test_qform_only(self):
        for flip in (False, True):
            self.check_file(self.write(f"qform{flip}.nii", True, False, flip), "qform")

    def test_no_transform(self):
        for flip in (False, True):
            self.check_file(self.write(f"none{flip}.nii.gz", False, False, flip), "base")

    def test_sform_wins_over_qform(self):
        path = os.path.join(self.folder.name, "both.nii.gz")
        image = nib.Nifti1Image(np.zeros((4, 4, 4), np.float32), make_affine(False))
        image.set_qform(make_affine(True), code=1)  # a different qform: must be ignored
        image.set_sform(make_affine(False), code=1)
        nib.save(image, path)
        self.check_file(path, "sform")

    def test_dipy_func_coef_is_sform_only(self):
        path = os.path.join(DIPY_FILES, "func_coef.nii.gz")
        header = nib.load(path).header
        self.assertEqual((int(header["qform_code"]), int(header["sform_code"])), (0, 2))
        self.assertEqual(self.check_file(path), "sform")

    def test_real_files(self):
        paths = sorted(glob.glob(os.path.join(NIBABEL_DATA, "*.nii*")))
        paths = [p for p in paths if "dconn" not in p and "nifti2" not in p]
        if SH_DATA:
            paths += sorted(glob.glob(os.path.join(SH_DATA, "small_64D_*.nii.gz")))
        sources = []
        for path in paths:
            if len(nib.load(path).shape) > 4:
                continue
            with self.subTest(path=os.path.basename(path)):
                sources.append(self.check_file(path))
        self.assertGreaterEqual(len(sources), 5)

    def test_errors_name_the_file(self):
        missing = os.path.join(self.folder.name, "missing.nii.gz")
        with self.assertRaisesRegex(nifti.NiftiError, "missing.nii.gz: no such file"):
            nifti.read(missing)
        garbage = os.path.join(self.folder.name, "garbage.nii")
        with open(garbage, "wb") as stream:
            stream.write(b"not a nifti header" * 30)
        with self.assertRaisesRegex(nifti.NiftiError, "garbage.nii: "):
            nifti.read(garbage)


if __name__ == "__main__":
    unittest.main()
