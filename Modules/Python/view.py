# SPDX-License-Identifier: BSD-3-Clause
"""sightline-view: open a user's own files, see them.

  sightline-view FILE [FILE ...] [options]

Each FILE goes to the Sightline mapper that fits it, all in one window (or, with --output, one
image rendered without a window or OpenGL by vtkSightlineImageRenderer):

  .trk .tck .trx       streamlines (TrackVis, MRtrix3, TRX: file or directory) -> exact tubes,
                       direction colours, or --color ARRAY (per point or per streamline);
                       --group NAME shows a TRX group's streamlines, --tsf a .tck's scalars
  .swc                 neuron morphology -> exact tubes with the file's radii
  .nii .nii.gz         SH coefficients or tensors on the 4th axis -> exact glyphs, one slice
  .mif .mif.gz         the same from MRtrix3 (e.g. FODs from dwi2fod, tensors from dwi2tensor)
  .vtr                 spherical (r, theta, phi) or cylindrical (rho, phi, z) rectilinear grid
                       in VTK's XML format -> ray-cast volume on its own grid
  .nc                  CF netCDF Earth or planetary model (longitude, latitude, depth/radius)
                       -> ray-cast volume on its own spherical grid, placed on the globe, with
                       a graticule; --variable picks the variable, --cut wedge|hemisphere opens it

An image's component count says what it holds: 6 is a diffusion tensor, 9/81/729 a full tensor,
36 a Voigt matrix, 15, 28, 45, 66, ... an SH series (lmax 4, 6, 8, 10, ...). --basis makes any
SH count an SH series, --layout any tensor count a tensor. A scalar NIfTI (FA, T1, b0) given
with --underlay is drawn as a grey slice beneath the glyphs (in the window, and traced as an
exact plane without one).

Window keys: mouse rotates/pans/zooms (VTK's trackball camera); Up/Down or PageUp/PageDown move
the glyph slice; a/c/s pick an axial/coronal/sagittal slice; h cycles shadows (off, hard,
soft); o toggles translucent tubes and volumes; p saves a screenshot (sightline-view-NNN.png);
r resets the camera; q quits.
"""
import argparse
import math
import os
import sys
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline
from sightline import nifti

EXAMPLES = """examples:
  sightline-view bundle.trk tracks.tck neuron.swc
  sightline-view brain.trx --group CST_left --group CST_right --color fa
  sightline-view fod.mif.gz --underlay t1.nii.gz --slice coronal
  sightline-view func_coef.nii.gz --basis dipy --legacy --output odf.png --size 1200 900
  sightline-view dti.nii.gz --layout fsl --underlay fa.nii.gz
  sightline-view fod.nii.gz --underlay t1.nii.gz --mosaic axial:8,coronal:8,sagittal:8 \\
      --size 3200 1200 --output report.png      # no X server needed
  sightline-view earth.vtr --output earth.exr     # colour and depth (EXR channels R G B A Z)
"""

SH_COUNTS = {(l + 1) * (l + 2) // 2: l for l in range(0, 17, 2)}  # 1, 6, 15, 28, 45, ... -> lmax
BASES = {  # name: (mapper basis, legacy by default)
    "dipy": ("descoteaux07", True), "descoteaux07": ("descoteaux07", True),
    "mrtrix3": ("tournier07", False), "tournier07": ("tournier07", False),
}
# Tensor layouts: the mapper's layout, and for 6-component files in another order, the
# permutation into the unique-component order xx, xy, xz, yy, yz, zz.
LAYOUTS = {
    "fsl": ("SymmetricUnique", None),            # xx xy xz yy yz zz (FSL dtifit, unique order)
    "unique": ("SymmetricUnique", None),         # any even order, one per monomial
    "vtk": ("VTKSymmetric", None),               # xx yy zz xy yz xz (vtkTensorGlyph)
    "dipy": ("SymmetricUnique", (0, 1, 3, 2, 4, 5)),     # xx xy yy xz yz zz (lower triangle)
    "mrtrix3": ("SymmetricUnique", (0, 3, 4, 1, 5, 2)),  # xx yy zz xy xz yz (dwi2tensor)
    "full": ("Full", None),
    "voigt": ("Voigt", None),
}
TENSOR_COUNTS = {6: "6 (order-2 tensor)", 9: "9 (3x3)", 36: "36 (6x6 Voigt)", 81: "81 (3^4)",
                 729: "729 (3^6)"}
NIFTI_INTENT_SYMMATRIX = 1005
BACKGROUND = (0.07, 0.075, 0.09)
SHADOWS = ("off", "hard", "soft")
TRANSLUCENT = 0.3


class ViewError(Exception):
    """A problem with the user's input, reported as one line without a traceback."""


def lower_extension(path):
    if os.path.isdir(path) and os.path.isfile(os.path.join(path, "header.json")):
        return ".trx"  # TRX's directory form
    name = os.path.basename(os.path.normpath(path)).lower()
    for double in (".nii.gz", ".mif.gz"):
        if name.endswith(double):
            return double
    return os.path.splitext(name)[1]


def run_reader(algorithm, path, what):
    """Updates a reader with VTK's error messages collected; a failure becomes a ViewError."""
    with nifti.VTKErrors() as errors:
        algorithm.Update()
    if errors.text or (hasattr(algorithm, "GetErrorCode") and algorithm.GetErrorCode()):
        raise ViewError(f"{path}: could not read it as {what}" + errors.detail())
    return algorithm.GetOutputDataObject(0)


def run_reader_piece(reader, path, what, pieces):
    """Piece 0 of `pieces` of a reader's output (see run_reader)."""
    with nifti.VTKErrors() as errors:
        reader.UpdatePiece(0, pieces, 0)
    if errors.text:
        raise ViewError(f"{path}: could not read it as {what}" + errors.detail())
    return reader.GetOutput()


class Progress:
    """Prints a VTK algorithm's ProgressEvent on stderr when a stage takes a while."""

    def __init__(self, label):
        self.label, self.start, self.last = label, None, -1

    def __call__(self, caller, _event):
        fraction = caller.GetProgress()
        now = time.perf_counter()
        if self.start is None or fraction <= 0.0:
            self.start, self.last = now, -1
        step = int(fraction * 4)  # a line at 25, 50, 75 and 100 %, once the stage is slow
        if now - self.start > 0.5 and step > self.last:
            self.last = step
            stage = caller.GetProgressText()  # the part of a long build, where it names one
            label = f"{self.label}, {stage}" if stage else self.label
            print(f"  {label}: {fraction * 100:3.0f}% ({now - self.start:.1f} s)",
                  file=sys.stderr, flush=True)

    def watch(self, algorithm):
        algorithm.AddObserver(vtk.vtkCommand.ProgressEvent, self)
        return algorithm


def direction_colors(lines):
    """Adds RGB point colours |unit tangent| (red left-right, green anterior-posterior, blue
    inferior-superior) to polylines, as DIPY and TrackVis colour streamlines."""
    points = vtk_to_numpy(lines.GetPoints().GetData()).astype(np.float64)
    tangents = np.zeros_like(points)
    cells = lines.GetLines()
    offsets = vtk_to_numpy(cells.GetOffsetsArray())
    ids = vtk_to_numpy(cells.GetConnectivityArray())
    if len(ids):
        # np.gradient along every polyline at once (a loop per streamline takes minutes at
        # 10^7 of them): central differences inside, one-sided at the ends, 0 for one point.
        used = offsets[1:] > offsets[:-1]
        first = np.zeros(len(ids), bool)
        last = np.zeros(len(ids), bool)
        first[offsets[:-1][used]] = True
        last[offsets[1:][used] - 1] = True
        position = np.arange(len(ids))
        following = np.where(last, position, position + 1)
        preceding = np.where(first, position, position - 1)
        walk = points[ids[following]] - points[ids[preceding]]
        tangents[ids] = walk / np.where(first | last, 1.0, 2.0)[:, None]
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-12)
    colors = numpy_to_vtk((np.abs(tangents) * 255).astype(np.uint8), deep=True)
    colors.SetName("direction")
    lines.GetPointData().SetScalars(colors)
    return lines


