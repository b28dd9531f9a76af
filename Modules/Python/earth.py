# SPDX-License-Identifier: BSD-3-Clause
"""Earth and planetary models on spherical grids: what a geoscientist's view of one needs
around vtkSightlineSphericalVolumeMapper.

- read_model: a CF netCDF longitude/latitude/depth model (vtkSightlineNetCDFSphericalReader)
  as the mapper's (r, colatitude, azimuth) grid, with named errors;
- diverging_volume_property: perturbations (dvs, dlnVp, ...) in a diverging map centred on zero
  (slow red, fast blue, as tomographers draw them), transparent near zero;
- cut_away: the grid without an azimuth wedge (or a hemisphere), so that the inside shows;
  exact, since it keeps whole cells;
- graticule_actor: parallels and meridians (vtkSightlineGraticuleSource) on the model's outer
  sphere as exact Sightline tubes (so that they show in a window and in GL-free images alike),
  over the model's own latitude and longitude range, on the side a camera sees.
"""
import math

import numpy as np
import vtk
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_STRING

import sightline


class ModelError(Exception):
    """A file that is not a model the reader can place on the sphere (the reader's words)."""


def _errors_of(algorithm):
    messages = []

    @calldata_type(VTK_STRING)
    def collect(caller, event, message):
        messages.append(message)

    algorithm.AddObserver(vtk.vtkCommand.ErrorEvent, collect)
    return messages


def read_model(path, variable=None, reference_radius=6371.0, vertical="auto"):
    """(vtkRectilinearGrid, reader) of a CF netCDF model: x = radius (km), y = colatitude,
    z = azimuth (radians), the variables as point data, `variable` (or the first) active."""
    reader = sightline.vtkSightlineNetCDFSphericalReader()
    reader.SetFileName(str(path))
    if variable:
        reader.SetVariableName(variable)
    reader.SetReferenceRadius(reference_radius)
    reader.SetVerticalCoordinate(("auto", "depth", "radius", "altitude").index(vertical))
    errors = _errors_of(reader)
    reader.Update()
    if errors or reader.GetOutput().GetNumberOfPoints() == 0:
        detail = "; ".join(str(e).strip().splitlines()[-1] for e in errors if e)
        raise ModelError(detail or f"{path}: no model could be read")
    return reader.GetOutput(), reader


def diverging_volume_property(low, high, max_opacity=0.8, floor=0.002):
    """Colour and opacity for a perturbation in [low, high]: blue (fast, > 0) - white - red
    (slow, < 0) on a range symmetric about zero; opacity grows with |value| from `floor`.
    A range that does not straddle zero gets a sequential ramp over [low, high] instead."""
    color, opacity = vtk.vtkColorTransferFunction(), vtk.vtkPiecewiseFunction()
    if low < 0.0 < high:
        extent = max(-low, high)
        for t, rgb in ((-1.0, (0.65, 0.0, 0.05)), (-0.5, (0.95, 0.45, 0.3)),
                       (0.0, (0.97, 0.97, 0.95)), (0.5, (0.4, 0.6, 0.95)),
                       (1.0, (0.02, 0.2, 0.6))):
            color.AddRGBPoint(t * extent, *rgb)
        opacity.AddPoint(-extent, max_opacity)
        opacity.AddPoint(0.0, floor)
        opacity.AddPoint(extent, max_opacity)
    else:
        if not high > low:
            high = low + 1.0
        for t, rgb in ((0.0, (0.18, 0.12, 0.45)), (0.35, (0.13, 0.47, 0.56)),
                       (0.7, (0.35, 0.75, 0.38)), (1.0, (0.99, 0.9, 0.15))):
            color.AddRGBPoint(low + t * (high - low), *rgb)
        opacity.AddPoint(low, floor)
        opacity.AddPoint(high, max_opacity)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    return prop


def _grid(radius, colatitude, azimuth, arrays, active):
    grid = vtk.vtkRectilinearGrid()
    grid.SetDimensions(len(radius), len(colatitude), len(azimuth))
    for setter, values in ((grid.SetXCoordinates, radius), (grid.SetYCoordinates, colatitude),
                           (grid.SetZCoordinates, azimuth)):
        setter(numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=True))
    for name, values in arrays.items():
        array = numpy_to_vtk(np.ascontiguousarray(values).ravel(), deep=True)
        array.SetName(name)
        grid.GetPointData().AddArray(array)
    grid.GetPointData().SetActiveScalars(active)
    return grid


