# SPDX-License-Identifier: BSD-3-Clause
"""Sightline in PyVista: exact tubes, glyphs, spheres and spherical volumes on a pyvista.Plotter.

    import pyvista as pv
    import sightline.pyvista  # gives every plotter a `sightline` component

    plotter = pv.Plotter(off_screen=True)
    plotter.sightline.add_tubes(streamlines, radius=0.4, scalars="FA", cmap="viridis")
    plotter.sightline.add_sh_glyphs(odf_image, basis="descoteaux07")
    plotter.add_mesh(brain_surface, opacity=0.3)  # ordinary PyVista actors mix in, depth and all
    plotter.screenshot("figure.png")

Each add_* takes PyVista (or plain VTK) datasets, PyVista's colour maps and scalar bars, and
returns the vtkActor (vtkVolume for add_spherical_volume) it added, whose mapper is the
Sightline mapper: everything the mapper offers stays reachable through actor.GetMapper().

PyVista 0.48 and later register the component through `pyvista.register_plotter_component`
(and its lifecycle hooks); older PyVista (Debian 13 packages 0.44) has no registry, so the same
`plotter.sightline` namespace is attached to pyvista.BasePlotter as a cached property.
"""
import numpy as np
import pyvista
import vtk

import sightline

__all__ = ["SightlineError", "SightlinePlotterComponent"]

COMPONENT_NAME = "sightline"


class SightlineError(ValueError):
    """Input the Sightline plotter component cannot draw (the message says why)."""


class _ColourMapping:
    """What PyVista's add_scalar_bar reads from a mapper (lookup_table, scalar_range), for a
    Sightline mapper: a shared scalar bar's range change reaches the mapper too."""

    def __init__(self, mapper, table):
        self._mapper = mapper
        self.lookup_table = table

    @property
    def scalar_range(self):
        return tuple(self._mapper.GetScalarRange())

    @scalar_range.setter
    def scalar_range(self, clim):
        self._mapper.SetScalarRange(float(clim[0]), float(clim[1]))
        self.lookup_table.scalar_range = (float(clim[0]), float(clim[1]))


def _dataset(data, kinds, what):
    """`data` wrapped by PyVista, checked to be one of `kinds` (VTK class names)."""
    if data is None:
        raise SightlineError(f"{what}: no dataset given")
    if isinstance(data, np.ndarray):
        data = pyvista.PolyData(np.asarray(data, dtype=float).reshape(-1, 3))
    wrapped = pyvista.wrap(data) if isinstance(data, vtk.vtkDataObject) else None
    if wrapped is None or not any(wrapped.IsA(kind) for kind in kinds):
        name = type(data).__name__
        raise SightlineError(f"{what} draws {' or '.join(kinds)}, not a {name}")
    # A shallow copy: arrays added for colouring stay off the caller's dataset.
    return wrapped.copy(deep=False)


def _named_array(data, scalars, what, preference="point"):
    """(name, association) of the array `scalars` names, or of a numpy array added under the
    name 'Data' (per point, or per cell where the count says so)."""
    if isinstance(scalars, str):
        point = data.GetPointData().GetAbstractArray(scalars)
        cell = data.GetCellData().GetAbstractArray(scalars)
        if point is not None and (cell is None or preference == "point"):
            return scalars, "point"
        if cell is not None:
            return scalars, "cell"
        names = sorted(set(data.point_data.keys()) | set(data.cell_data.keys()))
        raise SightlineError(f"{what}: no array '{scalars}' (there are: {', '.join(names) or 'none'})")
    values = np.asarray(scalars)
    if len(values) == data.n_points and (preference == "point" or len(values) != data.n_cells):
        data.point_data["Data"] = values
        return "Data", "point"
    if len(values) == data.n_cells:
        data.cell_data["Data"] = values
        return "Data", "cell"
    raise SightlineError(f"{what}: {len(values)} scalars for {data.n_points} points and "
                         f"{data.n_cells} cells")


def _colour_range(values, clim):
    """clim, or the finite values' range (0..1 when there are none), never empty."""
    if clim is None:
        finite = values[np.isfinite(values)]
        clim = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if not clim[1] > clim[0]:
        clim = (clim[0], clim[0] + 1.0)
    return clim


