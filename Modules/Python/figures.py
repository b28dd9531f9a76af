# SPDX-License-Identifier: BSD-3-Clause
"""Report figures on machines with no display, no OpenGL and little memory.

mosaic() draws rows of evenly spaced slices of an SH or tensor image (NIfTI or MRtrix3) as
exact glyphs, and/or a tractogram as exact tubes (whole, or a slab around each slice), over an
anatomical underlay, each panel framed on the brain and labelled with orientation letters and
its slice position, and returns (and optionally writes) one image:

    import sightline.figures
    image = sightline.figures.mosaic("fod.nii.gz", underlay="t1.nii.gz",
                                     panels="axial:8,coronal:8,sagittal:8",
                                     size=(3200, 1200), output="report.png")

Everything is traced by vtkSightlineImageRenderer: no X connection is opened, no OpenGL
context made. Memory stays bounded by the slices drawn, not by the image: a NIfTI file is read
in one sequential pass (a .nii.gz decompressed once) that keeps only the planes the panels show;
a .mif is read slice by slice through the reader's extents; each panel's glyphs are freed once
it is traced. The underlay (a 3-D scalar image) is read whole.

The same function is `sightline-view IMAGE --underlay T1 --mosaic axial:8,... --output F.png`
(and `sightline-view TRACTS.trx --underlay T1 --mosaic ... --slab 6 --output F.png`).
"""
import gzip
import os
import time
import zlib
from types import SimpleNamespace

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline
from sightline import nifti, view

__all__ = ["FigureError", "mosaic", "parse_panels"]

# World axis (RAS) normal to each orientation, and the panel's screen axes in world terms:
# neurological convention (the subject's right on the right), axial seen from above, coronal
# from behind, sagittal from the right. Letters: (left edge, right edge, bottom, top).
VIEWS = {
    "axial": (2, (1, 0, 0), (0, 1, 0), ("L", "R", "P", "A")),
    "coronal": (1, (1, 0, 0), (0, 0, 1), ("L", "R", "I", "S")),
    "sagittal": (0, (0, 1, 0), (0, 0, 1), ("P", "A", "I", "S")),
}
WORLD_AXIS_NAMES = "xyz"
# NIfTI datatype codes -> numpy types (byte order added from the header).
NIFTI_TYPES = {2: "u1", 4: "i2", 8: "i4", 16: "f4", 64: "f8", 256: "i1", 512: "u2", 768: "u4",
               1024: "i8", 1280: "u8"}


class FigureError(ValueError):
    """A figure that cannot be made from these inputs (the message says why)."""


def parse_panels(text):
    """'axial:8,coronal:8,sagittal:8' -> [('axial', 8), ('coronal', 8), ('sagittal', 8)]."""
    rows = []
    for part in text.split(","):
        name, _, count = part.strip().partition(":")
        if name not in VIEWS:
            raise FigureError(f"--mosaic {text}: '{name}' is not axial, coronal or sagittal")
        try:
            count = int(count) if count else 8
        except ValueError:
            raise FigureError(f"--mosaic {text}: '{part}' needs a whole number of slices") from None
        if not 1 <= count <= 64:
            raise FigureError(f"--mosaic {text}: 1 to 64 slices per row, got {count}")
        rows.append((name, count))
    return rows


