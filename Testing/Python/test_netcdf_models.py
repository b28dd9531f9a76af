# SPDX-License-Identifier: BSD-3-Clause
"""Earth models from CF netCDF files (vtkSightlineNetCDFSphericalReader, sightline.earth,
sightline-view): files shaped like IRIS's Earth Model Collection, written with python3-netcdf4
in every convention the reader accepts, against the analytic model they were written from.

- every node lands where the model puts it (radius from depth, colatitude from latitude,
  azimuth from longitude) with the model's value there, in each convention;
- conventions that describe the same model draw the same image;
- a layered model drawn against the exact optical depths of its shells (sphere chords);
- fill values become empty cells; sub-extents (MPI pieces) are slices of the whole;
- bad files are named errors; sightline-view draws a model with a wedge cut away.
"""
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
import vtk
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_STRING

import sightline
from sightline import earth

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Examples", "Python"))
import write_earth_model as model  # noqa: E402  (the example writes the files users get)

EARTH_KM = model.EARTH_KM
TEMP = os.environ.get("SIGHTLINE_TEST_TEMP_DIR") or tempfile.gettempdir()


def errors_of(algorithm):
    """The list that collects `algorithm`'s error messages."""
    errors = []

    @calldata_type(VTK_STRING)
    def on_error(caller, event, message):
        errors.append(message)

    algorithm.AddObserver(vtk.vtkCommand.ErrorEvent, on_error)
    return errors


def read(path, **settings):
    reader = sightline.vtkSightlineNetCDFSphericalReader()
    reader.SetFileName(path)
    for key, value in settings.items():
        getattr(reader, "Set" + key)(value)
    errors = errors_of(reader)
    reader.Update()
    return reader, reader.GetOutput(), errors


def nodes(grid):
    """(depth km, latitude, east longitude in [0, 360)) of every node, x fastest, and values."""
    r = vtk_to_numpy(grid.GetXCoordinates())
    theta = vtk_to_numpy(grid.GetYCoordinates())
    phi = vtk_to_numpy(grid.GetZCoordinates())
    P, T, R = np.meshgrid(phi, theta, r, indexing="ij")
    depth = np.round(EARTH_KM - R, 6)
    latitude = np.round(90.0 - np.degrees(T), 6)
    east = np.round(np.mod(np.degrees(P), 360.0), 6) % 360.0
    return depth.ravel(), latitude.ravel(), east.ravel()


def values(grid, name=None):
    data = grid.GetPointData()
    array = data.GetArray(name) if name else data.GetScalars()
    return vtk_to_numpy(array)


class Path:
    counter = 0

    @classmethod
    def new(cls, stem):
        cls.counter += 1
        return os.path.join(TEMP, f"netcdf_{os.getpid()}_{cls.counter}_{stem}.nc")


CONVENTIONS = {
    "emc": {},
    "metres_descending_360_classic": dict(depth_units="m", latitude_descending=True,
                                          longitudes="360", order=("latitude", "longitude", "depth"),
                                          file_format="NETCDF3_CLASSIC"),
    "radius_lon_first": dict(vertical="radius", order=("longitude", "depth", "latitude")),
}
REGIONAL = (-30.0, 30.0, 150.0, 210.0)  # crosses the 180-degree meridian


