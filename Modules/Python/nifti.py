# SPDX-License-Identifier: BSD-3-Clause
"""NIfTI affines for images read with VTK's vtkNIFTIImageReader: the one place Sightline's
examples and sightline-view decide where a NIfTI voxel lies in world (scanner) space.

vtkNIFTIImageReader returns a qform matrix only when qform_code > 0 and an sform matrix only
when sform_code > 0, so code that reads only one of them fails on many real files (DIPY's
func_coef.nii.gz has sform_code 2 and qform_code 0). This module picks the affine as nibabel's
Nifti1Header.get_best_affine() does:

  1. the sform (srow_x, srow_y, srow_z) when sform_code > 0;
  2. else the qform (quaternion, pixdim and qoffset, with qfac = pixdim[0]) when qform_code > 0;
  3. else nibabel's base affine: the voxel sizes on the diagonal, x negated (radiological
     Analyze convention) and the image centre at the origin. (The NIfTI standard's "method 1"
     has no flip and no centring; nibabel, and so DIPY, use this one, which keeps glyphs on the
     same place as in DIPY's own views of such a file.)

and re-expresses it for the VTK image: vtkNIFTIImageReader reverses the slice order when
qfac (pixdim[0]) is negative and puts voxel (i, j, k) at data coordinates origin + index *
spacing, so the matrix handed to a mapper's SetDataToWorldMatrix (or a vtkImageSlice's
SetUserMatrix) is the affine composed with the map from data coordinates back to file indices.
"""
import math
import os

import numpy as np
import vtk

__all__ = ["NiftiError", "VTKErrors", "best_affine", "check_header", "data_to_world",
           "file_axes_to_world", "from_vtk_matrix", "read", "to_vtk_matrix"]

# NIfTI datatype codes and their bits per voxel (the standard's table; RGB, RGBA and complex
# included, so that a reader can name them).
DATATYPE_BITS = {2: 8, 4: 16, 8: 32, 16: 32, 32: 64, 64: 64, 128: 24, 256: 8, 512: 16, 768: 32,
                 1024: 64, 1280: 64, 1536: 128, 1792: 128, 2048: 256, 2304: 32}


class NiftiError(ValueError):
    """A file that is missing or not a readable NIfTI image (the message names it)."""