def select_groups(data, names, path, piece=False):
    """The streamlines of `data` in any of the TRX groups `names` (cell arrays group:NAME); a
    `piece` of a streamed file may hold none of them."""
    cells = data.GetCellData()
    available = sorted(cells.GetArrayName(i)[6:] for i in range(cells.GetNumberOfArrays())
                       if (cells.GetArrayName(i) or "").startswith("group:"))
    keep = np.zeros(data.GetNumberOfCells(), bool)
    for name in names:
        array = cells.GetArray("group:" + name)
        if array is None:
            raise ViewError(f"{path}: no group '{name}' (its groups: "
                            f"{', '.join(available) if available else 'none'})")
        keep |= vtk_to_numpy(array) != 0
    if not keep.any() and not piece:
        raise ViewError(f"{path}: the groups {', '.join(names)} hold no streamlines")
    lines = data.GetLines()
    offsets = vtk_to_numpy(lines.GetOffsetsArray())
    connectivity = vtk_to_numpy(lines.GetConnectivityArray())
    kept = np.flatnonzero(keep)
    lengths = offsets[kept + 1] - offsets[kept]
    ids = np.concatenate([connectivity[offsets[c]:offsets[c + 1]] for c in kept] +
                         [np.zeros(0, connectivity.dtype)])
    cell_array = vtk.vtkCellArray()
    cell_array.SetData(numpy_to_vtk(np.concatenate([[0], np.cumsum(lengths)]).astype(np.int64),
                                    deep=True, array_type=vtk.VTK_ID_TYPE),
                       numpy_to_vtk(ids.astype(np.int64), deep=True, array_type=vtk.VTK_ID_TYPE))
    result = vtk.vtkPolyData()
    result.SetPoints(data.GetPoints())
    result.GetPointData().ShallowCopy(data.GetPointData())
    result.SetLines(cell_array)
    for i in range(cells.GetNumberOfArrays()):
        values = vtk_to_numpy(cells.GetArray(i))[kept]
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=True,
                             array_type=cells.GetArray(i).GetDataType())
        array.SetName(cells.GetArrayName(i))
        result.GetCellData().AddArray(array)
    return result


def tube_reader(path, track_scalars=None):
    """The reader of a .trk, .tck, .trx or .swc file (not updated) and what it reads; ViewError
    for a file of another type or one that is missing."""
    extension = lower_extension(path)
    if extension not in TubeLayer.READERS:
        raise ViewError(f"{path}: not a .trk, .tck, .trx or .swc file")
    if not os.path.exists(path):
        raise ViewError(f"{path}: no such file")
    class_name, what = TubeLayer.READERS[extension]
    reader = getattr(sightline, class_name)()
    reader.SetFileName(path)
    if track_scalars:
        if extension != ".tck":
            raise ViewError(f"{path}: --tsf gives a .tck's track scalars; this is {what}")
        if not os.path.isfile(track_scalars):
            raise ViewError(f"{track_scalars}: no such file")
        reader.SetScalarFileName(track_scalars)
    Progress(f"reading {os.path.basename(path)}").watch(reader)
    return reader, what


def automatic_pieces(path):
    """Pieces to stream a tractogram in: one per 64 MiB of file from 512 MiB on (about 5 * 10^6
    float32 or 10^7 float16 points a piece: a piece's poly data and direction colours then take
    about 1 GB while it is turned into tubes), else 1 (the file read whole)."""
    if os.path.isdir(path):
        size = sum(os.path.getsize(os.path.join(root, name))
                   for root, _, names in os.walk(path) for name in names)
    else:
        size = os.path.getsize(path)
    return 1 if size < 512 * 2 ** 20 else math.ceil(size / (64 * 2 ** 20))


try:
    from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
except ImportError:  # VTK without its Python algorithm helper: no streaming
    VTKPythonAlgorithmBase = object


class TractogramPieces(VTKPythonAlgorithmBase):
    """Each piece of a streamline reader's output as the viewer draws it: direction colours,
    and only the streamlines of the chosen TRX groups. The tube mapper pulls pieces through it
    one at a time (vtkSightlineTubeMapper::StreamedPieces)."""

    def __init__(self, path, groups):
        super().__init__(nInputPorts=1, inputType="vtkPolyData",
                         nOutputPorts=1, outputType="vtkPolyData")
        self.path, self.groups, self.error = path, groups, None

    def RequestData(self, request, in_info, out_info):
        piece = vtk.vtkPolyData.GetData(in_info[0])
        output = vtk.vtkPolyData.GetData(out_info)
        data = vtk.vtkPolyData()
        data.ShallowCopy(piece)
        if data.GetNumberOfPoints() > 0:
            direction_colors(data)
            if self.groups:
                try:
                    data = select_groups(data, self.groups, self.path, piece=True)
                except ViewError as error:
                    self.error = error
                    return 0
        output.ShallowCopy(data)
        return 1


def read_tubes(path, track_scalars=None):
    """vtkPolyData of a .trk, .tck or .trx file (polylines in RAS+ mm, direction colours; a .tck's
    `track_scalars` .tsf as a point array) or of an .swc file (points with Radius, Type and
    ParentIndex arrays); ViewError naming the file when it is missing, of another type,
    unreadable or empty."""
    extension = lower_extension(path)
    reader, what = tube_reader(path, track_scalars)
    data = vtk.vtkPolyData()
    data.DeepCopy(run_reader(reader, path, what))
    if data.GetNumberOfPoints() == 0:
        raise ViewError(f"{path}: holds no points ({what} with nothing to draw)")
    if extension != ".swc":
        if data.GetNumberOfLines() == 0:
            raise ViewError(f"{path}: holds no streamlines")
        direction_colors(data)
    return data


def color_by_array(mapper, data, name, path, whole=None, value_range=None):
    """Colours tubes by the point or cell (per streamline) array `name` through a lookup table
    over its range in the whole file `whole`, or `value_range` (so that a group keeps the
    colours it has among all streamlines; vectors by magnitude); ViewError listing the arrays
    of `data` when it has none of that name."""
    point, cell = data.GetPointData().GetArray(name), data.GetCellData().GetArray(name)
    if point is None and cell is None:
        names = sorted(({data.GetPointData().GetArrayName(i)
                         for i in range(data.GetPointData().GetNumberOfArrays())} |
                        {data.GetCellData().GetArrayName(i)
                         for i in range(data.GetCellData().GetNumberOfArrays())}) - {"direction"})
        raise ViewError(f"{path}: no array '{name}' to colour by (its arrays: "
                        f"{', '.join(names) if names else 'none'})")
    array = point if point is not None else cell
    if value_range is None:
        value_range = array_range(whole, name)
    low, high = value_range
    table = vtk.vtkLookupTable()
    table.SetHueRange(0.667, 0.0)  # blue to red
    table.SetTableRange(low, high if high > low else low + 1)
    table.SetVectorModeToMagnitude()
    table.Build()
    mapper.SetLookupTable(table)
    mapper.UseLookupTableScalarRangeOn()
    mapper.SetColorModeToMapScalars()
    if point is not None:
        mapper.SetScalarModeToUsePointFieldData()
    else:
        mapper.SetScalarModeToUseCellFieldData()
    mapper.SelectColorArray(name)
    return f"coloured by {name} ({'per point' if point is not None else 'per streamline'}, " \
           f"{low:.3g} to {high:.3g})"


def colour_array_name(args):
    """The array tubes are coloured by: --color's, else a --tsf file's (the reader names its
    point array after the file, less .tsf), else None."""
    if args.color or not args.tsf:
        return args.color
    name = os.path.basename(args.tsf)
    return name[:-4] if name.endswith(".tsf") else name


def array_range(data, name):
    """The range of the point or cell array `name` of `data` (of its magnitude for vectors)."""
    array = data.GetPointData().GetArray(name) or data.GetCellData().GetArray(name)
    return array.GetRange(-1 if array.GetNumberOfComponents() > 1 else 0)


def streamed_range(reader, name, pieces, path, what):
    """The range of array `name` over every piece of `reader`'s output, each piece read and
    released in turn (the lookup table must span the whole file); None without such an array."""
    low, high = math.inf, -math.inf
    for piece in range(pieces):
        with nifti.VTKErrors() as errors:
            reader.UpdatePiece(piece, pieces, 0)
        if errors.text:
            raise ViewError(f"{path}: could not read it as {what}" + errors.detail())
        data = reader.GetOutput()
        if data.GetNumberOfPoints() and (data.GetPointData().GetArray(name) or
                                         data.GetCellData().GetArray(name)):
            a, b = array_range(data, name)
            low, high = min(low, a), max(high, b)
        data.ReleaseData()
    return (low, high) if low <= high else None


def shade(prop, ambient=0.2, specular=0.3):
    prop.SetAmbient(ambient)
    prop.SetDiffuse(1.0 - ambient)
    prop.SetSpecular(specular)
    prop.SetSpecularPower(25)