class NodesAreWhereTheModelPutsThem(unittest.TestCase):
    def check(self, path, global_grid):
        reader, grid, errors = read(path)
        self.assertEqual(errors, [])
        for axis in (grid.GetXCoordinates(), grid.GetYCoordinates(), grid.GetZCoordinates()):
            self.assertTrue(np.all(np.diff(vtk_to_numpy(axis)) > 0), "axes increase")
        depth, latitude, east = nodes(grid)
        expected = model.dvs(depth, latitude, east).astype(np.float32)
        np.testing.assert_array_equal(values(grid, "dvs"), expected)
        vs = (model.reference_vs(depth) * (1 + 0.01 * model.dvs(depth, latitude, east)))
        np.testing.assert_array_equal(values(grid, "vs"), vs.astype(np.float32))
        self.assertEqual(grid.GetPointData().GetScalars().GetName(), "dvs")
        phi = vtk_to_numpy(grid.GetZCoordinates())
        if global_grid:  # closed: the first meridian again, one turn on
            self.assertAlmostEqual(phi[-1] - phi[0], 2 * math.pi, places=12)
        return grid

    def test_global_models_in_each_convention(self):
        for name, settings in CONVENTIONS.items():
            with self.subTest(name):
                path = Path.new(name)
                model.write_model(path, step=10.0, **settings)
                grid = self.check(path, True)
                r = vtk_to_numpy(grid.GetXCoordinates())
                np.testing.assert_allclose(r, np.sort(EARTH_KM - model.DEPTHS_KM), rtol=0,
                                           atol=1e-9)
                self.assertEqual(grid.GetDimensions(),
                                 (len(model.DEPTHS_KM), 19, 37))

    def test_regional_model_across_the_seam(self):
        for longitudes in ("-180", "360"):
            with self.subTest(longitudes):
                path = Path.new("regional" + longitudes)
                model.write_model(path, step=2.5, region=REGIONAL, longitudes=longitudes)
                grid = self.check(path, False)
                phi = np.degrees(vtk_to_numpy(grid.GetZCoordinates()))
                self.assertAlmostEqual(phi[-1] - phi[0], 60.0, places=9)
                self.assertAlmostEqual(np.mod(phi[0], 360.0), 150.0, places=9)

    def test_polar_cap_and_equatorial_band(self):
        # A cap reaching the pole (colatitude 0 is a node) and a band closed round the globe.
        for name, region, shape in (("cap", (60.0, 90.0, 0.0, 355.0), (7, 73)),
                                    ("band", (-10.0, 10.0, 0.0, 355.0), (5, 73))):
            with self.subTest(name):
                path = Path.new(name)
                model.write_model(path, step=5.0, region=region, latitude_descending=True)
                grid = self.check(path, True)
                self.assertEqual(grid.GetDimensions()[1:], shape)
                theta = np.degrees(vtk_to_numpy(grid.GetYCoordinates()))
                self.assertAlmostEqual(theta[0], 90.0 - region[1], places=9)

    def test_reference_radius_and_vertical_override(self):
        path = Path.new("mars")
        model.write_model(path, step=30.0)
        _, grid, errors = read(path, ReferenceRadius=3389.5)
        self.assertEqual(errors, [])
        np.testing.assert_allclose(vtk_to_numpy(grid.GetXCoordinates()),
                                   np.sort(3389.5 - model.DEPTHS_KM), atol=1e-9)
        # Read as an altitude instead, the same numbers lie above the surface.
        _, grid, errors = read(path, VerticalCoordinate=3)
        self.assertEqual(errors, [])
        np.testing.assert_allclose(vtk_to_numpy(grid.GetXCoordinates()),
                                   EARTH_KM + model.DEPTHS_KM, atol=1e-9)


def render(grid, size=64, opacity_points=((-4.0, 0.6), (0.0, 0.0), (2.5, 0.6)),
           interpolate=True, direction=(0.55, -0.7, 0.45)):
    mapper = sightline.vtkSightlineSphericalVolumeMapper()
    mapper.SetInputDataObject(grid)
    mapper.SetInterpolatePointData(interpolate)
    color = vtk.vtkColorTransferFunction()
    color.AddRGBPoint(-10.0, 1.0, 1.0, 1.0)
    color.AddRGBPoint(10.0, 1.0, 1.0, 1.0)
    opacity = vtk.vtkPiecewiseFunction()
    for value, alpha in opacity_points:
        opacity.AddPoint(value, alpha)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(1000.0)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    camera = vtk.vtkCamera()
    d = np.asarray(direction, float) / np.linalg.norm(direction)
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(*(20000.0 * d))
    camera.SetViewUp(0, 0, 1)
    camera.ParallelProjectionOn()
    camera.SetParallelScale(7000.0)
    camera.SetClippingRange(10000.0, 30000.0)
    renderer = sightline.vtkSightlineImageRenderer()
    renderer.AddVolume(volume)
    renderer.SetActiveCamera(camera)
    renderer.SetSize(size, size)
    renderer.Update()
    rgba = vtk_to_numpy(renderer.GetOutput().GetPointData().GetScalars()).reshape(size, size, 4)
    return rgba[..., 0].astype(float) / 255.0