class SightlinePlotterComponent:
    """`plotter.sightline`: Sightline's exact primitives added to a PyVista plotter."""

    def __init__(self, plotter):
        self._plotter = plotter

    # -- the primitives ---------------------------------------------------------------------
    def add_tubes(self, lines, radius=None, radius_array=None, predecessor_array=None,
                  **kwargs):
        """Poly-lines (streamlines: a PolyData with lines) as exact generalised tubes: spheres
        at the points joined by tangent cone stumps. radius in world units (default 1/200 of
        the diagonal), or radius_array names per-point radii; predecessor_array names per-point
        parent indices for trees (SWC neurons). Colour keywords as for add_spheres."""
        data = _dataset(lines, ["vtkPolyData"], "add_tubes")
        if data.GetNumberOfLines() == 0 and predecessor_array is None:
            raise SightlineError("add_tubes: the PolyData holds no lines")
        mapper = sightline.vtkSightlineTubeMapper()
        mapper.SetInputDataObject(data)
        if predecessor_array is not None:
            self._require_array(data, predecessor_array, "add_tubes")
            mapper.SetPredecessorArrayName(predecessor_array)
        if radius_array is not None:
            self._require_array(data, radius_array, "add_tubes")
            mapper.SetRadiusArrayName(radius_array)
        else:
            mapper.SetRadius(float(radius) if radius is not None else data.length / 200.0)
        return self._add_actor(mapper, data, "add_tubes", **kwargs)

    def add_spheres(self, points, radius=None, radius_array=None, **kwargs):
        """Points (any point set, or an N x 3 array) as exact spheres. radius in world units
        (default 1/100 of the diagonal), or radius_array names per-point radii.

        Colour keywords (every add_* but add_spherical_volume): scalars (an array name or
        values), cmap, clim, color, opacity, show_scalar_bar, scalar_bar_args, lighting,
        name, reset_camera, as in pyvista.Plotter.add_mesh."""
        data = _dataset(points, ["vtkPointSet"], "add_spheres")
        mapper = sightline.vtkSightlineSphereMapper()
        mapper.SetInputDataObject(data)
        if radius_array is not None:
            self._require_array(data, radius_array, "add_spheres")
            mapper.SetRadiusArrayName(radius_array)
        else:
            mapper.SetRadius(float(radius) if radius is not None else max(data.length, 1.0) / 100.0)
        return self._add_actor(mapper, data, "add_spheres", **kwargs)

    def add_sh_glyphs(self, image, coefficients=None, basis="descoteaux07", legacy=None,
                      scale=1.0, normalization="max_amplitude", slice_orientation="extent",
                      slice_number=None, **kwargs):
        """An image (ImageData) of spherical-harmonic coefficients (even orders, one tuple per
        voxel: `coefficients` names the array, default the active scalars) as exact SH glyphs.
        basis 'descoteaux07' (DIPY) or 'tournier07' (MRtrix3); legacy defaults to the basis's
        own (DIPY's legacy descoteaux07). scale: glyph size in half voxels; normalization
        'max_amplitude', 'global', 'coefficient_norm' or 'none'. slice_orientation 'extent'
        (every voxel) or 'axial', 'coronal', 'sagittal' with slice_number. Without scalars
        the glyphs are coloured by direction."""
        data = _dataset(image, ["vtkImageData"], "add_sh_glyphs")
        mapper = sightline.vtkSightlineSHGlyphMapper()
        if coefficients is not None:
            self._require_array(data, coefficients, "add_sh_glyphs", point_only=True)
            mapper.SetCoefficientArrayName(coefficients)
        if str(basis).lower() not in ("descoteaux07", "tournier07"):
            raise SightlineError(f"add_sh_glyphs: basis '{basis}' is not descoteaux07 or tournier07")
        mapper.SetBasisByName(str(basis).lower())
        if legacy is not None:
            mapper.SetLegacyBasis(bool(legacy))
        return self._add_glyphs(mapper, data, "add_sh_glyphs", scale, normalization,
                                slice_orientation, slice_number, **kwargs)

    def add_tensor_glyphs(self, image, tensors=None, layout="automatic", shape="tensor_function",
                          scale=1.0, normalization="max_amplitude", slice_orientation="extent",
                          slice_number=None, **kwargs):
        """An image of symmetric tensors of order 2 to 12 (`tensors` names the array, default
        the active tensors or scalars) as exact glyphs of |T(w)|, or shape='ellipsoid' for
        second-order tensors as vtkTensorGlyph draws them. layout 'automatic',
        'symmetric_unique', 'full', 'vtk_symmetric' or 'voigt'. Other keywords as for
        add_sh_glyphs."""
        data = _dataset(image, ["vtkImageData"], "add_tensor_glyphs")
        mapper = sightline.vtkSightlineTensorGlyphMapper()
        if tensors is not None:
            self._require_array(data, tensors, "add_tensor_glyphs", point_only=True)
            mapper.SetTensorArrayName(tensors)
        layouts = {"automatic": "Automatic", "symmetric_unique": "SymmetricUnique",
                   "full": "Full", "vtk_symmetric": "VTKSymmetric", "voigt": "Voigt"}
        shapes = {"tensor_function": "TensorFunction", "ellipsoid": "Ellipsoid"}
        getattr(mapper, "SetTensorLayoutTo" + self._choice(layouts, layout, "layout"))()
        getattr(mapper, "SetShapeTo" + self._choice(shapes, shape, "shape"))()
        return self._add_glyphs(mapper, data, "add_tensor_glyphs", scale, normalization,
                                slice_orientation, slice_number, **kwargs)

    def add_spherical_volume(self, grid, scalars=None, cmap=None, clim=None, opacity="linear",
                             coordinates="spherical", angles="radians", unit_distance=None,
                             show_scalar_bar=True, scalar_bar_args=None, name=None,
                             reset_camera=None):
        """A RectilinearGrid on (r, theta, phi) axes (x radius, y polar angle from +z, z
        azimuth; or coordinates='cylindrical': r, phi, z) ray-cast exactly on its own cells.
        cmap/clim/opacity as pyvista.Plotter.add_volume (opacity: a name such as 'linear',
        'sigmoid', 'geom' or values over the colour range); unit_distance: the length over
        which full opacity accumulates (default 1/8 of the largest extent)."""
        data = _dataset(grid, ["vtkRectilinearGrid"], "add_spherical_volume")
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputDataObject(data)
        self._choice({"spherical": None, "cylindrical": None}, coordinates, "coordinates")
        self._choice({"radians": None, "degrees": None}, angles, "angles")
        if coordinates == "cylindrical":
            mapper.SetCoordinateSystemToCylindrical()
        if angles == "degrees":
            mapper.SetAngleUnitsToDegrees()
        if scalars is None:
            array = data.GetPointData().GetScalars() or data.GetCellData().GetScalars()
            if array is None:
                raise SightlineError("add_spherical_volume: the grid has no active scalars; "
                                     "name an array with scalars=")
            scalars = array.GetName()
        name_, association = _named_array(data, scalars, "add_spherical_volume")
        if association == "point":
            data.GetPointData().SetActiveScalars(name_)
        else:
            data.GetCellData().SetActiveScalars(name_)
        values = (data.point_data if association == "point" else data.cell_data)[name_]
        clim = _colour_range(np.asarray(values), clim)
        table = pyvista.LookupTable(cmap=cmap or self._plotter.theme.cmap)
        table.scalar_range = clim
        count = table.n_values
        if isinstance(opacity, str):
            opacity = pyvista.opacity_transfer_function(opacity, count)
        opacity = np.atleast_1d(np.asarray(opacity, dtype=float))
        if opacity.size != count:  # values spread evenly over the colour range
            opacity = np.interp(np.linspace(0, 1, count), np.linspace(0, 1, opacity.size), opacity)
        if opacity.min() < 0 or opacity.max() > 1:
            raise SightlineError("add_spherical_volume: opacity values lie in [0, 1]")
        # Transfer functions over the data's own values (PyVista's add_volume rescales the data
        # to table indices instead; the mapper reads the grid as it is).
        colour, scalar_opacity = vtk.vtkColorTransferFunction(), vtk.vtkPiecewiseFunction()
        for index, value in enumerate(np.linspace(clim[0], clim[1], count)):
            colour.AddRGBPoint(value, *table.GetTableValue(index)[:3])
            scalar_opacity.AddPoint(value, opacity[index])
        prop = vtk.vtkVolumeProperty()
        prop.SetColor(colour)
        prop.SetScalarOpacity(scalar_opacity)
        prop.SetInterpolationTypeToLinear()
        if unit_distance is None:
            bounds = mapper.GetBounds()
            unit_distance = max(bounds[1] - bounds[0], bounds[3] - bounds[2],
                                bounds[5] - bounds[4]) / 8.0
        prop.SetScalarOpacityUnitDistance(float(unit_distance))
        volume = vtk.vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        self._plotter.add_actor(volume, name=name, reset_camera=self._reset(reset_camera))
        if show_scalar_bar:
            mapper.SetScalarRange(*clim)
            self._plotter.add_scalar_bar(**self._bar_arguments(scalar_bar_args, name_),
                                         mapper=_ColourMapping(mapper, table))
        return volume

    # -- shared --------------------------------------------------------------------------------
    def _add_glyphs(self, mapper, data, what, scale, normalization, slice_orientation,
                    slice_number, **kwargs):
        normalizations = {"max_amplitude": "MaxAmplitude", "global": "Global",
                          "coefficient_norm": "CoefficientNorm", "none": "None"}
        orientations = {"extent": "Extent", "axial": "Axial", "coronal": "Coronal",
                        "sagittal": "Sagittal"}
        getattr(mapper, "SetNormalizationTo" + self._choice(normalizations, normalization,
                                                            "normalization"))()
        getattr(mapper, "SetSliceOrientationTo" + self._choice(orientations, slice_orientation,
                                                              "slice_orientation"))()
        if slice_number is not None:
            mapper.SetSliceNumber(int(slice_number))
        mapper.SetScaleFactor(float(scale))
        mapper.SetInputDataObject(data)
        if kwargs.get("scalars") is not None:
            mapper.SetColoringToScalars()
        elif kwargs.get("color") is not None:
            mapper.SetColoringToSolid()
        return self._add_actor(mapper, data, what, default_color=False, **kwargs)

    def _add_actor(self, mapper, data, what, scalars=None, cmap=None, clim=None, color=None,
                   opacity=1.0, show_scalar_bar=True, scalar_bar_args=None, lighting=True,
                   name=None, reset_camera=None, default_color=True):
        actor = vtk.vtkActor()
        actor.SetMapper(mapper)
        prop = actor.GetProperty()
        theme = self._plotter.theme
        if scalars is not None:
            array_name, association = _named_array(data, scalars, what)
            values = np.asarray((data.point_data if association == "point"
                                 else data.cell_data)[array_name], dtype=float)
            if values.ndim > 1:
                values = np.linalg.norm(values, axis=1)
            clim = _colour_range(values, clim)
            table = pyvista.LookupTable(cmap=cmap or theme.cmap)
            table.scalar_range = clim
            mapper.SetLookupTable(table)
            mapper.SetScalarRange(*clim)
            mapper.ScalarVisibilityOn()
            mapper.SetColorModeToMapScalars()
            if association == "point":
                mapper.SetScalarModeToUsePointFieldData()
            else:
                mapper.SetScalarModeToUseCellFieldData()
            mapper.SelectColorArray(array_name)
        else:
            mapper.ScalarVisibilityOff()
            if color is not None or default_color:
                prop.SetColor(pyvista.Color(color, default_color=theme.color).float_rgb)
        prop.SetOpacity(float(opacity))
        if lighting:
            prop.SetAmbient(0.2)
            prop.SetDiffuse(0.8)
            prop.SetSpecular(0.3)
            prop.SetSpecularPower(30)
        else:
            prop.SetAmbient(1.0)
            prop.SetDiffuse(0.0)
            prop.SetSpecular(0.0)
        self._plotter.add_actor(actor, name=name, reset_camera=self._reset(reset_camera))
        if scalars is not None and show_scalar_bar:
            self._plotter.add_scalar_bar(**self._bar_arguments(scalar_bar_args, array_name),
                                         mapper=_ColourMapping(mapper, table))
        return actor

    def _reset(self, reset_camera):
        """PyVista's rule: the first actor frames the camera unless told otherwise."""
        if reset_camera is not None:
            return bool(reset_camera)
        return not self._plotter.camera_set

    @staticmethod
    def _bar_arguments(scalar_bar_args, array_name):
        arguments = dict(scalar_bar_args or {})
        arguments.setdefault("title", array_name)
        return arguments

    @staticmethod
    def _choice(options, value, what):
        key = str(value).lower()
        if key not in options:
            raise SightlineError(f"{what} '{value}' is not one of: {', '.join(options)}")
        return options[key]

    @staticmethod
    def _require_array(data, name, what, point_only=False):
        if data.GetPointData().GetAbstractArray(name) is not None:
            return
        if not point_only and data.GetCellData().GetAbstractArray(name) is not None:
            return
        names = sorted(data.point_data.keys()) if point_only else sorted(
            set(data.point_data.keys()) | set(data.cell_data.keys()))
        raise SightlineError(f"{what}: no array '{name}' (there are: {', '.join(names) or 'none'})")


def _register():
    """plotter.sightline on every PyVista plotter: through PyVista's registry where it has one
    (0.48+), otherwise as a cached property of BasePlotter (what the registry does)."""
    register = getattr(pyvista, "register_plotter_component", None)
    if register is not None:
        if not any(r.name == COMPONENT_NAME for r in pyvista.registered_plotter_components()):
            register(COMPONENT_NAME)(SightlinePlotterComponent)
        return
    base = pyvista.BasePlotter
    if isinstance(getattr(base, COMPONENT_NAME, None), property):
        return

    def component(plotter):
        cached = plotter.__dict__.get("_sightline_component")
        if cached is None:
            cached = plotter.__dict__["_sightline_component"] = SightlinePlotterComponent(plotter)
        return cached

    setattr(base, COMPONENT_NAME, property(component, doc=SightlinePlotterComponent.__doc__))


_register()