# -- layers: one per file ---------------------------------------------------------------------
class Layer:
    """What one file adds to the scene."""
    glyphs = False

    def __init__(self, path):
        self.path = path
        self.actors, self.volumes = [], []

    def props(self):
        return self.actors + self.volumes

    def bounds(self):
        return [prop.GetBounds() for prop in self.props()]

    def set_translucent(self, on):
        return False

    def frame_points(self):
        """Points the camera frames: the corners of every prop's bounds."""
        return np.array([[box[i], box[2 + j], box[4 + k]] for box in self.bounds()
                         for i in (0, 1) for j in (0, 1) for k in (0, 1)])


class TubeLayer(Layer):
    """Streamlines (.trk, .tck) and neurons (.swc) as exact generalised tubes."""

    READERS = {".trk": ("vtkSightlineTrackVisReader", "a TrackVis .trk file"),
               ".tck": ("vtkSightlineTCKReader", "an MRtrix3 .tck file"),
               ".trx": ("vtkSightlineTRXReader", "a TRX tractogram"),
               ".swc": ("vtkSightlineSWCReader", "an SWC neuron morphology")}

    def __init__(self, path, extension, args):
        super().__init__(path)
        pieces = 1 if extension == ".swc" else (args.pieces or automatic_pieces(path))
        self.streamed = pieces > 1
        if self.streamed:
            self.stream(path, args, pieces)
            return
        data = whole = read_tubes(path, args.tsf)
        if args.group:
            if extension != ".trx":
                raise ViewError(f"{path}: --group selects TRX groups; this is not a .trx")
            data = select_groups(whole, args.group, path)
        mapper = sightline.vtkSightlineTubeMapper()
        mapper.SetInputDataObject(data)
        diagonal = math.sqrt(sum((data.GetBounds()[2 * i + 1] - data.GetBounds()[2 * i]) ** 2
                                 for i in range(3)))
        if extension == ".swc":
            mapper.SetPredecessorArrayName("ParentIndex")
            if args.radius:
                mapper.SetRadius(args.radius)
                self.radius_text = f"radius {args.radius:g}"
            else:
                mapper.SetRadiusArrayName("Radius")
                self.radius_text = "radii from the file"
            self.count_text = f"{data.GetNumberOfPoints()} samples"
            # Coloured by SWC structure type as NeuroMorpho.org draws them: soma white, axon
            # blue, basal dendrite red, apical dendrite magenta, others grey-gold.
            table = vtk.vtkLookupTable()
            types = [(0.8, 0.7, 0.5), (0.95, 0.95, 0.95), (0.3, 0.5, 1.0), (0.95, 0.3, 0.25),
                     (0.9, 0.3, 0.9), (0.8, 0.7, 0.5), (0.8, 0.7, 0.5), (0.8, 0.7, 0.5)]
            table.SetNumberOfTableValues(len(types))
            for index, rgb in enumerate(types):
                table.SetTableValue(index, *rgb, 1.0)
            table.SetTableRange(-0.5, len(types) - 0.5)
            mapper.SetLookupTable(table)
            mapper.UseLookupTableScalarRangeOn()
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray("Type")
            color = None
        else:
            mapper.SetColorModeToDirectScalars()
            # Streamline files are in mm: 0.5 mm, or thinner for tiny test data.
            radius = args.radius or min(0.5, diagonal / 200.0)
            mapper.SetRadius(radius)
            self.radius_text = f"radius {radius:.3g}"
            self.count_text = (f"{data.GetNumberOfLines()} streamlines, "
                               f"{data.GetNumberOfPoints()} points")
            color_array = colour_array_name(args)
            if color_array:
                self.count_text += ", " + color_by_array(mapper, data, color_array, path, whole)
            color = None
        Progress(f"tubes of {os.path.basename(path)}").watch(mapper)
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        if color:
            actor.GetProperty().SetColor(*color)
        shade(actor.GetProperty())
        self.mapper, self.actors = mapper, [actor]
        self.data = data

    def stream(self, path, args, pieces):
        """The tractogram pulled by the tube mapper in `pieces`, each released once its tubes
        are built: the whole poly data never exists (vtkSightlineTubeMapper::StreamedPieces)."""
        reader, what = tube_reader(path, args.tsf)
        reader.RemoveObservers(vtk.vtkCommand.ProgressEvent)  # the mapper's progress counts pieces
        reader.ReleaseDataFlagOn()  # each piece goes once the filter below has used it
        # Piece 0 first: it names what a bad file or option is before the long work.
        first = vtk.vtkPolyData()
        first.ShallowCopy(run_reader_piece(reader, path, what, pieces))
        if first.GetNumberOfPoints() == 0 and pieces == 1:
            raise ViewError(f"{path}: holds no points ({what} with nothing to draw)")
        if args.group:
            if lower_extension(path) != ".trx":
                raise ViewError(f"{path}: --group selects TRX groups; this is not a .trx")
            select_groups(first, args.group, path, piece=True)  # names an unknown group
        color_array = colour_array_name(args)
        mapper = sightline.vtkSightlineTubeMapper()
        mapper.SetColorModeToDirectScalars()
        radius = args.radius or 0.5  # streamed files are whole brains, in mm
        mapper.SetRadius(radius)
        self.radius_text = f"radius {radius:.3g}"
        colouring = ""
        if color_array:
            value_range = streamed_range(reader, color_array, pieces, path, what)
            if value_range is None:
                color_by_array(mapper, first, color_array, path)  # names the arrays there are
            colouring = ", " + color_by_array(mapper, first, color_array, path,
                                              value_range=value_range)
        first.ReleaseData()
        pieces_filter = TractogramPieces(path, args.group)
        pieces_filter.SetInputConnection(reader.GetOutputPort())
        mapper.SetInputConnection(pieces_filter.GetOutputPort())
        mapper.SetLinkLayout(mapper.LINKS_CHUNKED)
        mapper.SetStreamedPieces(pieces)
        Progress(f"tubes of {os.path.basename(path)}").watch(mapper)
        with nifti.VTKErrors() as errors:
            mapper.GetBounds()  # builds the tubes, piece by piece
        if pieces_filter.error:
            raise pieces_filter.error
        if errors.text or mapper.GetNumberOfLinks() == 0:
            raise ViewError(f"{path}: could not draw it as {what}" + errors.detail())
        self.count_text = (f"{mapper.GetNumberOfLinks()} points streamed in {pieces} pieces"
                           + colouring)
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        shade(actor.GetProperty())
        self.mapper, self.actors = mapper, [actor]
        self.keep = (reader, pieces_filter)
        self.data = None

    def set_translucent(self, on):
        self.actors[0].GetProperty().SetOpacity(TRANSLUCENT if on else 1.0)
        return True

    def describe(self):
        return f"{self.path}: {self.count_text}, tubes ({self.radius_text})"

    def frame_points(self):
        """The tubes' points (at most 5000 of them): a bundle's bounding box has empty
        corners that would make it look small. Streamed: the tubes' bounds."""
        if self.data is None:
            return super().frame_points()
        points = vtk_to_numpy(self.data.GetPoints().GetData()).astype(float)
        return points[::max(1, len(points) // 5000)]


def glyph_actor(kind, detail, count, args, image, data_to_world, file_axes=None):
    """(mapper, actor) drawing `image` as SH ('sh', basis) or tensor ('tensor', layout) glyphs
    with the options' legacy basis, tensor shape, frame and scale (GlyphLayer.classify gives
    kind and detail); data_to_world and file_axes are vtkMatrix4x4s."""
    if kind == "sh":
        mapper = sightline.vtkSightlineSHGlyphMapper()
        basis, legacy = BASES[detail]
        mapper.SetBasisByName(basis)
        mapper.SetLegacyBasis(legacy if args.legacy is None else args.legacy)
    else:
        mapper = sightline.vtkSightlineTensorGlyphMapper()
        getattr(mapper, "SetTensorLayoutTo" + LAYOUTS[detail][0])()
        if count == 6 and args.tensor_shape == "ellipsoid":
            mapper.SetShapeToEllipsoid()  # as vtkTensorGlyph, mrview and DIPY draw DTI
    mapper.SetInputDataObject(image)
    mapper.SetDataToWorldMatrix(data_to_world)
    if args.frame == "voxel":
        mapper.SetDirectionToWorldMatrix(file_axes)
    mapper.SetScaleFactor(args.scale)
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    shade(actor.GetProperty(), ambient=0.15, specular=0.4)
    actor.GetProperty().SetSpecularPower(40)
    return mapper, actor


class GlyphLayer(Layer):
    """SH or tensor glyphs of one slice of a NIfTI or MRtrix3 image."""
    glyphs = True

    def __init__(self, path, extension, args):
        super().__init__(path)
        self.args = args
        name = os.path.basename(path)
        if extension == ".mif" or extension == ".mif.gz":
            if not os.path.isfile(path):
                raise ViewError(f"{path}: no such file")
            reader = sightline.vtkSightlineMIFReader()
            reader.SetFileName(path)
            Progress(f"reading {name}").watch(reader)
            image = run_reader(reader, path, "an MRtrix3 image")
            self.data_to_world = reader.GetTransformMatrix()
            self.file_axes = None  # .mif images are stored with world-axis directions
            intent_symmatrix, source = False, "mif"
        else:
            try:
                reader = nifti.read(path, as_vector=True)
            except nifti.NiftiError as error:
                raise ViewError(str(error)) from None
            image = reader.GetOutput()
            self.data_to_world = nifti.data_to_world(reader)
            self.file_axes = nifti.file_axes_to_world(reader)
            _, source = nifti.best_affine(reader.GetNIFTIHeader())
            intent_symmatrix = reader.GetNIFTIHeader().GetIntentCode() == NIFTI_INTENT_SYMMATRIX
        self.reader, self.affine_source = reader, source
        scalars = image.GetPointData().GetScalars()
        if scalars is None or image.GetNumberOfPoints() == 0:
            raise ViewError(f"{path}: an empty image")
        count = scalars.GetNumberOfComponents()
        self.kind, self.detail = self.classify(path, count, extension, intent_symmatrix, args)
        self.count = count
        if self.kind == "tensor" and LAYOUTS[self.detail][1] is not None:
            image = self.permuted(image, LAYOUTS[self.detail][1])
        self.image = image

        if args.frame == "voxel" and self.file_axes is None:
            raise ViewError(f"{path}: --frame voxel is for NIfTI files (.mif directions are "
                            "in world axes)")
        self.mapper, actor = glyph_actor(self.kind, self.detail, count, args, image,
                                         self.data_to_world, self.file_axes)
        self.mapper.SetInteractiveSubsampling(2)
        Progress(f"glyphs of {name}").watch(self.mapper)
        self.actors = [actor]
        self.shadows = args.shadows
        self.set_shadows(args.shadows)
        self.underlay = None
        self.set_slice(args.slice, args.index)

    @staticmethod
    def classify(path, count, extension, intent_symmatrix, args):
        """('sh', basis) or ('tensor', layout) from the component count and the options."""
        if args.layout:
            fits = {"unique": [c for c in sorted(SH_COUNTS) if c > 1],
                    "full": [3 ** order for order in range(2, 13, 2)], "voigt": [36]}
            fits = fits.get(args.layout, [6])  # the 6-component orders
            if count not in fits:
                raise ViewError(f"{path}: --layout {args.layout} is for "
                                f"{', '.join(map(str, fits))} components, the file has {count}")
            return "tensor", args.layout
        if count == 1:
            raise ViewError(f"{path}: one value per voxel is a scalar image, not glyphs; pass it "
                            "with --underlay to draw it beneath them")
        if args.basis:
            if count not in SH_COUNTS:
                raise ViewError(f"{path}: {count} components per voxel is no SH series; lmax 2, "
                                f"4, 6, ... have {', '.join(str(c) for c in sorted(SH_COUNTS))}")
            return "sh", args.basis
        if count == 6:  # a diffusion tensor, in the order its writer uses
            if extension in (".mif", ".mif.gz"):
                return "tensor", "mrtrix3"
            return "tensor", "dipy" if intent_symmatrix else "fsl"
        if count in TENSOR_COUNTS:
            return "tensor", {9: "full", 81: "full", 729: "full", 36: "voigt"}[count]
        if count in SH_COUNTS:
            return "sh", "mrtrix3" if extension in (".mif", ".mif.gz") else "dipy"
        raise ViewError(
            f"{path}: {count} components per voxel is neither an SH series "
            f"({', '.join(str(c) for c in sorted(SH_COUNTS) if c > 1)}) nor a tensor "
            f"({', '.join(str(c) for c in TENSOR_COUNTS)}); a 3-D scalar image goes with --underlay")

    @staticmethod
    def permuted(image, order):
        values = vtk_to_numpy(image.GetPointData().GetScalars())[:, list(order)]
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName("tensor")
        copy = vtk.vtkImageData()
        copy.CopyStructure(image)
        copy.GetPointData().SetScalars(array)
        return copy

    def describe(self):
        what = (f"SH lmax {SH_COUNTS[self.count]}, basis {self.mapper.GetBasisAsString()} "
                f"(legacy {bool(self.mapper.GetLegacyBasis())})" if self.kind == "sh"
                else f"tensors, layout {self.detail}")
        return (f"{self.path}: {self.image.GetDimensions()} voxels x {self.count} components, "
                f"{what}, affine from the {self.affine_source}; {self.orientation} slice "
                f"{self.index} of {self.slice_count()}")

    # -- slice ----------------------------------------------------------------------------------
    def slice_count(self):
        extent = self.image.GetExtent()
        return extent[2 * self.axis + 1] - extent[2 * self.axis] + 1

    def set_slice(self, orientation, index=None):
        getattr(self.mapper, "SetSliceOrientationTo" + orientation.capitalize())()
        self.axis = self.mapper.GetSliceAxis()
        extent = self.image.GetExtent()
        low, high = extent[2 * self.axis], extent[2 * self.axis + 1]
        if index is None or index < 0:
            index = (low + high) // 2
        self.orientation, self.index = orientation, min(max(index, low), high)
        self.mapper.SetSliceNumber(self.index)
        if self.underlay is not None:
            self.underlay.follow(self)

    def move_slice(self, step):
        self.set_slice(self.orientation, self.index + step)

    def set_shadows(self, mode):
        getattr(self.mapper, "SetShadowModeTo" + mode.capitalize())()
        self.shadows = mode

    def slice_frame(self):
        """World centre of the slice, its unit normal (towards +z, +y or +x for axial, coronal,
        sagittal) and an in-plane up direction (anterior for axial, superior otherwise)."""
        matrix = nifti.from_vtk_matrix(self.data_to_world)
        spacing, origin = np.array(self.image.GetSpacing()), np.array(self.image.GetOrigin())
        extent = list(self.image.GetExtent())
        extent[2 * self.axis] = extent[2 * self.axis + 1] = self.index
        centre = origin + spacing * 0.5 * (np.array(extent[0::2]) + np.array(extent[1::2]))
        centre = (matrix @ np.append(centre, 1.0))[:3]
        normal = matrix[:3, self.axis] / np.linalg.norm(matrix[:3, self.axis])
        world_axis = {"axial": 2, "coronal": 1, "sagittal": 0}[self.orientation]
        if normal[world_axis] < 0:
            normal = -normal
        up = np.array([0.0, 1.0, 0.0]) if self.orientation == "axial" else np.array([0.0, 0.0, 1.0])
        up = up - normal * np.dot(up, normal)
        if np.linalg.norm(up) < 1e-6:
            up = np.array([1.0, 0.0, 0.0]) - normal * normal[0]
        return centre, normal, up / np.linalg.norm(up)


class Underlay:
    """A scalar NIfTI drawn as a grey vtkImageSlice just beneath a glyph layer's slice."""

    def __init__(self, path):
        try:
            self.reader = nifti.read(path, as_vector=False)
        except nifti.NiftiError as error:
            raise ViewError(f"--underlay {error}") from None
        image = self.reader.GetOutput()
        if image.GetNumberOfScalarComponents() != 1:
            raise ViewError(f"--underlay {path}: {image.GetNumberOfScalarComponents()} values per "
                            "voxel; the underlay is a scalar image (FA, T1, b0)")
        self.path, self.image = path, image
        self.to_world = nifti.data_to_world(self.reader, as_vtk=False)
        self.slice_mapper = vtk.vtkImageSliceMapper()
        self.slice_mapper.SetInputConnection(self.reader.GetOutputPort())
        self.slice_mapper.BorderOn()
        self.actor = vtk.vtkImageSlice()
        self.actor.SetMapper(self.slice_mapper)
        self.matrix = vtk.vtkMatrix4x4()
        self.actor.SetUserMatrix(self.matrix)
        values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(float)
        values = values[np.isfinite(values)]
        low, high = (np.percentile(values, [1, 99.5]) if values.size else (0.0, 1.0))
        window = max(high - low, 1e-6) / 0.7  # the brightest voxels 70 % grey: glyphs stand out
        prop = self.actor.GetProperty()
        prop.SetColorWindow(window)
        prop.SetColorLevel(low + 0.5 * window)
        prop.SetInterpolationTypeToNearest()

    def follow(self, layer):
        """The underlay's slice through the glyph slice's centre, moved just below the glyphs."""
        centre, normal, _ = layer.slice_frame()
        radius = layer.args.scale * 0.5 * min(layer.image.GetSpacing())
        self.place(centre, normal, -0.6 * radius)

    def place(self, centre, normal, shift, clamp=True):
        """Shows the slice through world point `centre` along the underlay's voxel axis closest
        to `normal`, moved by `shift` along it. A plane outside the image shows the nearest
        slice, or with clamp off hides the slice and returns False."""
        columns = self.to_world[:3, :3] / np.linalg.norm(self.to_world[:3, :3], axis=0)
        axis = int(np.argmax(np.abs(columns.T @ normal)))
        data = np.linalg.solve(self.to_world, np.append(centre, 1.0))[:3]
        origin, spacing = self.image.GetOrigin(), self.image.GetSpacing()
        extent = self.image.GetExtent()
        index = int(round((data[axis] - origin[axis]) / spacing[axis]))
        inside = extent[2 * axis] <= index <= extent[2 * axis + 1]
        self.actor.SetVisibility(inside or clamp)
        if not (inside or clamp):
            return False
        index = min(max(index, extent[2 * axis]), extent[2 * axis + 1])
        self.slice_mapper.SetOrientation(axis)
        self.slice_mapper.SetSliceNumber(index)
        shifted = self.to_world.copy()
        shifted[:3, 3] += shift * np.asarray(normal, float)
        self.matrix.DeepCopy(nifti.to_vtk_matrix(shifted))
        return True


def ramp_volume_property(low, high, max_opacity=0.6):
    """A vtkVolumeProperty for values in [low, high]: a perceptual colour ramp (dark blue, teal,
    green, yellow) and opacity rising linearly from 0 to max_opacity."""
    color, opacity = vtk.vtkColorTransferFunction(), vtk.vtkPiecewiseFunction()
    for t, rgb in ((0.0, (0.18, 0.12, 0.45)), (0.35, (0.13, 0.47, 0.56)),
                   (0.7, (0.35, 0.75, 0.38)), (1.0, (0.99, 0.9, 0.15))):
        color.AddRGBPoint(low + t * (high - low), *rgb)
    opacity.AddPoint(low, 0.0)
    opacity.AddPoint(high, max_opacity)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    return prop


def read_grid(path):
    """(vtkRectilinearGrid, its scalars, 'points' or 'cells') of a .vtr file with one scalar
    array (the active one, or the first); ViewError naming the problem."""
    if not os.path.isfile(path):
        raise ViewError(f"{path}: no such file")
    reader = vtk.vtkXMLRectilinearGridReader()
    if lower_extension(path) != ".vtr" or not reader.CanReadFile(path):
        raise ViewError(f"{path}: not a VTK XML rectilinear grid (.vtr) file")
    reader.SetFileName(path)
    Progress(f"reading {os.path.basename(path)}").watch(reader)
    grid = run_reader(reader, path, "a VTK XML rectilinear grid")
    data, association = grid.GetPointData(), "points"
    if grid.GetCellData().GetNumberOfArrays() and not data.GetNumberOfArrays():
        data, association = grid.GetCellData(), "cells"
    if data.GetNumberOfArrays() == 0:
        raise ViewError(f"{path}: the grid has no data array to draw")
    if data.GetScalars() is None:
        data.SetActiveScalars(data.GetArrayName(0))
    scalars = data.GetScalars()
    if scalars.GetNumberOfComponents() != 1:
        raise ViewError(f"{path}: array '{scalars.GetName()}' has "
                        f"{scalars.GetNumberOfComponents()} components; the volume needs one")
    return grid, scalars, association


def angles_in_degrees(grid, coordinates="spherical"):
    """Whether a spherical (y, z) or cylindrical (y) grid's angles exceed 2 pi: degrees."""
    angles = ((grid.GetYCoordinates(), grid.GetZCoordinates()) if coordinates == "spherical"
              else (grid.GetYCoordinates(),))
    return any(np.abs(vtk_to_numpy(axis)).max() > 2 * math.pi + 1e-6 for axis in angles)


class GridVolumeLayer(Layer):
    """What the volume layers share: one vtkVolume whose opacity unit distance 'o' stretches,
    and a one-line description (self.text)."""

    def set_translucent(self, on):
        prop = self.volumes[0].GetProperty()
        prop.SetScalarOpacityUnitDistance(self.unit_distance * (4.0 if on else 1.0))
        return True

    def describe(self):
        return f"{self.path}: {self.text}"


class VolumeLayer(GridVolumeLayer):
    """A spherical or cylindrical vtkRectilinearGrid (.vtr), ray-cast on its own cells."""

    def __init__(self, path, extension, args):
        super().__init__(path)
        grid, scalars, association = read_grid(path)
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputDataObject(grid)
        if args.grid == "cylindrical":
            mapper.SetCoordinateSystemToCylindrical()
        degrees = args.angles == "degrees"
        if args.angles == "auto":
            degrees = angles_in_degrees(grid, args.grid)
        if degrees:
            mapper.SetAngleUnitsToDegrees()
        Progress(f"volume of {os.path.basename(path)}").watch(mapper)
        low, high = scalars.GetRange()
        if not high > low:
            high = low + 1.0
        prop = ramp_volume_property(low, high)
        bounds = mapper.GetBounds()
        size = max(bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4])
        self.unit_distance = size / 8.0
        prop.SetScalarOpacityUnitDistance(self.unit_distance)
        volume = vtk.vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        self.mapper, self.volumes, self.grid = mapper, [volume], grid
        self.text = (f"{args.grid} grid {tuple(grid.GetDimensions())} nodes, "
                     f"'{scalars.GetName()}' on {association} in [{low:.4g}, {high:.4g}], "
                     f"angles in {'degrees' if degrees else 'radians'}")



class EarthModelLayer(GridVolumeLayer):
    """A CF netCDF model (longitude, latitude, depth or radius) as an exact spherical volume
    on the globe: perturbations in a diverging map centred on zero, a graticule of exact tubes
    on the outer sphere, and optionally a wedge or hemisphere cut away facing the camera."""

    def __init__(self, path, args):
        super().__init__(path)
        from sightline import earth

        if not os.path.isfile(path):
            raise ViewError(f"{path}: no such file")
        try:
            grid, reader = earth.read_model(path, args.variable, args.reference_radius,
                                            args.vertical)
            azimuth = vtk_to_numpy(grid.GetZCoordinates())
            longitude = args.view_longitude
            if longitude is None:  # the middle of a regional model; 0 E for a globe
                span = azimuth[-1] - azimuth[0]
                longitude = 0.0 if span > 2 * math.pi - 1e-6 else math.degrees(
                    azimuth[0] + span / 2)
            # The colour range is the whole model's, whatever the cut leaves.
            values = vtk_to_numpy(grid.GetPointData().GetScalars())
            finite = values[np.isfinite(values)]
            if finite.size == 0:
                raise ViewError(f"{path}: every value of the variable is missing")
            low, high = float(finite.min()), float(finite.max())
            missing = values.size - finite.size
            if args.cut:
                grid = earth.cut_away(grid, longitude, 90.0 if args.cut == "wedge" else 180.0)
        except earth.ModelError as error:
            raise ViewError(f"{path}: {error}") from None
        colatitude = vtk_to_numpy(grid.GetYCoordinates())
        latitude = args.view_latitude
        if latitude is None:  # the middle of a regional model's latitudes; 20 N for a globe
            latitude = 20.0 if np.ptp(colatitude) > math.pi - 1e-6 else 90.0 - math.degrees(
                0.5 * (colatitude[0] + colatitude[-1]))
        lat, lon = math.radians(latitude), math.radians(longitude)
        self.view_direction = np.array([math.cos(lat) * math.cos(lon),
                                        math.cos(lat) * math.sin(lon), math.sin(lat)])
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputDataObject(grid)
        Progress(f"volume of {os.path.basename(path)}").watch(mapper)
        prop = earth.diverging_volume_property(low, high)
        outer = float(vtk_to_numpy(grid.GetXCoordinates()).max())
        self.unit_distance = outer / 40.0  # features a few hundred km across read as solid
        prop.SetScalarOpacityUnitDistance(self.unit_distance)
        volume = vtk.vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        self.mapper, self.volumes, self.grid = mapper, [volume], grid
        if args.graticule:
            self.actors = [earth.graticule_actor(grid, facing=self.view_direction)]
        names = [reader.GetVariableNameOf(i) for i in range(reader.GetNumberOfVariables())]
        radius = vtk_to_numpy(grid.GetXCoordinates())
        self.text = (f"'{grid.GetPointData().GetScalars().GetName()}' of {names} on "
                     f"{tuple(grid.GetDimensions())} nodes (r, colatitude, longitude), radius "
                     f"{radius.min():.0f}-{radius.max():.0f} km, values in [{low:.4g}, {high:.4g}]"
                     + (f", {missing} missing" if missing else "")
                     + (f", {args.cut} cut away" if args.cut else ""))


    def frame_points(self):
        """Points on the model's section: its inner and outer spheres over its latitude and
        longitude range (the box's corners would frame a globe loosely, a cap far too wide)."""
        r = vtk_to_numpy(self.grid.GetXCoordinates())
        theta = vtk_to_numpy(self.grid.GetYCoordinates())
        phi = vtk_to_numpy(self.grid.GetZCoordinates())
        R, T, P = np.meshgrid([r[0], r[-1]], np.linspace(theta[0], theta[-1], 19),
                              np.linspace(phi[0], phi[-1], 37), indexing="ij")
        return np.stack([R * np.sin(T) * np.cos(P), R * np.sin(T) * np.sin(P), R * np.cos(T)],
                        axis=-1).reshape(-1, 3)


def load(path, args):
    extension = lower_extension(path)
    if extension in TubeLayer.READERS:
        if not os.path.exists(path):
            raise ViewError(f"{path}: no such file")
        return TubeLayer(path, extension, args)
    if extension in (".nii", ".nii.gz", ".mif", ".mif.gz"):
        return GlyphLayer(path, extension, args)
    if extension == ".vtr":
        return VolumeLayer(path, extension, args)
    if extension in (".nc", ".nc4", ".cdf"):
        return EarthModelLayer(path, args)
    raise ViewError(f"{path}: unknown file type '{extension or os.path.basename(path)}'; "
                    "sightline-view opens .trk, .tck, .trx, .swc, .nii, .nii.gz, .mif, .mif.gz, "
                    ".vtr, .nc")


# -- the scene -------------------------------------------------------------------------------
def glyph_lights(centre, normal, up):
    """[scene light, headlight] for a glyph slice (centre, unit normal, in-plane up): the
    oblique scene light makes glyph shadows fall on neighbours; a user light turns VTK's own
    headlight off, so a dimmer one is added back."""
    direction = 0.35 * normal + 0.55 * up - 0.75 * np.cross(up, normal)
    light = vtk.vtkLight()
    light.SetLightTypeToSceneLight()
    light.SetFocalPoint(*centre)
    light.SetPosition(*(centre + 100.0 * direction / np.linalg.norm(direction)))
    light.SetIntensity(0.75)
    headlight = vtk.vtkLight()
    headlight.SetLightTypeToHeadlight()
    headlight.SetIntensity(0.5)
    return [light, headlight]


class Scene:
    def __init__(self, layers, args):
        self.layers, self.args = layers, args
        self.glyphs = [layer for layer in layers if layer.glyphs]
        self.renderer = vtk.vtkRenderer()
        self.renderer.SetBackground(*BACKGROUND)
        for layer in layers:
            for actor in layer.actors:
                self.renderer.AddActor(actor)
            for volume in layer.volumes:
                self.renderer.AddVolume(volume)
        if args.underlay:
            if not self.glyphs:
                raise ViewError("--underlay draws beneath glyphs: give an SH or tensor image too")
            self.underlay = Underlay(args.underlay)
            self.glyphs[0].underlay = self.underlay
            self.renderer.AddViewProp(self.underlay.actor)
        else:
            self.underlay = None
        for layer in self.glyphs:
            layer.set_slice(layer.orientation, layer.index)
        self.translucent = False
        self.light, self.lights = None, []
        if self.glyphs:
            self.lights = glyph_lights(*self.glyphs[0].slice_frame())
            self.light = self.lights[0]
            for light in self.lights:
                self.renderer.AddLight(light)
        self.reset_camera()

    def reset_camera(self):
        camera = self.renderer.GetActiveCamera()
        if self.glyphs:
            centre, normal, up = self.glyphs[0].slice_frame()
            tilt = math.radians(90.0 - self.args.elevation)
            direction = math.cos(tilt) * normal - math.sin(tilt) * up
            view_up = math.cos(tilt) * up + math.sin(tilt) * normal
        elif any(hasattr(layer, "view_direction") for layer in self.layers):
            # an Earth model: from above its view latitude and longitude, north up
            centre = np.zeros(3)
            direction = next(layer.view_direction for layer in self.layers
                             if hasattr(layer, "view_direction"))
            view_up = np.array([0.0, 0.0, 1.0])
        else:  # from the left, a little in front and above, superior up
            centre = np.zeros(3)
            direction, view_up = np.array([-1.0, -0.35, 0.25]), np.array([0.0, 0.0, 1.0])
        camera.SetFocalPoint(*centre)
        camera.SetPosition(*(centre + direction))
        camera.SetViewUp(*view_up)
        camera.SetViewAngle(30.0)
        bounds = self.data_bounds()
        self.renderer.ResetCamera(bounds)  # the bounding sphere in view: zoom in to the box
        width, height = self.args.size
        corners = np.concatenate([layer.frame_points() for layer in self.layers])
        corners = np.hstack([corners, np.ones((len(corners), 1))])
        for _ in range(3):  # Zoom narrows the view angle: converges in a few steps
            matrix = nifti.from_vtk_matrix(
                camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
            projected = corners @ matrix.T
            extent = np.abs(projected[:, :2] / projected[:, 3:4]).max()
            camera.Zoom(0.9 / extent)  # the data's box fills 90 % of the shorter way
        self.renderer.ResetCameraClippingRange(bounds)
        return camera

    def data_bounds(self):
        """The bounds to frame: the glyph slices' (the underlay extends them only in-plane)
        and every other layer's."""
        boxes = [box for layer in self.layers for box in layer.bounds()
                 if box and box[0] <= box[1]]
        if not boxes:
            raise ViewError("nothing to draw: the files hold no visible data")
        boxes = np.array(boxes)
        return [float(value) for pair in zip(boxes[:, 0::2].min(axis=0), boxes[:, 1::2].max(axis=0))
                for value in pair]

    # -- key actions (window keys and --keys) -------------------------------------------------
    def move_slice(self, step):
        for layer in self.glyphs:
            layer.move_slice(step)
        return self.glyph_status()

    def set_orientation(self, orientation):
        for layer in self.glyphs:
            layer.set_slice(orientation)
        self.reset_camera()
        return self.glyph_status()

    def cycle_shadows(self):
        for layer in self.glyphs:
            layer.set_shadows(SHADOWS[(SHADOWS.index(layer.shadows) + 1) % len(SHADOWS)])
        return "shadows " + ", ".join(layer.shadows for layer in self.glyphs)

    def toggle_translucent(self):
        self.translucent = not self.translucent
        changed = [layer for layer in self.layers if layer.set_translucent(self.translucent)]
        state = "translucent" if self.translucent else "opaque"
        return f"{state}: {len(changed)} tube/volume layer(s)"

    def glyph_status(self):
        return "; ".join(f"{layer.orientation} slice {layer.index}" for layer in self.glyphs)


# -- output ----------------------------------------------------------------------------------
def write_exr(path, rgba, depth):
    """An uncompressed scanline OpenEXR file with 32-bit float channels R, G, B, A and Z.
    rgba: (h, w, 4) in [0, 1], first row the top of the image; depth: (h, w)."""
    import struct

    height, width = depth.shape
    channels = {"A": rgba[..., 3], "B": rgba[..., 2], "G": rgba[..., 1], "R": rgba[..., 0],
                "Z": depth}
    names = sorted(channels)  # EXR stores channels in alphabetical order

    def attribute(name, kind, payload):
        return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(payload)) + payload

    chlist = b"".join(name.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for name in names)
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = (struct.pack("<ii", 20000630, 2)
              + attribute("channels", "chlist", chlist + b"\0")
              + attribute("compression", "compression", b"\0")
              + attribute("dataWindow", "box2i", box)
              + attribute("displayWindow", "box2i", box)
              + attribute("lineOrder", "lineOrder", b"\0")
              + attribute("pixelAspectRatio", "float", struct.pack("<f", 1.0))
              + attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
              + attribute("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    row_bytes = 4 * width * len(names)
    start = len(header) + 8 * height
    offsets = struct.pack(f"<{height}Q", *(start + y * (8 + row_bytes) for y in range(height)))
    stack = np.stack([channels[name] for name in names], axis=1).astype("<f4")  # (h, c, w)
    with open(path, "wb") as stream:
        stream.write(header + offsets)
        for y in range(height):
            stream.write(struct.pack("<ii", y, row_bytes) + stack[y].tobytes())


def image_arrays(image):
    """(rgba uint8 (h, w, 4), depth (h, w) or None) of a VTK image, top row first."""
    width, height, _ = image.GetDimensions()
    scalars = vtk_to_numpy(image.GetPointData().GetScalars())
    rgba = scalars.reshape(height, width, -1)[::-1]
    if rgba.shape[2] == 3:
        rgba = np.concatenate([rgba, np.full((height, width, 1), 255, rgba.dtype)], axis=2)
    depth = image.GetPointData().GetArray("Depth")
    if depth is not None:
        depth = vtk_to_numpy(depth).reshape(height, width)[::-1]
    return rgba, depth


def coverage(rgba):
    """Fraction of pixels that differ from the background, and the covered bounding box
    (x0, y0, x1, y1) in pixels, or None."""
    background = np.round(np.array(BACKGROUND) * 255)
    covered = np.abs(rgba[..., :3].astype(float) - background).max(axis=-1) > 8
    if not covered.any():
        return 0.0, None
    rows, columns = np.nonzero(covered.any(axis=1))[0], np.nonzero(covered.any(axis=0))[0]
    return float(covered.mean()), (int(columns[0]), int(rows[0]), int(columns[-1]), int(rows[-1]))


def report(rgba, path):
    fraction, box = coverage(rgba)
    height, width = rgba.shape[:2]
    where = (f", data within x {box[0]}-{box[2]}, y {box[1]}-{box[3]} of {width}x{height}"
             if box else "")
    print(f"wrote {path} ({fraction * 100:.1f}% of pixels not background{where})")
    if box is None:
        print("warning: the image is empty", file=sys.stderr)


def render_to_file(scene, args):
    """--output: the GL-free vtkSightlineImageRenderer (no window, no OpenGL, no X server); the
    underlay is traced as an exact plane beneath the glyphs."""
    width, height = args.size
    extension = os.path.splitext(args.output)[1].lower()
    if extension not in (".png", ".exr"):
        raise ViewError(f"--output {args.output}: the image must be .png or .exr")
    folder = os.path.dirname(os.path.abspath(args.output))
    if not os.path.isdir(folder):
        raise ViewError(f"--output {args.output}: no folder {folder}")
    start = time.perf_counter()
    batch = sightline.vtkSightlineImageRenderer()
    for layer in scene.layers:
        for actor in layer.actors:
            batch.AddActor(actor)
        for volume in layer.volumes:
            batch.AddVolume(volume)
    if scene.underlay is not None:
        batch.AddImageSlice(scene.underlay.actor)
    for light in scene.lights:
        batch.AddLight(light)
    batch.SetActiveCamera(scene.renderer.GetActiveCamera())
    batch.SetSize(width, height)
    batch.SetBackground(*BACKGROUND)
    batch.Update()
    image, how = batch.GetOutput(), "GL-free"
    seconds = time.perf_counter() - start
    rgba, depth = image_arrays(image)
    if extension == ".png":
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(args.output)
        writer.SetInputData(image)
        writer.Write()
    else:
        if depth is None:
            raise ViewError("the renderer gave no depth for the .exr")
        write_exr(args.output, rgba.astype(np.float32) / 255.0, depth.astype(np.float32))
    print(f"rendered {width}x{height} ({how}) in {seconds:.2f} s")
    report(rgba, args.output)


class Viewer:
    """The interactive window: VTK's trackball camera plus Sightline's keys."""

    def __init__(self, scene, args):
        self.scene, self.args = scene, args
        self.window = vtk.vtkRenderWindow()
        self.window.AddRenderer(scene.renderer)
        self.window.SetSize(*args.size)
        self.window.SetWindowName("sightline-view: " + ", ".join(
            os.path.basename(layer.path) for layer in scene.layers))
        self.screenshots = 0
        self.actions = {
            "Up": lambda: scene.move_slice(1), "Prior": lambda: scene.move_slice(1),
            "Down": lambda: scene.move_slice(-1), "Next": lambda: scene.move_slice(-1),
            "a": lambda: scene.set_orientation("axial"),
            "c": lambda: scene.set_orientation("coronal"),
            "s": lambda: scene.set_orientation("sagittal"),
            "h": scene.cycle_shadows, "o": scene.toggle_translucent, "p": self.screenshot,
            "r": lambda: scene.reset_camera() and "camera reset",
        }

    def handle(self, key):
        action = self.actions.get(key)
        if action is None:
            return False
        message = action()
        if message:
            print(f"[{key}] {message}", flush=True)
        self.scene.renderer.ResetCameraClippingRange()
        self.window.Render()
        return True

    def screenshot(self):
        folder = self.args.screenshot_dir
        while True:
            self.screenshots += 1
            path = os.path.join(folder, f"sightline-view-{self.screenshots:03d}.png")
            if not os.path.exists(path):
                break
        self.window.Render()
        grab = vtk.vtkWindowToImageFilter()
        grab.SetInput(self.window)
        grab.ReadFrontBufferOff()
        grab.Update()
        writer = vtk.vtkPNGWriter()
        writer.SetFileName(path)
        writer.SetInputConnection(grab.GetOutputPort())
        writer.Write()
        report(image_arrays(grab.GetOutput())[0], path)
        return None

    def run(self, keys=None):
        if keys is not None:  # scripted: the key handlers in order, offscreen, then exit
            self.window.SetOffScreenRendering(1)
            self.window.SetMultiSamples(0)
            self.window.Render()
            for key in keys:
                if not self.handle(key):
                    raise ViewError(f"--keys: no action for key '{key}'")
            return
        interactor = vtk.vtkRenderWindowInteractor()
        interactor.SetRenderWindow(self.window)
        style = vtk.vtkInteractorStyleTrackballCamera()
        interactor.SetInteractorStyle(style)
        interactor.SetDesiredUpdateRate(8.0)  # the mappers trace every second pixel meanwhile

        # Observers on the style replace its own OnKeyPress/OnChar: our keys act once, on the
        # key press; VTK's other keys keep their meaning (q/e quit, f fly to), except the ones
        # that would switch the tubes to wireframe or stereo.
        def on_key_press(caller, _event):
            self.handle(caller.GetInteractor().GetKeySym())

        def on_char(caller, _event):
            key = caller.GetInteractor().GetKeySym()
            if key not in self.actions and key not in ("w", "3", "j", "t", "u"):
                style.OnChar()

        style.AddObserver(vtk.vtkCommand.CharEvent, on_char)
        style.AddObserver(vtk.vtkCommand.KeyPressEvent, on_key_press)
        interactor.Initialize()
        self.window.Render()
        print("keys: Up/Down slice, a/c/s orientation, h shadows, o translucency, p screenshot, "
              "r reset camera, q quit", flush=True)
        interactor.Start()


def add_legacy_options(parser):
    """--legacy / --no-legacy (args.legacy: True, False or None for the basis' default); also
    used by the SH examples."""
    legacy = parser.add_mutually_exclusive_group()
    legacy.add_argument("--legacy", dest="legacy", action="store_true", default=None,
                        help="the legacy variant of the basis (default: the basis' own)")
    legacy.add_argument("--no-legacy", dest="legacy", action="store_false",
                        help="the non-legacy variant of the basis")


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog="sightline-view", description=__doc__.split("\n\n", 1)[1].split("\nWindow keys")[0],
        epilog=__doc__.split("\n\n")[-1] + "\n" + EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("files", nargs="+", metavar="FILE")
    parser.add_argument("--output", metavar="FILE.png|FILE.exr",
                        help="write one image without a window (vtkSightlineImageRenderer, no "
                             "OpenGL; .exr adds the depth as channel Z) and exit")
    parser.add_argument("--size", type=int, nargs=2, default=(1200, 900), metavar=("W", "H"),
                        help="window or image size in pixels (default 1200 900)")
    glyphs = parser.add_argument_group("SH and tensor images")
    glyphs.add_argument("--basis", choices=sorted(BASES),
                        help="read the image as SH coefficients in this basis (default: dipy = "
                             "descoteaux07 legacy for NIfTI, mrtrix3 = tournier07 for .mif)")
    add_legacy_options(glyphs)
    glyphs.add_argument("--layout", choices=sorted(LAYOUTS),
                        help="read the image as tensors in this component order (default by "
                             "count: 6 -> fsl (xx xy xz yy yz zz), or dipy (xx xy yy xz yz zz) "
                             "when the NIfTI intent is SYMMATRIX, or mrtrix3 (xx yy zz xy xz yz) "
                             "for .mif; 9/81/729 -> full; 36 -> voigt)")
    glyphs.add_argument("--tensor-shape", choices=("ellipsoid", "function"), default="ellipsoid",
                        help="order-2 tensors as ellipsoids (default) or as the tensor function "
                             "r(w) = |w^T D w|; higher orders are always the function")
    glyphs.add_argument("--frame", choices=("world", "voxel"), default="world",
                        help="axes of the glyph directions: world (scanner axes, as MRtrix3 "
                             "writes them; default) or voxel (the NIfTI file's axes, as DIPY "
                             "fits with FSL-style b-vectors give them)")
    glyphs.add_argument("--slice", choices=("axial", "coronal", "sagittal"), default="axial")
    glyphs.add_argument("--index", type=int, default=-1, help="slice index (default: middle)")
    glyphs.add_argument("--scale", type=float, default=1.0,
                        help="glyph size; 1 makes the longest lobe fill its voxel (default)")
    glyphs.add_argument("--shadows", choices=SHADOWS, default="soft")
    glyphs.add_argument("--underlay", metavar="NIFTI",
                        help="scalar NIfTI (FA, T1, b0) drawn as a grey slice beneath the glyphs")
    glyphs.add_argument("--mosaic", metavar="ROWS",
                        help="a report figure instead of one view: rows of evenly spaced "
                             "slices framed on the brain, labelled, e.g. "
                             "axial:8,coronal:8,sagittal:8 (needs --output FILE.png; no X, "
                             "bounded memory: only the drawn slices are read)")
    glyphs.add_argument("--slab", type=float, metavar="MM",
                        help="with --mosaic and a tractogram: draw in each panel only the "
                             "streamlines within a slab this thick around the slice (default: "
                             "the whole tractogram, cut by the underlay)")
    glyphs.add_argument("--scalar-bar", action="store_true",
                        help="with --mosaic: the underlay's grey window as a labelled ramp")
    glyphs.add_argument("--elevation", type=float, default=50.0,
                        help="camera elevation above the slice plane in degrees (default 50)")
    other = parser.add_argument_group("tubes and volumes")
    other.add_argument("--radius", type=float,
                       help="tube radius (default: the SWC file's radii; for streamlines 0.5 mm, "
                            "or 1/200 of the bundle's diagonal when that is smaller)")
    other.add_argument("--color", metavar="ARRAY",
                       help="colour streamlines by a per-point or per-streamline array (a TRX "
                            "dpv or dps, a .trk scalar or property) instead of by direction")
    other.add_argument("--tsf", metavar="FILE.tsf",
                       help="MRtrix3 track scalars (tcksample's .tsf) for a .tck: a point array "
                            "named after the file, which colours the tubes unless --color says")
    other.add_argument("--group", action="append", metavar="NAME",
                       help="show only the streamlines of this TRX group (repeat for several)")
    other.add_argument("--pieces", type=int, default=0, metavar="N",
                       help="stream a tractogram in N pieces, never holding its poly data whole "
                            "(chunked tubes; default: 1 below 512 MiB of file, else one piece "
                            "per 64 MiB)")
    other.add_argument("--grid", choices=("spherical", "cylindrical"), default="spherical",
                       help=".vtr coordinates: (r, theta, phi) or (rho, phi, z)")
    other.add_argument("--angles", choices=("auto", "radians", "degrees"), default="auto",
                       help=".vtr angle units (auto: degrees when an angle exceeds 2 pi)")
    earth = parser.add_argument_group("Earth and planetary models (.nc)")
    earth.add_argument("--variable", metavar="NAME",
                       help="the variable to draw (default: the first on the grid)")
    earth.add_argument("--cut", choices=("wedge", "hemisphere"),
                       help="remove a 90-degree wedge or a hemisphere facing the camera")
    earth.add_argument("--view-longitude", type=float, metavar="DEG",
                       help="look from above this longitude (default: the model's middle, 0 E "
                            "for a global one); the cut is centred on it")
    earth.add_argument("--view-latitude", type=float, metavar="DEG",
                       help="look from above this latitude (default: the model's middle, 20 N "
                            "for a global one)")
    earth.add_argument("--reference-radius", type=float, default=6371.0, metavar="KM",
                       help="radius depths are measured from (default 6371, the Earth)")
    earth.add_argument("--vertical", choices=("auto", "depth", "radius", "altitude"),
                       default="auto", help="what the vertical coordinate is (default: from "
                                            "its 'positive' attribute and name)")
    earth.add_argument("--no-graticule", dest="graticule", action="store_false",
                       help="no parallels and meridians on the outer sphere")
    parser.add_argument("--screenshot-dir", default=".", metavar="DIR",
                        help="where the p key saves sightline-view-NNN.png (default: here)")
    parser.add_argument("--keys", metavar="K1,K2,...",
                        help="run these window keys in order in an offscreen window and exit "
                             "(scripted use and tests, e.g. Up,h,o,p)")
    args = parser.parse_args(argv)
    if args.scale <= 0:
        parser.error(f"--scale must be positive, got {args.scale}")
    if args.radius is not None and args.radius <= 0:
        parser.error(f"--radius must be positive, got {args.radius}")
    if args.slab is not None and args.slab <= 0:
        parser.error(f"--slab must be positive, got {args.slab}")
    if args.pieces < 0:
        parser.error(f"--pieces must be 1 or more (0: automatic), got {args.pieces}")
    if min(args.size) <= 0:
        parser.error(f"--size must be positive, got {args.size[0]} {args.size[1]}")
    return args


def run_mosaic(args):
    """--mosaic: sightline.figures.mosaic on the SH or tensor image and/or the tractogram given."""
    from sightline import figures

    kinds = {path: lower_extension(path) for path in args.files}
    images = [p for p, e in kinds.items() if e in (".nii", ".nii.gz", ".mif", ".mif.gz")]
    tracts = [p for p, e in kinds.items() if e in (".trk", ".tck", ".trx")]
    if len(images) > 1 or len(tracts) > 1 or len(images) + len(tracts) != len(args.files):
        raise ViewError("--mosaic draws one SH or tensor image (.nii, .nii.gz, .mif, .mif.gz) "
                        f"and/or one tractogram (.trk, .tck, .trx), got {' '.join(args.files)}")
    if not args.output or not args.output.lower().endswith(".png"):
        raise ViewError("--mosaic writes a picture: give --output FILE.png")
    try:
        figures.mosaic(images[0] if images else None, underlay=args.underlay,
                       panels=args.mosaic, size=args.size, output=args.output,
                       tractogram=tracts[0] if tracts else None, slab=args.slab,
                       radius=args.radius, basis=args.basis, legacy=args.legacy,
                       layout=args.layout, frame=args.frame, scale=args.scale,
                       tensor_shape=args.tensor_shape, background=BACKGROUND,
                       scalar_bar=args.scalar_bar)
    except figures.FigureError as error:
        raise ViewError(str(error)) from None


def main(argv=None):
    args = parse_arguments(argv)
    try:
        if args.mosaic:
            run_mosaic(args)
            return 0
        layers = []
        for path in args.files:
            start = time.perf_counter()
            print(f"loading {path} ...", flush=True)
            layer = load(path, args)
            layers.append(layer)
            seconds = time.perf_counter() - start
            print(f"  {layer.describe()}" + (f" [{seconds:.1f} s]" if seconds > 0.5 else ""),
                  flush=True)
        scene = Scene(layers, args)
        if args.output:
            render_to_file(scene, args)
            return 0
        if args.keys is None and sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
            raise ViewError("no X display for the window: use --output FILE.png, or run under "
                            "xvfb-run")
        Viewer(scene, args).run(args.keys.split(",") if args.keys is not None else None)
        return 0
    except (ViewError, nifti.NiftiError) as error:
        print(f"sightline-view: error: {error}", file=sys.stderr)
        return 2