# -- reading only the planes drawn ------------------------------------------------------------
class NiftiPlanes:
    """Planes of a 3-D or 4-D NIfTI image (values on the 4th axis as components), read in one
    sequential pass; data coordinates are the voxel index times the voxel size."""

    def __init__(self, path):
        reader = vtk.vtkNIFTIImageReader()
        if not os.path.isfile(path) or not reader.CanReadFile(path):
            raise FigureError(f"{path}: no such file" if not os.path.isfile(path)
                              else f"{path}: not a NIfTI-1/2 file")
        try:
            nifti.check_header(path)
        except nifti.NiftiError as error:
            raise FigureError(str(error)) from None
        reader.SetFileName(path)
        with nifti.VTKErrors() as errors:
            reader.UpdateInformation()
        header = reader.GetNIFTIHeader()
        if reader.GetErrorCode() or header is None:
            raise FigureError(f"{path}: could not read its NIfTI header" + errors.detail())
        self.path = path
        dims = [max(header.GetDim(i), 1) if header.GetDim(0) >= i else 1 for i in range(1, 8)]
        self.shape, self.count = tuple(dims[:3]), int(np.prod(dims[3:]))
        code = header.GetDataType()
        if code not in NIFTI_TYPES:
            raise FigureError(f"{path}: NIfTI datatype {code} is not a plain number type")
        opener = gzip.open if path.lower().endswith(".gz") else open
        with opener(path, "rb") as stream:
            size = stream.read(4)
        order = "<" if int.from_bytes(size, "little") in (348, 540) else ">"
        self.dtype = np.dtype(order + NIFTI_TYPES[code])
        self.offset = int(header.GetVoxOffset())
        slope, inter = header.GetSclSlope(), header.GetSclInter()
        self.scaling = (slope, inter) if slope not in (0.0, 1.0) or inter != 0.0 else None
        affine, self.affine_source = nifti.best_affine(header)
        self.spacing = np.array([abs(header.GetPixDim(i)) or 1.0 for i in (1, 2, 3)])
        self.origin = np.zeros(3)
        self.data_to_world = affine @ np.diag(np.append(1.0 / self.spacing, 1.0))
        self.file_axes = np.eye(4)
        self.file_axes[:3, :3] = affine[:3, :3] / self.spacing[None, :]

    def volumes(self, first_only=False):
        """Yields the image's 3-D volumes in file order, as (z, y, x) float32 arrays."""
        opener = gzip.open if self.path.lower().endswith(".gz") else open
        nx, ny, nz = self.shape
        size = nx * ny * nz * self.dtype.itemsize
        with opener(self.path, "rb") as stream:
            for index in range(1 if first_only else self.count):
                try:
                    if index == 0:
                        stream.seek(self.offset)
                    data = stream.read(size)
                except (OSError, EOFError, zlib.error) as error:  # a damaged .gz
                    raise FigureError(f"{self.path}: cannot read its voxel data ({error})") from None
                if len(data) != size:
                    raise FigureError(f"{self.path}: the file ends inside its voxel data")
                volume = np.frombuffer(data, self.dtype).reshape(nz, ny, nx).astype(np.float32)
                if self.scaling:
                    with np.errstate(invalid="ignore", over="ignore"):  # a NaN or huge slope
                        volume = volume * np.float32(self.scaling[0]) + np.float32(self.scaling[1])
                yield volume

    def mask_box(self):
        """(lower, upper) voxel indices of the nonzero voxels of the first volume (the brain
        for SH's l = 0 term or a tensor's xx), or None when it is all zero."""
        volume = next(self.volumes(first_only=True))
        inside = np.nonzero(np.abs(volume) > 0)
        if not inside[0].size:
            return None
        zyx = [(int(a.min()), int(a.max())) for a in inside]
        return np.array([zyx[2][0], zyx[1][0], zyx[0][0]]), np.array([zyx[2][1], zyx[1][1], zyx[0][1]])

    def planes(self, wanted):
        """{(axis, index): vtkImageData one voxel thick with all components} in one pass."""
        nx, ny, nz = self.shape
        out = {}
        for key in wanted:
            axis, _ = key
            count = (ny * nz, nx * nz, nx * ny)[axis]
            out[key] = np.empty((count, self.count), np.float32)
        for component, volume in enumerate(self.volumes()):
            for (axis, index), values in out.items():
                plane = np.take(volume, index, axis=2 - axis)  # volume is (z, y, x)
                values[:, component] = plane.reshape(-1)  # x fastest, as VTK orders points
            del volume
        return {key: self._image(key, values) for key, values in out.items()}

    def _image(self, key, values):
        axis, index = key
        extent = [0, self.shape[0] - 1, 0, self.shape[1] - 1, 0, self.shape[2] - 1]
        extent[2 * axis] = extent[2 * axis + 1] = index
        return plane_image(extent, self.spacing, self.origin, values)