def cut_away(grid, centre_longitude, width_degrees):
    """The grid without the azimuth wedge of `width_degrees` centred on `centre_longitude`
    (degrees east; 180 removes a hemisphere), keeping whole cells: the nodes outside the wedge,
    from its east edge round to its west edge. A regional grid keeps what lies outside the
    wedge on its own range (its larger side, where the wedge splits it)."""
    radius = vtk_to_numpy(grid.GetXCoordinates()).astype(np.float64)
    colatitude = vtk_to_numpy(grid.GetYCoordinates()).astype(np.float64)
    azimuth = vtk_to_numpy(grid.GetZCoordinates()).astype(np.float64)
    data = grid.GetPointData()
    names = [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]
    arrays = {name: vtk_to_numpy(data.GetArray(name)).reshape(
        len(azimuth), len(colatitude), len(radius)) for name in names}
    full_turn = abs(azimuth[-1] - azimuth[0] - 2 * math.pi) < 1e-9
    if full_turn:  # a closed globe: drop the closing meridian, roll, close again
        azimuth = azimuth[:-1]
        arrays = {name: values[:-1] for name, values in arrays.items()}
    centre = math.radians(centre_longitude)
    half = math.radians(width_degrees) / 2
    offset = np.mod(azimuth - centre + math.pi, 2 * math.pi) - math.pi  # in [-pi, pi)
    keep = np.abs(offset) >= half - 1e-12
    if full_turn:
        order = np.argsort(np.mod(offset, 2 * math.pi))  # from the wedge's east edge
        order = order[keep[order]]
        kept = azimuth[order]
        kept = kept[0] + np.mod(kept - kept[0], 2 * math.pi)
        kept[1:][np.diff(kept) <= 0] += 2 * math.pi
        arrays = {name: values[order] for name, values in arrays.items()}
        azimuth = kept
    else:
        # The longest run of kept nodes of a regional grid.
        runs, start = [], None
        for i, k in enumerate(list(keep) + [False]):
            if k and start is None:
                start = i
            elif not k and start is not None:
                runs.append((start, i))
                start = None
        if not runs:
            raise ModelError("the cut removes the whole model")
        first, last = max(runs, key=lambda run: run[1] - run[0])
        azimuth = azimuth[first:last]
        arrays = {name: values[first:last] for name, values in arrays.items()}
    if len(azimuth) < 2:
        raise ModelError("the cut leaves less than one cell of longitude")
    return _grid(radius, colatitude, azimuth, arrays, data.GetScalars().GetName())


def graticule_actor(grid, facing=None, step_degrees=30.0, color=(0.85, 0.88, 0.92)):
    """An actor of exact tubes along the graticule (vtkSightlineGraticuleSource) just above
    `grid`'s outer sphere, over its latitude and longitude range (a spherical grid in the
    mapper's default convention); with `facing` (a direction towards the camera) only on the
    hemisphere it points to. Regional grids get a finer step (about a quarter of their span)."""
    radius = vtk_to_numpy(grid.GetXCoordinates())
    colatitude = np.degrees(vtk_to_numpy(grid.GetYCoordinates()))
    azimuth = np.degrees(vtk_to_numpy(grid.GetZCoordinates()))
    outer = float(radius.max())
    span = max(np.ptp(colatitude), np.ptp(azimuth))
    source = sightline.vtkSightlineGraticuleSource()
    source.SetRadius(outer * 1.004)
    source.SetStep(step_degrees if span > 2 * step_degrees else max(1.0, round(span / 4.0)))
    source.SetLatitudeRange(90.0 - colatitude.max(), 90.0 - colatitude.min())
    source.SetLongitudeRange(azimuth.min(), azimuth.max())
    if facing is not None:
        source.SetFacingDirection(*facing)
    mapper = sightline.vtkSightlineTubeMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    mapper.SetRadius(outer * 0.0022)
    mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*color)
    actor.GetProperty().SetAmbient(0.4)
    return actor