def _qform_affine(header):
    """The qform as nibabel's Nifti1Header.get_qform() computes it."""
    b, c, d = header.GetQuaternB(), header.GetQuaternC(), header.GetQuaternD()
    w2 = 1.0 - (b * b + c * c + d * d)
    if w2 < 0.0:  # rounding in the stored quaternion: treat as a 180 degree rotation
        if w2 < -3 * np.finfo(np.float32).eps:
            raise NiftiError(f"invalid qform quaternion (b, c, d) = ({b}, {c}, {d})")
        w2 = 0.0
    a = math.sqrt(w2)
    rotation = np.array([
        [a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
        [2 * (b * c + a * d), a * a + c * c - b * b - d * d, 2 * (c * d - a * b)],
        [2 * (b * d - a * c), 2 * (c * d + a * b), a * a + d * d - c * c - b * b]])
    qfac = header.GetPixDim(0)
    qfac = -1.0 if qfac < 0 else 1.0
    zooms = np.array([header.GetPixDim(i) for i in (1, 2, 3)], dtype=float)
    zooms[2] *= qfac
    affine = np.eye(4)
    affine[:3, :3] = rotation * zooms[None, :]
    affine[:3, 3] = [header.GetQOffsetX(), header.GetQOffsetY(), header.GetQOffsetZ()]
    return affine


def _base_affine(header):
    """nibabel's get_base_affine(): voxel sizes, x flipped, the volume's centre at 0."""
    shape = np.array([max(header.GetDim(i), 1) if header.GetDim(0) >= i else 1
                      for i in (1, 2, 3)], dtype=float)
    zooms = np.array([abs(header.GetPixDim(i)) or 1.0 for i in (1, 2, 3)])
    affine = np.eye(4)
    affine[:3, :3] = np.diag(zooms)
    affine[:3, 3] = -(shape - 1.0) / 2.0 * zooms
    affine[0] *= -1.0
    return affine


def best_affine(header):
    """(affine, source): the 4x4 voxel-index-to-world affine of a vtkNIFTIImageHeader (e.g.
    reader.GetNIFTIHeader()) as nibabel's get_best_affine() picks it; source is 'sform',
    'qform' or 'base'."""
    if header.GetSFormCode() > 0:
        affine = np.eye(4)
        affine[:3] = [header.GetSRowX(), header.GetSRowY(), header.GetSRowZ()]
        return affine, "sform"
    if header.GetQFormCode() > 0:
        return _qform_affine(header), "qform"
    return _base_affine(header), "base"


def _data_to_index(reader):
    """4x4 map from the reader output's data coordinates to the file's voxel indices."""
    image = reader.GetOutput()
    origin, spacing = np.array(image.GetOrigin()), np.array(image.GetSpacing())
    matrix = np.eye(4)
    matrix[:3, :3] = np.diag(1.0 / spacing)
    matrix[:3, 3] = -origin / spacing
    if reader.GetQFac() < 0:  # the reader reversed the slices: k_file = (nk - 1) - k_vtk
        extent = image.GetExtent()
        flip = np.eye(4)
        flip[2, 2] = -1.0
        flip[2, 3] = extent[4] + extent[5]
        matrix = flip @ matrix
    return matrix


def to_vtk_matrix(array):
    matrix = vtk.vtkMatrix4x4()
    for row in range(4):
        for column in range(4):
            matrix.SetElement(row, column, float(array[row][column]))
    return matrix


def from_vtk_matrix(matrix):
    return np.array([[matrix.GetElement(row, column) for column in range(4)] for row in range(4)])


def data_to_world(reader, as_vtk=True):
    """The matrix from an updated vtkNIFTIImageReader's output data coordinates to world
    coordinates (for SetDataToWorldMatrix / SetUserMatrix); numpy when as_vtk is False."""
    affine, _ = best_affine(reader.GetNIFTIHeader())
    matrix = affine @ _data_to_index(reader)
    return to_vtk_matrix(matrix) if as_vtk else matrix


def file_axes_to_world(reader, as_vtk=True):
    """The linear map from the file's voxel axes (per unit of voxel size) to world axes: for
    SH directions given in those axes (DIPY fits with FSL-style b-vectors), the mapper's
    SetDirectionToWorldMatrix. It undoes the reader's slice reversal."""
    affine, _ = best_affine(reader.GetNIFTIHeader())
    spacing = np.array(reader.GetOutput().GetSpacing())
    matrix = np.eye(4)
    matrix[:3, :3] = affine[:3, :3] / spacing[None, :]
    return to_vtk_matrix(matrix) if as_vtk else matrix


def check_header(path):
    """Checks the fixed fields of a single-file NIfTI-1 or NIfTI-2 header (.nii, .nii.gz) before
    VTK's reader sees it: the header size and magic, dim[0] in 1..7, positive dimensions, a
    known datatype whose bitpix agrees, a voxel offset past the header and, for an uncompressed
    file, voxel data that fits in the file. Raises NiftiError naming the file and the field
    (VTK's reader can crash on some broken headers instead of reporting them)."""
    import gzip
    import struct

    opener = gzip.open if path.lower().endswith(".gz") else open
    try:
        with opener(path, "rb") as stream:
            head = stream.read(540)
    except (OSError, EOFError) as error:
        raise NiftiError(f"{path}: cannot read it ({error})") from None
    if len(head) < 348:
        raise NiftiError(f"{path}: {len(head)} bytes, shorter than a NIfTI header")
    for order in "<>":
        size = struct.unpack(order + "i", head[:4])[0]
        if size in (348, 540):
            break
    else:
        raise NiftiError(f"{path}: not a NIfTI file (header size field {size}, not 348 or 540)")
    if size == 348:
        magic = head[344:348]
        dim = struct.unpack(order + "8h", head[40:56])
        datatype, bitpix = struct.unpack(order + "2h", head[70:74])
        offset = struct.unpack(order + "f", head[108:112])[0]
        valid_magic = (b"n+1\0",)
    else:
        if len(head) < 540:
            raise NiftiError(f"{path}: {len(head)} bytes, shorter than a NIfTI-2 header")
        magic = head[4:12]
        datatype, bitpix = struct.unpack(order + "2h", head[12:16])
        dim = struct.unpack(order + "8q", head[16:80])
        offset = struct.unpack(order + "q", head[168:176])[0]
        valid_magic = (b"n+2\0\r\n\032\n",)
    if magic not in valid_magic:
        raise NiftiError(f"{path}: not a single-file NIfTI image (magic {bytes(magic)!r})")
    if not 1 <= dim[0] <= 7:
        raise NiftiError(f"{path}: dim[0] is {dim[0]}; a NIfTI image has 1 to 7 dimensions")
    if any(d < 1 for d in dim[1:dim[0] + 1]):
        raise NiftiError(f"{path}: dimensions {list(dim[1:dim[0] + 1])} are not all positive")
    if datatype not in DATATYPE_BITS:
        raise NiftiError(f"{path}: unknown NIfTI datatype {datatype}")
    if bitpix != DATATYPE_BITS[datatype]:
        raise NiftiError(f"{path}: bitpix {bitpix} does not match datatype {datatype} "
                         f"({DATATYPE_BITS[datatype]} bits)")
    if not (math.isfinite(offset) and offset >= size):
        raise NiftiError(f"{path}: voxel offset {offset} lies inside the header")
    if not path.lower().endswith(".gz"):
        count = 1
        for d in dim[1:dim[0] + 1]:
            count *= int(d)
        needed = int(offset) + count * DATATYPE_BITS[datatype] // 8
        if needed > os.path.getsize(path):
            raise NiftiError(f"{path}: the header's {count} voxels need {needed} bytes, the "
                             f"file has {os.path.getsize(path)}")


def read(path, as_vector=True):
    """An updated vtkNIFTIImageReader for `path` (.nii or .nii.gz); with as_vector the 4th axis
    becomes the components of one array (SH coefficients, tensor components). Raises
    NiftiError naming the file when it is missing or unreadable."""
    if not os.path.isfile(path):
        raise NiftiError(f"{path}: no such file")
    reader = vtk.vtkNIFTIImageReader()
    if not reader.CanReadFile(path):
        raise NiftiError(f"{path}: not a NIfTI-1/2 file")
    check_header(path)
    reader.SetFileName(path)
    if as_vector:
        reader.TimeAsVectorOn()
    with VTKErrors() as errors:  # the reader's own messages go into ours
        reader.Update()
    if reader.GetErrorCode() or reader.GetOutput().GetNumberOfPoints() == 0:
        raise NiftiError(f"{path}: could not read it as NIfTI" + errors.detail())
    return reader


class VTKErrors:
    """Collects VTK's error and warning messages while active (instead of printing them), so
    that a failed read can be reported in one line that names the file."""

    def __enter__(self):
        self.window = vtk.vtkStringOutputWindow()
        self.previous = vtk.vtkOutputWindow.GetInstance()
        vtk.vtkOutputWindow.SetInstance(self.window)
        self.text = ""
        return self

    def __exit__(self, *exception):
        vtk.vtkOutputWindow.SetInstance(self.previous)
        self.text = self.window.GetOutput().strip()
        return False

    def detail(self):
        """The last message's text without VTK's 'ERROR: In file, line N' prefix, as
        ' (text)', or ''."""
        lines = [line.strip() for line in self.text.splitlines() if line.strip()]
        lines = [line for line in lines if not line.startswith(("ERROR:", "Warning:", "vtk"))] or lines
        return f" ({lines[-1]})" if lines else ""