class MifPlanes:
    """Planes of an MRtrix3 image through vtkSightlineMIFReader's extents (only those read)."""

    def __init__(self, path):
        if not os.path.isfile(path):
            raise FigureError(f"{path}: no such file")
        self.reader = sightline.vtkSightlineMIFReader()
        self.reader.SetFileName(path)
        with nifti.VTKErrors() as errors:
            self.reader.UpdateInformation()
        if self.reader.GetErrorCode():
            raise FigureError(f"{path}: could not read its MRtrix3 header" + errors.detail())
        info = self.reader.GetOutputInformation(0)
        whole = info.Get(vtk.vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT())
        self.whole = list(whole)
        self.shape = tuple(whole[2 * a + 1] - whole[2 * a] + 1 for a in range(3))
        self.spacing = np.array(info.Get(vtk.vtkDataObject.SPACING()))
        self.origin = np.array(info.Get(vtk.vtkDataObject.ORIGIN()))
        self.data_to_world = nifti.from_vtk_matrix(self.reader.GetTransformMatrix())
        self.file_axes, self.affine_source = None, "mif"

    def mask_box(self):
        return None  # finding it would read the whole file: the panels span the image

    def planes(self, wanted):
        out = {}
        for axis, index in wanted:
            extent = list(self.whole)
            extent[2 * axis] = extent[2 * axis + 1] = self.whole[2 * axis] + index
            with nifti.VTKErrors() as errors:
                self.reader.UpdateExtent(extent)
            image = self.reader.GetOutput()
            if self.reader.GetErrorCode() or image.GetNumberOfPoints() == 0:
                raise FigureError(f"could not read slice {index}" + errors.detail())
            copy = vtk.vtkImageData()
            copy.DeepCopy(image)
            out[(axis, index)] = copy
        return out


def plane_image(extent, spacing, origin, values):
    image = vtk.vtkImageData()
    image.SetExtent(*extent)
    image.SetSpacing(*spacing)
    image.SetOrigin(*origin)
    array = numpy_to_vtk(values, deep=True)
    array.SetName("coefficients")
    image.GetPointData().SetScalars(array)
    return image


def open_planes(path):
    lower = path.lower()
    if lower.endswith((".nii", ".nii.gz")):
        return NiftiPlanes(path)
    if lower.endswith((".mif", ".mif.gz")):
        return MifPlanes(path)
    raise FigureError(f"{path}: a mosaic draws an SH or tensor image (.nii, .nii.gz, .mif, "
                      ".mif.gz)")


# -- panels -----------------------------------------------------------------------------------
def closest_axis(data_to_world, world_axis):
    columns = data_to_world[:3, :3] / np.linalg.norm(data_to_world[:3, :3], axis=0)
    return int(np.argmax(np.abs(columns[world_axis])))


def box_corners(lower, upper, source):
    """World coordinates of the 8 corners of a voxel-index box (voxel edges included)."""
    corners = []
    for i in range(8):
        index = np.where([(i >> a) & 1 for a in range(3)], upper + 0.5, lower - 0.5)
        data = source.origin + index * source.spacing
        corners.append((source.data_to_world @ np.append(data, 1.0))[:3])
    return np.array(corners)


def slice_indices(lower, upper, count):
    """`count` evenly spaced indices strictly inside [lower, upper]."""
    return sorted({int(round(lower + (upper - lower) * (i + 1) / (count + 1))) for i in range(count)})