class Images(unittest.TestCase):
    def test_conventions_draw_the_same_image(self):
        images = {}
        for name, settings in CONVENTIONS.items():
            path = Path.new("image_" + name)
            model.write_model(path, step=10.0, **settings)
            images[name] = render(read(path)[1])
        reference = images.pop("emc")
        self.assertGreater(np.count_nonzero(reference > 0.05), 200, "the model shows")
        for name, image in images.items():
            difference = np.abs(image - reference)
            self.assertLessEqual(difference.max(), 1.0 / 255 + 1e-9, name)
            self.assertLess(np.count_nonzero(difference), 0.01 * difference.size, name)
        regional = []
        for longitudes in ("-180", "360"):
            path = Path.new("image_regional" + longitudes)
            model.write_model(path, step=2.5, region=REGIONAL, longitudes=longitudes)
            regional.append(render(read(path)[1], direction=(-0.9, 0.15, 0.1)))
        self.assertGreater(np.count_nonzero(regional[0] > 0.05), 20, "the slab shows")
        np.testing.assert_array_equal(regional[0], regional[1])

    def test_layered_model_against_sphere_chords(self):
        # A value per depth node; with InterpolatePointData off each cell holds the mean of its
        # corners, constant on the shell between two depth nodes, so a ray's optical depth is
        # the sum over shells of extinction times the chord length in the shell.
        layer_value = {d: (i % 3) - 1.0 + 0.25 * (i % 2) for i, d in enumerate(model.DEPTHS_KM)}

        def layered(depth, latitude, longitude):
            depth = np.broadcast_arrays(depth, latitude, longitude)[0]
            return np.vectorize(lambda d: layer_value[float(d)])(depth)

        path = Path.new("layered")
        model.write_model(path, field=layered, step=15.0)
        size = 64
        opacity_points = ((-1.0, 0.3), (0.0, 0.05), (1.25, 0.5))
        image = render(read(path)[1], size=size, opacity_points=opacity_points,
                       interpolate=False)
        radii = EARTH_KM - model.DEPTHS_KM  # decreasing
        alpha = np.interp  # the opacity function is piecewise linear in the value
        xs, ys = zip(*opacity_points)
        centres = ((np.arange(size) + 0.5) / size * 2 - 1) * 7000.0
        b2 = centres[None, :] ** 2 + centres[:, None] ** 2

        def chord(radius):
            return 2.0 * np.sqrt(np.maximum(radius * radius - b2, 0.0))

        tau = np.zeros_like(b2)
        for i in range(len(radii) - 1):
            mean = 0.5 * (layer_value[model.DEPTHS_KM[i]] + layer_value[model.DEPTHS_KM[i + 1]])
            extinction = -math.log(1.0 - alpha(mean, xs, ys)) / 1000.0
            tau += extinction * (chord(radii[i]) - chord(radii[i + 1]))
        expected = 1.0 - np.exp(-tau)
        self.assertGreater(expected.max(), 0.5)
        self.assertLessEqual(np.abs(image - expected).max(), 1.0 / 255 + 1e-9)

    def test_fill_values_are_empty_cells(self):
        def missing(depth, latitude, longitude):
            return (latitude >= 40) & (depth <= 410)

        full, holed = Path.new("full"), Path.new("holed")
        model.write_model(full, step=10.0)
        model.write_model(holed, step=10.0, missing=missing)
        _, grid, errors = read(holed)
        self.assertEqual(errors, [])
        depth, latitude, east = nodes(grid)
        np.testing.assert_array_equal(np.isnan(values(grid)), missing(depth, latitude, east))
        looking_north = (0.2, 0.1, 1.0)
        a = render(read(full)[1], direction=looking_north, interpolate=False,
                   opacity_points=((-4.0, 0.6), (0.0, 0.3), (2.5, 0.6)))
        b = render(grid, direction=looking_north, interpolate=False,
                   opacity_points=((-4.0, 0.6), (0.0, 0.3), (2.5, 0.6)))
        self.assertTrue(np.all(np.isfinite(b)))
        self.assertTrue(np.all(b <= a + 1.0 / 255 + 1e-9), "a hole never adds opacity")
        self.assertGreater(np.count_nonzero(a - b > 0.02), 50, "the hole shows")


class Pieces(unittest.TestCase):
    def test_sub_extents_are_slices_of_the_whole(self):
        path = Path.new("pieces")
        model.write_model(path, step=10.0, order=("latitude", "depth", "longitude"),
                          latitude_descending=True)
        _, whole, _ = read(path)
        nx, ny, nz = whole.GetDimensions()
        whole_values = values(whole).reshape(nz, ny, nx)
        for extent in ((0, nx - 1, 0, ny - 1, 10, 20), (3, 9, 2, 15, 30, nz - 1)):
            reader = sightline.vtkSightlineNetCDFSphericalReader()
            reader.SetFileName(path)
            reader.UpdateExtent(extent)
            piece = reader.GetOutput()
            self.assertEqual(list(piece.GetExtent()), list(extent))
            i0, i1, j0, j1, k0, k1 = extent
            np.testing.assert_array_equal(
                values(piece).reshape(k1 - k0 + 1, j1 - j0 + 1, i1 - i0 + 1),
                whole_values[k0:k1 + 1, j0:j1 + 1, i0:i1 + 1])
            np.testing.assert_array_equal(vtk_to_numpy(piece.GetZCoordinates()),
                                          vtk_to_numpy(whole.GetZCoordinates())[k0:k1 + 1])


def write_raw(path, axes, dims=("depth", "latitude", "longitude"), variable="dvs"):
    """A file from explicit coordinate variables: axes = {name: (values, attributes)}."""
    import netCDF4

    data = netCDF4.Dataset(path, "w")
    for name, (coordinate, attributes) in axes.items():
        data.createDimension(name, len(coordinate))
        var = data.createVariable(name, "f8", (name,))
        for key, value in attributes.items():
            setattr(var, key, value)
        var[:] = coordinate
    if variable:
        var = data.createVariable(variable, "f4", dims)
        var[:] = np.zeros([len(axes[d][0]) for d in dims], np.float32)
    data.close()
    return path


DEPTH = ([0.0, 100.0, 200.0], {"units": "km", "positive": "down"})
LATITUDE = ([-10.0, 0.0, 10.0], {"units": "degrees_north"})
LONGITUDE = ([0.0, 10.0, 20.0], {"units": "degrees_east"})


class BadFiles(unittest.TestCase):
    def expect(self, path, words, **settings):
        _, grid, errors = read(path, **settings)
        self.assertTrue(errors, path)
        text = " ".join(errors)
        for word in words:
            self.assertIn(word, text)
        self.assertEqual(grid.GetNumberOfPoints(), 0)

    def test_named_errors(self):
        cases = {
            "latitude_not_monotonic": (dict(latitude=([-10.0, 10.0, 0.0], LATITUDE[1])),
                                       ["'latitude'", "not strictly monotonic"]),
            "depth_without_units": (dict(depth=(DEPTH[0], {"positive": "down"})),
                                    ["'depth'", "no units attribute"]),
            "depth_in_furlongs": (dict(depth=(DEPTH[0], {"units": "furlong", "positive": "down"})),
                                  ["'furlong'", "not a length"]),
            "depth_beyond_radius": (dict(depth=([0.0, 3000.0, 7000.0], DEPTH[1])),
                                    ["7000", "beyond the reference radius 6371"]),
            "latitude_beyond_pole": (dict(latitude=([80.0, 90.0, 100.0], LATITUDE[1])),
                                     ["'latitude'", "beyond the pole"]),
            "longitude_twice_round": (dict(longitude=(list(np.arange(0.0, 721.0, 90.0)),
                                                      LONGITUDE[1])),
                                      ["more than once"]),
            "one_depth": (dict(depth=([100.0], DEPTH[1])), ["at least two"]),
            "nan_longitude": (dict(longitude=([0.0, float("nan"), 20.0], LONGITUDE[1])),
                              ["not finite"]),
        }
        for name, (change, words) in cases.items():
            with self.subTest(name):
                axes = {"depth": DEPTH, "latitude": LATITUDE, "longitude": LONGITUDE}
                axes.update(change)
                self.expect(write_raw(Path.new(name), axes), words)
        with self.subTest("vertical_of_unknown_kind"):  # km, axis Z, no 'positive', named z
            axes = {"z": (DEPTH[0], {"units": "km", "axis": "Z"}), "latitude": LATITUDE,
                    "longitude": LONGITUDE}
            path = write_raw(Path.new("unknown_kind"), axes, dims=("z", "latitude", "longitude"))
            self.expect(path, ["depth, a radius or an altitude", "VerticalCoordinate"])
            _, grid, errors = read(path, VerticalCoordinate=2)  # told: a radius
            self.assertEqual(errors, [])
            np.testing.assert_array_equal(vtk_to_numpy(grid.GetXCoordinates()), DEPTH[0])

    def test_no_model_and_wrong_variable(self):
        path = write_raw(Path.new("good"), {"depth": DEPTH, "latitude": LATITUDE,
                                            "longitude": LONGITUDE})
        self.expect(path, ["'vp'", "not in the file"], VariableName="vp")
        self.expect(path, ["'depth'", "does not lie on"], VariableName="depth")
        path = write_raw(Path.new("flat"), {"latitude": LATITUDE, "longitude": LONGITUDE},
                         dims=("latitude", "longitude"))
        self.expect(path, ["no variable lies on a longitude"])
        text = Path.new("text")
        with open(text, "w") as stream:
            stream.write("not netCDF at all\n")
        self.expect(text, ["netCDF cannot open it"])
        self.expect(Path.new("absent"), ["Cannot open", "missing or unreadable"])
        # A classic header whose first dimension name claims 4 GB (libnetcdf would allocate it).
        classic = Path.new("classic")
        model.write_model(classic, step=45.0, file_format="NETCDF3_CLASSIC")
        with open(classic, "rb") as stream:
            data = bytearray(stream.read())
        self.assertEqual(bytes(data[:4]), b"CDF\x01")
        data[16:20] = (0xFFFFFFF0).to_bytes(4, "big")  # after magic, numrecs, tag, count
        damaged = Path.new("damaged")
        with open(damaged, "wb") as stream:
            stream.write(bytes(data))
        self.expect(damaged, ["damaged netCDF header", "more than the file holds"])
        self.assertEqual(sightline.vtkSightlineNetCDFSphericalReader.CanReadFile(text), 0)
        self.assertEqual(sightline.vtkSightlineNetCDFSphericalReader.CanReadFile(path), 0)