def draw_text(canvas, text, x, y, size, anchor="left", colour=(255, 255, 255)):
    """Writes text (white by default) with a dark shadow into canvas (h, w, 3, top row first)
    at pixel (x, y) (its left/centre/right, middle), with VTK's FreeType renderer (no OpenGL).
    Returns its width in pixels."""
    renderer = vtk.vtkTextRenderer()
    prop = vtk.vtkTextProperty()
    prop.SetFontSize(size)
    prop.BoldOn()
    prop.SetColor(1, 1, 1)
    image, dims = vtk.vtkImageData(), [0, 0]
    if not renderer.RenderString(prop, text, image, dims, 72):
        return 0
    width, height, _ = image.GetDimensions()
    alpha = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, 4)[::-1, :, 3]
    rows, columns = np.nonzero(alpha)
    if not rows.size:
        return 0
    alpha = alpha[rows.min():rows.max() + 1, columns.min():columns.max() + 1] / 255.0
    h, w = alpha.shape
    left = {"left": x, "centre": x - w // 2, "right": x - w}[anchor]
    top = y - h // 2
    for dx, dy, value in ((1, 1, (0, 0, 0)), (0, 0, colour)):  # shadow, then the text
        y0, x0 = max(top + dy, 0), max(left + dx, 0)
        y1, x1 = min(top + dy + h, canvas.shape[0]), min(left + dx + w, canvas.shape[1])
        if y1 <= y0 or x1 <= x0:
            continue
        a = alpha[y0 - top - dy:y1 - top - dy, x0 - left - dx:x1 - left - dx, None]
        region = canvas[y0:y1, x0:x1].astype(np.float32)
        blended = region * (1 - a) + np.array(value, np.float32) * a
        canvas[y0:y1, x0:x1] = blended.round().astype(np.uint8)
    return w


def draw_direction_key(canvas, x, y, size):
    """The direction colours' key, right-aligned at (x, y): red L-R, green A-P, blue S-I (the
    |tangent| and |lobe direction| colouring of tubes and glyphs)."""
    for text, colour in (("S-I", (90, 140, 255)), ("A-P", (60, 220, 60)), ("L-R", (255, 70, 70))):
        x -= draw_text(canvas, text, x, y, size, "right", colour) + size // 2


def draw_scalar_bar(canvas, x, y, height, low, high, size):
    """A grey ramp from `low` (bottom) to `high` (top), `height` pixels tall with its top right
    corner at (x, y), labelled with both values: the underlay's window."""
    width = max(6, size // 2)
    ramp = np.linspace(255, 0, height)[:, None, None].round().astype(np.uint8)
    y1, x0 = min(y + height, canvas.shape[0]), max(x - width, 0)
    canvas[y:y1, x0:x] = ramp[:y1 - y]
    draw_text(canvas, f"{high:.4g}", x0 - 4, y + size // 2, size, "right")
    draw_text(canvas, f"{low:.4g}", x0 - 4, y1 - size // 2, size, "right")


class Tractogram:
    """A .trk, .tck or .trx read whole (direction colours, RAS mm), drawn as exact tubes: the
    whole tractogram (built once, traced in every panel) or per panel the runs of streamline
    points within a slab around the slice."""

    def __init__(self, path, radius=None):
        if view.lower_extension(path) not in (".trk", ".tck", ".trx"):
            raise FigureError(f"{path}: a mosaic draws streamlines from .trk, .tck or .trx")
        try:
            self.data = view.read_tubes(path)
        except view.ViewError as error:
            raise FigureError(str(error)) from None
        bounds = np.array(self.data.GetBounds())
        self.lower, self.upper = bounds[0::2], bounds[1::2]
        self.radius = radius or min(0.5, float(np.linalg.norm(self.upper - self.lower)) / 200.0)
        cells = self.data.GetLines()
        self.offsets = vtk_to_numpy(cells.GetOffsetsArray())
        self.ids = vtk_to_numpy(cells.GetConnectivityArray())
        self.whole = None

    def corners(self):
        return np.array([np.where([(i >> a) & 1 for a in range(3)], self.upper, self.lower)
                         for i in range(8)])

    def actor(self, world_axis, position, slab=None):
        """The tubes' actor for a panel: the whole tractogram (slab None) or the runs of
        points within slab / 2 of `position` along `world_axis`."""
        if slab is None:
            if self.whole is None:
                self.whole = self._actor(self.data)
            return self.whole
        points = vtk_to_numpy(self.data.GetPoints().GetData())
        keep = np.abs(points[self.ids, world_axis] - position) <= 0.5 * slab
        line = np.repeat(np.arange(len(self.offsets) - 1), np.diff(self.offsets))
        new_line = np.ones(len(self.ids), bool)
        new_line[1:] = line[1:] != line[:-1]
        previous = np.concatenate([[False], keep[:-1]])
        starts = keep & (new_line | ~previous)
        run = np.cumsum(starts) - 1  # the run each kept entry belongs to
        counts = np.bincount(run[keep], minlength=int(starts.sum()))
        long_runs = counts >= 2  # a tube link needs two points
        chosen = keep.copy()
        chosen[keep] = long_runs[run[keep]]
        offsets = np.concatenate([[0], np.cumsum(counts[long_runs])]).astype(np.int64)
        cells = vtk.vtkCellArray()
        cells.SetData(numpy_to_vtk(offsets, deep=True, array_type=vtk.VTK_ID_TYPE),
                      numpy_to_vtk(self.ids[chosen].astype(np.int64), deep=True,
                                   array_type=vtk.VTK_ID_TYPE))
        piece = vtk.vtkPolyData()
        piece.SetPoints(self.data.GetPoints())
        piece.GetPointData().ShallowCopy(self.data.GetPointData())
        piece.SetLines(cells)
        return self._actor(piece) if len(offsets) > 1 else None

    def _actor(self, data):
        mapper = sightline.vtkSightlineTubeMapper()
        mapper.SetInputDataObject(data)
        mapper.SetColorModeToDirectScalars()
        mapper.SetRadius(self.radius)
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        view.shade(actor.GetProperty())
        return actor


class Panel(SimpleNamespace):
    """One panel: its place in the grid, its orientation and the world point its slice
    plane goes through (plus, for an image, the slice's voxel axis and index)."""


def plan_panels(rows, source, tracts):
    """The panels in reading order, and the world corners of the box they frame: the image's
    brain (nonzero first volume), else the streamlines' bounds."""
    panels = []
    if source is not None:
        box = source.mask_box()
        lower, upper = box if box is not None else (np.zeros(3, int), np.array(source.shape) - 1)
        corners = box_corners(lower, upper, source)
        for row, (orientation, count) in enumerate(rows):
            world_axis = VIEWS[orientation][0]
            axis = closest_axis(source.data_to_world, world_axis)
            indices = slice_indices(lower[axis], upper[axis], count)
            if source.data_to_world[world_axis, axis] < 0:
                indices.reverse()  # panels run from low to high world coordinates
            for column, index in enumerate(indices):
                centre = source.origin + source.spacing * (lower + upper) / 2.0
                centre[axis] = source.origin[axis] + source.spacing[axis] * index
                centre = (source.data_to_world @ np.append(centre, 1.0))[:3]
                panels.append(Panel(row=row, column=column, orientation=orientation,
                                    axis=axis, index=index, centre=centre))
        return panels, corners
    corners = tracts.corners()  # without an image, mosaic() has a tractogram
    low, high = corners.min(axis=0), corners.max(axis=0)
    for row, (orientation, count) in enumerate(rows):
        world_axis = VIEWS[orientation][0]
        for column in range(count):
            centre = (low + high) / 2.0
            centre[world_axis] = low[world_axis] + (high - low)[world_axis] * (column + 1) / (count + 1)
            panels.append(Panel(row=row, column=column, orientation=orientation, axis=None,
                                index=None, centre=centre))
    return panels, corners


def panel_camera(panel, corners, aspect):
    """A parallel camera looking at the panel's plane from its viewing side, framing the box's
    corners with a small margin."""
    _, right, up, _ = VIEWS[panel.orientation]
    right, up = np.array(right, float), np.array(up, float)
    toward_camera = np.cross(right, up)
    extent_right, extent_up = corners @ right, corners @ up
    middle = (right * (extent_right.min() + extent_right.max()) / 2
              + up * (extent_up.min() + extent_up.max()) / 2)
    focal = middle + toward_camera * np.dot(panel.centre, toward_camera)
    depth = float(np.ptp(corners @ toward_camera)) + 10.0
    camera = vtk.vtkCamera()
    camera.ParallelProjectionOn()
    camera.SetFocalPoint(*focal)
    camera.SetPosition(*(focal + toward_camera * depth))
    camera.SetViewUp(*up)
    camera.SetParallelScale(1.04 * max(np.ptp(extent_up) / 2, np.ptp(extent_right) / 2 / aspect))
    camera.SetClippingRange(0.1, 2 * depth)
    return camera, toward_camera, up


def mosaic(image=None, underlay=None, panels="axial:8,coronal:8,sagittal:8", size=(3200, 1200),
           output=None, tractogram=None, slab=None, radius=None, basis=None, legacy=None,
           layout=None, frame="world", scale=1.0, tensor_shape="ellipsoid",
           background=(0.0, 0.0, 0.0), labels=True, scalar_bar=False, supersample=None,
           verbose=True):
    """Rows of evenly spaced slices, traced without OpenGL: glyphs of `image` (an SH or tensor
    NIfTI/.mif) and/or tubes of `tractogram` (.trk, .tck, .trx) over an optional scalar
    `underlay` (NIfTI). Returns the (height, width, 3) uint8 picture (top row first) and writes
    it to `output` (.png) when given.

    panels: 'axial:8,coronal:8,sagittal:8' (a row per entry; slices evenly spaced over the
    brain: the image's nonzero first volume, else the streamlines' bounds); size: (width,
    height) of the whole figure; slab: draw per panel only the streamlines' runs within slab/2
    mm of the slice (None: the whole tractogram, cut by the underlay plane); radius: tube
    radius in mm (default 0.5); basis/legacy/layout/frame/scale/tensor_shape: as
    sightline-view's options (basis 'dipy' or 'mrtrix3', default by file type); background: RGB
    in [0, 1]; labels: orientation letters (on each row's first panel) and every panel's slice
    position, and the direction colours' key; scalar_bar: the underlay's grey window as a
    labelled ramp in the first row's last panel; supersample: rays per pixel along each axis (None: 2 where a voxel or a tube is
    under 6 pixels wide, which otherwise aliases into moire, else 1)."""
    start = time.perf_counter()
    rows = parse_panels(panels) if isinstance(panels, str) else list(panels)
    width, height = (int(v) for v in size)
    if width <= 0 or height <= 0:
        raise FigureError(f"the figure size must be positive, got {width}x{height}")
    columns = max(count for _, count in rows)
    panel_w, panel_h = width // columns, height // len(rows)
    if panel_w < 16 or panel_h < 16:
        raise FigureError(f"{width}x{height} leaves panels of {panel_w}x{panel_h} pixels: make "
                          "the figure larger or use fewer slices")
    if image is None and tractogram is None:
        raise FigureError("a mosaic needs an SH or tensor image or a tractogram")
    if slab is not None and not slab > 0:
        raise FigureError(f"the slab must be a positive thickness in mm, got {slab}")
    options = SimpleNamespace(basis=basis, legacy=legacy, layout=layout, frame=frame,
                              scale=scale, tensor_shape=tensor_shape)
    source = open_planes(image) if image is not None else None
    if source is not None and frame == "voxel" and source.file_axes is None:
        raise FigureError(f"{image}: frame 'voxel' is for NIfTI files (.mif directions are in "
                          "world axes)")
    try:
        under = view.Underlay(underlay) if underlay else None
    except view.ViewError as error:
        raise FigureError(str(error).replace("--underlay ", "underlay ")) from None
    tracts = Tractogram(tractogram, radius) if tractogram is not None else None
    plan, corners = plan_panels(rows, source, tracts)
    if verbose:
        print(f"mosaic: {len(plan)} panels of {panel_w}x{panel_h}", flush=True)
    planes, kind = {}, None
    if source is not None:
        if verbose:
            print(f"  reading {len(plan)} slices of {os.path.basename(image)} ...", flush=True)
        planes = source.planes(sorted({(p.axis, p.index) for p in plan}))
        count = next(iter(planes.values())).GetNumberOfScalarComponents()
        extension = ".mif" if isinstance(source, MifPlanes) else ".nii"
        try:
            kind, detail = view.GlyphLayer.classify(image, count, extension, False, options)
        except view.ViewError as error:
            raise FigureError(str(error)) from None
        data_to_world = nifti.to_vtk_matrix(source.data_to_world)
        file_axes = nifti.to_vtk_matrix(source.file_axes) if source.file_axes is not None else None
    canvas = np.empty((height, width, 3), np.uint8)
    canvas[:] = np.round(np.array(background) * 255)
    for number, panel in enumerate(plan):
        panel_start = time.perf_counter()
        world_axis, _, _, letters = VIEWS[panel.orientation]
        camera, toward_camera, up = panel_camera(panel, corners, panel_w / panel_h)
        renderer = sightline.vtkSightlineImageRenderer()
        beneath = 0.0  # how far behind the slice plane the underlay goes
        if kind is not None:
            plane = planes[(panel.axis, panel.index)]
            if not any((p.axis, p.index) == (panel.axis, panel.index) for p in plan[number + 1:]):
                del planes[(panel.axis, panel.index)]  # no later panel shows it
            if kind == "tensor" and view.LAYOUTS[detail][1] is not None:
                plane = view.GlyphLayer.permuted(plane, view.LAYOUTS[detail][1])
            mapper, actor = view.glyph_actor(kind, detail, count, options, plane, data_to_world,
                                             file_axes)
            getattr(mapper, "SetSliceOrientationTo" + panel.orientation.capitalize())()
            mapper.SetSliceNumber(panel.index)
            renderer.AddActor(actor)
            beneath = 0.6 * scale * 0.5 * float(min(source.spacing))  # beneath the glyphs
        if tracts is not None:
            actor = tracts.actor(world_axis, panel.centre[world_axis], slab)
            if actor is not None:
                renderer.AddActor(actor)
            if slab is not None:
                beneath = max(beneath, 0.5 * slab)  # the whole slab in front of the plane
        if under is not None and under.place(panel.centre, toward_camera, -beneath, clamp=False):
            renderer.AddImageSlice(under.actor)
        for light in view.glyph_lights(panel.centre, toward_camera, up):
            renderer.AddLight(light)
        renderer.SetActiveCamera(camera)
        # Glyphs and tubes a few pixels wide alias into moire at one ray a pixel: trace k x k
        # rays a pixel and average them (k from the smallest feature's size in pixels).
        pixels_per_mm = panel_h / (2.0 * camera.GetParallelScale())
        features = ([float(min(source.spacing))] if kind else []) + \
            ([2.0 * tracts.radius] if tracts is not None else [])
        feature = min(features)
        k = supersample or (1 if feature * pixels_per_mm >= 6 else 2)
        renderer.SetSize(k * panel_w, k * panel_h)
        renderer.SetBackground(*background)
        renderer.Update()
        picture, _ = view.image_arrays(renderer.GetOutput())
        if k > 1:
            picture = picture[..., :3].reshape(panel_h, k, panel_w, k, 3).mean(axis=(1, 3))
            picture = picture.round().astype(np.uint8)
        y0, x0 = panel.row * panel_h, panel.column * panel_w
        canvas[y0:y0 + panel_h, x0:x0 + panel_w] = picture[..., :3]
        position = f"{WORLD_AXIS_NAMES[world_axis]} = {panel.centre[world_axis]:.1f} mm"
        if labels:
            text = max(10, panel_h // 18)
            if panel.column == 0:  # letters once per row: between panels they would read "R L"
                draw_text(canvas, letters[0], x0 + 4, y0 + panel_h // 2, text)
                draw_text(canvas, letters[1], x0 + panel_w - 4, y0 + panel_h // 2, text, "right")
                draw_text(canvas, letters[3], x0 + panel_w // 2, y0 + text, text, "centre")
                draw_text(canvas, letters[2], x0 + panel_w // 2, y0 + panel_h - text, text,
                          "centre")
            draw_text(canvas, position, x0 + 4, y0 + panel_h - text, max(8, text * 3 // 4))
        del renderer  # this panel's glyphs (and slab tubes) go now
        if verbose:
            print(f"  panel {number + 1}/{len(plan)}: {panel.orientation} at {position} "
                  f"({time.perf_counter() - panel_start:.1f} s)", flush=True)
    if labels:
        text = max(10, panel_h // 18)
        right = (max(p.column for p in plan if p.row == 0) + 1) * panel_w - 6
        draw_direction_key(canvas, right, text, max(8, text * 3 // 4))
    if scalar_bar and under is not None:
        prop = under.actor.GetProperty()
        low = prop.GetColorLevel() - 0.5 * prop.GetColorWindow()
        right = (max(p.column for p in plan if p.row == 0) + 1) * panel_w - 6
        draw_scalar_bar(canvas, right, 2 * max(10, panel_h // 18), panel_h // 2, low,
                        low + prop.GetColorWindow(), max(8, panel_h // 24))
    if output:
        write_png(canvas, output)
    if verbose:
        print(f"mosaic: {width}x{height} in {time.perf_counter() - start:.1f} s"
              + (f" -> {output}" if output else ""), flush=True)
    return canvas


def write_png(canvas, path):
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FigureError(f"{path}: no folder {folder}")
    height, width, _ = canvas.shape
    image = vtk.vtkImageData()
    image.SetDimensions(width, height, 1)
    array = numpy_to_vtk(np.ascontiguousarray(canvas[::-1]).reshape(-1, 3), deep=True)
    image.GetPointData().SetScalars(array)
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()