class Hardening(unittest.TestCase):
    """Damaged classic files (cut short, bytes changed) end in an error or a consistent grid,
    never a crash; the in-memory path reads what the file path reads."""

    def read_bytes(self, data):
        reader = sightline.vtkSightlineNetCDFSphericalReader()
        reader.SetInputString(data)
        reader.ReadFromInputStringOn()
        errors = errors_of(reader)
        reader.Update()
        return reader.GetOutput(), errors

    def check(self, grid, errors):
        if grid.GetNumberOfPoints() == 0:
            return
        count = 1
        for axis in (grid.GetXCoordinates(), grid.GetYCoordinates(), grid.GetZCoordinates()):
            values = vtk_to_numpy(axis)
            self.assertTrue(np.all(np.isfinite(values)) and np.all(np.diff(values) > 0))
            count *= len(values)
        self.assertEqual(count, grid.GetNumberOfPoints())
        data = grid.GetPointData()
        for i in range(data.GetNumberOfArrays()):
            self.assertEqual(data.GetArray(i).GetNumberOfTuples(), count)

    def test_damaged_classic_files(self):
        path = Path.new("hardening")
        model.write_model(path, step=30.0, file_format="NETCDF3_CLASSIC")
        with open(path, "rb") as stream:
            data = stream.read()
        whole, errors = self.read_bytes(data)
        self.assertEqual(errors, [])
        np.testing.assert_array_equal(values(whole), values(read(path)[1]))
        cut_errors = 0
        for length in range(0, len(data), max(1, len(data) // 60)):
            grid, errors = self.read_bytes(data[:length])
            self.check(grid, errors)
            cut_errors += bool(errors)
        self.assertGreater(cut_errors, 50, "cut files are named errors")
        rng = np.random.default_rng(38)
        header = 1200  # most mutations in the header, where the structure is
        for _ in range(300):
            mutated = bytearray(data)
            for position in rng.integers(0, header, size=rng.integers(1, 4)):
                mutated[position] = int(rng.integers(0, 256))
            grid, errors = self.read_bytes(bytes(mutated))
            self.check(grid, errors)


class View(unittest.TestCase):
    def view(self, *arguments):
        command = os.environ.get("SIGHTLINE_VIEW")
        if not command:
            self.skipTest("SIGHTLINE_VIEW is not set")
        return subprocess.run([command, *arguments], capture_output=True, text=True,
                              timeout=240)

    def test_sightline_view_cuts_a_wedge(self):
        path = Path.new("view")
        model.write_model(path, step=5.0)
        images = {}
        for cut in ("none", "wedge"):
            output = Path.new("view_" + cut)[:-3] + ".png"
            extra = [] if cut == "none" else ["--cut", "wedge"]
            result = self.view(path, "--variable", "dvs", "--size", "160", "120",
                               "--view-longitude", "300", "--output", output, *extra)
            self.assertEqual(result.returncode, 0, result.stderr)
            reader = vtk.vtkPNGReader()
            reader.SetFileName(output)
            reader.Update()
            images[cut] = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
        self.assertGreater(np.abs(images["none"].astype(int) - images["wedge"]).max(), 60,
                           "the cut opens the globe")
        result = self.view(path, "--variable", "vp", "--output", Path.new("x")[:-3] + ".png")
        self.assertEqual(result.returncode, 2)
        self.assertIn("'vp' is not in the file", result.stderr)


class Graticule(unittest.TestCase):
    def lines(self, **settings):
        source = sightline.vtkSightlineGraticuleSource()
        for key, value in settings.items():
            getattr(source, "Set" + key)(*value) if isinstance(value, tuple) else \
                getattr(source, "Set" + key)(value)
        source.Update()
        out = source.GetOutput()
        points = vtk_to_numpy(out.GetPoints().GetData())
        lat = vtk_to_numpy(out.GetPointData().GetArray("Latitude"))
        lon = vtk_to_numpy(out.GetPointData().GetArray("Longitude"))
        return out, points, lat, lon

    def test_lines_lie_on_the_sphere_at_their_latitude_and_longitude(self):
        out, points, lat, lon = self.lines(Radius=6371.0, Step=30.0)
        self.assertEqual(out.GetNumberOfLines(), 5 + 12)  # parallels -60..60, 12 meridians
        np.testing.assert_allclose(np.linalg.norm(points, axis=1), 6371.0, rtol=1e-12)
        np.testing.assert_allclose(np.degrees(np.arcsin(points[:, 2] / 6371.0)), lat, atol=1e-9)
        away_from_poles = np.abs(lat) < 89.9
        east = np.degrees(np.arctan2(points[:, 1], points[:, 0]))
        offset = np.mod(east - lon + 180.0, 360.0) - 180.0
        np.testing.assert_allclose(offset[away_from_poles], 0.0, atol=1e-9)
        meridians = np.unique(np.round(lon[np.abs(np.mod(lat, 30.0)) > 1e-6], 9))
        np.testing.assert_allclose(meridians, np.arange(0.0, 360.0, 30.0))

    def test_regional_range_across_the_antimeridian(self):
        out, points, lat, lon = self.lines(Radius=1.0, Step=10.0, LatitudeRange=(-30.0, 30.0),
                                           LongitudeRange=(150.0, 210.0))
        self.assertEqual(out.GetNumberOfLines(), 7 + 7)
        self.assertTrue(np.all((lat >= -30 - 1e-9) & (lat <= 30 + 1e-9)))
        self.assertTrue(np.all((lon >= 150 - 1e-9) & (lon <= 210 + 1e-9)))

    def test_facing_keeps_the_near_hemisphere(self):
        facing = np.array([0.3, -0.8, 0.5])
        whole, _, _, _ = self.lines(Radius=2.0, Step=15.0)
        near, points, _, _ = self.lines(Radius=2.0, Step=15.0, FacingDirection=tuple(facing))
        self.assertTrue(np.all(points @ facing > 0))
        self.assertGreater(near.GetNumberOfLines(), 0)
        self.assertLess(near.GetNumberOfPoints(), 0.6 * whole.GetNumberOfPoints())
        self.assertGreater(near.GetNumberOfPoints(), 0.4 * whole.GetNumberOfPoints())


class CutAway(unittest.TestCase):
    def test_wedge_keeps_whole_cells_round_the_seam(self):
        path = Path.new("cut")
        model.write_model(path, step=10.0)
        grid = read(path)[1]
        for centre, width in ((0.0, 90.0), (300.0, 180.0)):
            cut = earth.cut_away(grid, centre, width)
            phi = np.degrees(vtk_to_numpy(cut.GetZCoordinates()))
            self.assertTrue(np.all(np.diff(phi) > 0))
            # Every node kept lies outside the wedge, and all nodes outside it are kept.
            offset = np.mod(phi - centre + 180.0, 360.0) - 180.0
            self.assertTrue(np.all(np.abs(offset) >= width / 2 - 1e-9))
            outside = np.abs(np.mod(np.arange(0, 360, 10.0) - centre + 180, 360) - 180)
            self.assertEqual(len(phi), np.count_nonzero(outside >= width / 2 - 1e-9))
            depth, latitude, east = nodes(cut)
            np.testing.assert_array_equal(values(cut, "dvs"),
                                          model.dvs(depth, latitude, east).astype(np.float32))


if __name__ == "__main__":
    unittest.main()
