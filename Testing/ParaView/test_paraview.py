# SPDX-License-Identifier: BSD-3-Clause
"""The ParaView plugin under pvbatch: readers through File > Open's reader factory, every
Sightline representation on real data, property changes, and each ParaView image against the
VTK-level mapper drawing the same data with the same camera and lights.

Run by ctest as `pvbatch --force-offscreen-rendering test_paraview.py` (label paraview) with
SIGHTLINE_PLUGIN (the plugin's .so), SIGHTLINE_SH_DATA_DIR (the SHData fixture) and
SIGHTLINE_TEST_TEMP_DIR set; PYTHONPATH holds ParaView's Python and the 'sightline' package
built against ParaView's VTK, so the reference mappers run in the same process.
"""
import os
import sys
import tempfile
import unittest
import zipfile

import numpy as np
from paraview import servermanager
from paraview.simple import (Calculator, ClearSelection, ColorBy, Delete, GetColorTransferFunction,
                             GetOpacityTransferFunction, GroupDatasets, LoadPlugin, OpenDataFile,
                             PVTrivialProducer, Render, SelectSurfaceCells, SelectSurfacePoints,
                             SetActiveSource, Show, Threshold, Transform)
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import (vtkIdList, vtkOutputWindow, vtkStringOutputWindow,
                                      vtkUnsignedCharArray)
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkActor, vtkRenderer, vtkRenderWindow, vtkVolume, vtkWindowToImageFilter
from vtkmodules.vtkRenderingCore import vtkVolumeProperty
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

PLUGIN = os.environ.get("SIGHTLINE_PLUGIN", "")
SH_DATA = os.environ.get("SIGHTLINE_SH_DATA_DIR", "")
TEMP = os.environ.get("SIGHTLINE_TEST_TEMP_DIR", tempfile.gettempdir())
SWC_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data", "SWC")
BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"
SIZE = (400, 300)
BASELINES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Data", "Baseline", "ParaView")
# Against the stored baseline, at most this fraction of pixels may differ by more than 24/255
# (Mesa's rasterisation of ParaView's own props and the ray tracer's float rounding vary a
# little between machines; the ray-traced primitives themselves are deterministic).
BASELINE_TOLERANCE = 0.005

LoadPlugin(PLUGIN, ns=globals())
import sightline  # noqa: E402  (after ParaView's vtkmodules are on the path)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paraview_test_support as support  # noqa: E402


def view_image(view):
    """The view's last frame as an (h, w, 3) uint8 array."""
    grab = vtkWindowToImageFilter()
    grab.SetInput(view.GetRenderWindow())
    grab.ReadFrontBufferOff()
    grab.Update()
    image = grab.GetOutput()
    w, h, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].copy()


def make_view():
    view = support.make_view(SIZE)
    view.EnableRenderOnInteraction = 0
    return view


def reference_image(view, prop):
    """`prop` (an actor or volume with a Sightline mapper) drawn by plain VTK with the view's
    camera, lights and background: what the VTK-level mapper draws for the same data."""
    pv_renderer = view.GetRenderer()
    renderer = vtkRenderer()
    renderer.SetBackground(pv_renderer.GetBackground())
    renderer.GetActiveCamera().DeepCopy(pv_renderer.GetActiveCamera())
    renderer.AutomaticLightCreationOff()
    lights = pv_renderer.GetLights()
    lights.InitTraversal()
    for _ in range(lights.GetNumberOfItems()):
        light = lights.GetNextItem()
        copy = type(light)()
        copy.DeepCopy(light)
        renderer.AddLight(copy)
    renderer.AddViewProp(prop)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*SIZE)
    window.AddRenderer(renderer)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    grab.Update()
    image = grab.GetOutput()
    w, h, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3].copy()
    del window  # (Finalize here made Mesa report GLXBadContext at exit)
    return pixels


def save_png(pixels, name, folder=TEMP):
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData
    h, w, _ = pixels.shape
    image = vtkImageData()
    image.SetDimensions(w, h, 1)
    image.GetPointData().SetScalars(numpy_to_vtk(pixels.reshape(-1, 3).copy()))
    writer = vtkPNGWriter()
    writer.SetFileName(os.path.join(folder, name))
    writer.SetInputData(image)
    writer.Write()


def differing_fraction(a, b, tolerance=24):
    """Fraction of pixels whose largest channel difference exceeds `tolerance` (of 255)."""
    return float(np.mean(np.abs(a.astype(int) - b.astype(int)).max(axis=2) > tolerance))


def covered_fraction(pixels, background):
    back = np.round(np.array(background) * 255).astype(int)
    return float(np.mean(np.abs(pixels.astype(int) - back).max(axis=2) > 8))


def display_point(view, point):
    renderer = view.GetRenderer()
    renderer.SetWorldPoint(point[0], point[1], point[2], 1.0)
    renderer.WorldToDisplay()
    x, y, _ = renderer.GetDisplayPoint()
    return int(round(x)), int(round(y))


def click(view, source, pixel, cells=False):
    """ParaView's one-pixel surface selection at `pixel`: the selected ids (process, id pairs
    flattened), or [] when nothing was hit."""
    SetActiveSource(source)
    rectangle = [pixel[0], pixel[1], pixel[0], pixel[1]]
    (SelectSurfaceCells if cells else SelectSurfacePoints)(Rectangle=rectangle, View=view)
    selection = source.GetSelectionInput(source.Port)
    ids = []
    if selection is not None:
        for part in selection.Input:
            ids += list(part.IDs)[1::2]
    ClearSelection(source)
    return ids


class ParaViewPluginTest(unittest.TestCase):
    maxDiff = None

    def compare_with_vtk(self, view, source, representation, prop, name, tolerance=0.001,
                         colour_tolerance=24):
        """Renders the view, saves both images and asserts that at most `tolerance` of the
        pixels differ from the VTK-level mapper's image by more than `colour_tolerance`/255."""
        Render(view)
        pv_pixels = view_image(view)
        ref_pixels = reference_image(view, prop)
        save_png(pv_pixels, f"ParaView{name}.png")
        save_png(ref_pixels, f"ParaView{name}Reference.png")
        coverage = covered_fraction(pv_pixels, view.Background)
        self.assertGreater(coverage, 0.02, f"{name}: the representation drew (almost) nothing")
        fraction = differing_fraction(pv_pixels, ref_pixels, colour_tolerance)
        print(f"{name}: {coverage:.1%} of pixels covered, {fraction:.3%} differ from the VTK mapper "
              f"by more than {colour_tolerance}/255")
        self.assertLessEqual(fraction, tolerance, name)
        # And against the stored baseline (SIGHTLINE_UPDATE_BASELINES=1 rewrites it).
        baseline = os.path.join(BASELINES, f"{name}.png")
        if os.environ.get("SIGHTLINE_UPDATE_BASELINES") == "1":
            save_png(pv_pixels, f"{name}.png", BASELINES)
        self.assertTrue(os.path.exists(baseline), f"no baseline {baseline}")
        stored = support.read_png(baseline)
        self.assertEqual(stored.shape, pv_pixels.shape, name)
        drift = differing_fraction(pv_pixels, stored)
        print(f"{name}: {drift:.3%} differ from the baseline")
        self.assertLessEqual(drift, BASELINE_TOLERANCE, f"{name} against {baseline}")
        return pv_pixels

    def test_readers_are_registered_for_their_extensions(self):
        with tempfile.TemporaryDirectory() as folder:
            with zipfile.ZipFile(BUNDLES) as archive:
                archive.extract("sub_1/AF_L.trk", folder)
            # A .trx converted from DIPY's bundle by our writer, with a group of every other
            # streamline: File > Open must pick our reader and show the group as a cell array.
            trk = sightline.vtkSightlineTrackVisReader()
            trk.SetFileName(os.path.join(folder, "sub_1", "AF_L.trk"))
            trk.Update()
            tracks = trk.GetOutput()
            group = vtkUnsignedCharArray()
            group.SetName("group:even")
            for cell in range(tracks.GetNumberOfCells()):
                group.InsertNextValue(1 - cell % 2)
            tracks.GetCellData().AddArray(group)
            trx = os.path.join(folder, "AF_L.trx")
            writer = sightline.vtkSightlineTRXWriter()
            writer.SetInputData(tracks)
            writer.SetFileName(trx)
            writer.Write()
            files = {
                trx: "SightlineTRXReader",
                os.path.join(folder, "sub_1", "AF_L.trk"): "SightlineTrackVisReader",
                os.path.join(SWC_DIR, "neuron_three_point_soma.swc"): "SightlineSWCReader",
                os.path.join(SH_DATA, "small_64D_sh_tournier07.mif"): "SightlineMIFReader",
                os.path.join(SH_DATA, "small_64D_sh_tournier07.mif.gz"): "SightlineMIFReader",
                "/usr/lib/python3/dist-packages/nibabel/tests/data/standard.tck": "SightlineTCKReader",
            }
            for path, reader_name in files.items():
                reader = OpenDataFile(path)
                self.assertIsNotNone(reader, path)
                self.assertEqual(reader.GetXMLName(), reader_name, path)
                reader.UpdatePipeline()
                info = reader.GetDataInformation()
                self.assertGreater(info.GetNumberOfPoints(), 0, path)
                if path == trx:
                    self.assertEqual(info.GetNumberOfPoints(), tracks.GetNumberOfPoints())
                    self.assertEqual(info.GetNumberOfCells(), tracks.GetNumberOfCells())
                    self.assertIsNotNone(reader.CellData["group:even"])
                Delete(reader)

    def test_tubes_from_trk_coloured_through_the_lut(self):
        with tempfile.TemporaryDirectory() as folder:
            with zipfile.ZipFile(BUNDLES) as archive:
                archive.extract("sub_1/CST_R.trk", folder)
            reader = OpenDataFile(os.path.join(folder, "sub_1", "CST_R.trk"))
            height = Calculator(Input=reader, ResultArrayName="height", Function="coordsZ")
            view = make_view()
            rep = Show(height, view)
            rep.Representation = "Sightline Tubes"
            rep.TubeRadius = 0.6
            ColorBy(rep, ("POINTS", "height"))
            lut = GetColorTransferFunction("height")
            lut.ApplyPreset("Viridis (matplotlib)", True)
            rep.RescaleTransferFunctionToDataRange(True)
            view.ResetCamera()
            Render(view)
            # The same polylines, radius and lookup table through the VTK-level mapper.
            mapper = sightline.vtkSightlineTubeMapper()
            mapper.SetInputDataObject(height.GetClientSideObject().GetOutputDataObject(0))
            mapper.SetRadius(0.6)
            mapper.SetVaryRadius(0)
            mapper.SelectColorArray("height")
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SetLookupTable(lut.GetClientSideObject())
            mapper.SetUseLookupTableScalarRange(1)
            actor = vtkActor()
            actor.SetMapper(mapper)
            actor.GetProperty().DeepCopy(rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetProperty())
            pixels = self.compare_with_vtk(view, height, rep, actor, "TubesTrk")
            # Coloured, not white: ParaView turns InterpolateScalarsBeforeMapping on.
            covered = np.abs(pixels.astype(int) - np.round(np.array(view.Background) * 255)).max(axis=2) > 8
            self.assertGreater(np.std(pixels[covered].astype(float), axis=0).max(), 10)
            # A radius change reaches the mapper.
            rep.TubeRadius = 1.2
            Render(view)
            self.assertGreater(covered_fraction(view_image(view), view.Background),
                               covered.mean() * 1.2)
            # Opacity below 1 goes through the exact translucent union.
            rep.Opacity = 0.4
            rep.TubeRadius = 0.6
            sub = rep.GetClientSideObject().GetActiveRepresentation()
            self.assertTrue(sub.GetSightlineMapper().IsTranslucentFor(sub.GetActor()))
            actor.GetProperty().SetOpacity(0.4)
            # Closely: layers that lost the background behind them (ParaView's depth peeling left
            # GL_MAX blending on) were 7-19/255 off.
            self.compare_with_vtk(view, height, rep, actor, "TubesTrkTranslucent", colour_tolerance=3)
            Delete(view)

    @staticmethod
    def show_mif_sh_glyphs():
        """small_64D's MRtrix3 file as Sightline SH glyphs in a new view, coloured by lobe
        direction: (reader, view, representation)."""
        reader = OpenDataFile(os.path.join(SH_DATA, "small_64D_sh_tournier07.mif"))
        view = make_view()
        rep = Show(reader, view)
        rep.Representation = "Sightline SH Glyphs"
        ColorBy(rep, None)  # no array: the glyphs' own colouring (by lobe direction)
        rep.SHCoefficients = ["POINTS", "SHCoefficients"]
        rep.SHBasis = "tournier07 (MRtrix3)"
        rep.SHLegacyBasis = 0
        return reader, view, rep

    def test_sh_glyphs_from_mif(self):
        reader, view, rep = self.show_mif_sh_glyphs()
        rep.GlyphSliceOrientation = "Axial"
        rep.GlyphSlice = -1
        view.CameraPosition = [0, 0, 1]
        view.CameraFocalPoint = [0, 0, 0]
        view.CameraViewUp = [0, 1, 0]
        view.ResetCamera()
        Render(view)
        mapper = sightline.vtkSightlineSHGlyphMapper()
        mapper.SetInputDataObject(reader.GetClientSideObject().GetOutputDataObject(0))
        mapper.SetCoefficientArrayName("SHCoefficients")
        mapper.SetBasisToMRtrix3()
        mapper.SetSliceOrientationToAxial()
        mapper.SetSliceNumber(-1)
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().DeepCopy(rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetProperty())
        self.compare_with_vtk(view, reader, rep, actor, "SHGlyphsMif")
        Delete(view)

    def test_sh_glyph_volume_with_frustum_culling(self):
        """The whole MIF volume with FrustumCulling in a close-up: the same picture as the plain
        VTK mapper without culling, and glyphs outside the view keep loose boxes."""
        reader, view, rep = self.show_mif_sh_glyphs()
        rep.GlyphSliceOrientation = "Extent"
        rep.GlyphFrustumCulling = 1
        data = reader.GetClientSideObject().GetOutputDataObject(0)
        bounds = data.GetBounds()
        centre = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
        view.CameraFocalPoint = centre
        view.CameraPosition = [centre[0] + 6.0, centre[1] - 8.0, centre[2] + 7.0]
        view.CameraViewUp = [0, 0, 1]
        view.CameraParallelProjection = 0
        Render(view)
        culled = rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetMapper()
        loose = culled.GetLastLooseBoxes()
        self.assertGreater(loose, 0, "the close-up sees every glyph: no culling to test")
        self.assertGreater(culled.GetLastComputedBoxes(), 0)
        mapper = sightline.vtkSightlineSHGlyphMapper()
        mapper.SetInputDataObject(data)
        mapper.SetCoefficientArrayName("SHCoefficients")
        mapper.SetBasisToMRtrix3()
        mapper.SetSliceOrientationToExtent()
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().DeepCopy(rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetProperty())
        pv_pixels = view_image(view)
        ref_pixels = reference_image(view, actor)
        save_png(pv_pixels, "ParaViewSHGlyphVolumeCulled.png")
        save_png(ref_pixels, "ParaViewSHGlyphVolumeCulledReference.png")
        self.assertGreater(covered_fraction(pv_pixels, view.Background), 0.05)
        self.assertLessEqual(differing_fraction(pv_pixels, ref_pixels), 0.001)
        self.assertEqual(mapper.GetLastLooseBoxes(), 0)
        Delete(view)

    def test_spheres_and_tubes_from_swc(self):
        reader = OpenDataFile(os.path.join(SWC_DIR, "neuron_three_point_soma.swc"))
        view = make_view()
        rep = Show(reader, view)
        rep.Representation = "Sightline Spheres"
        ColorBy(rep, None)  # Solid Color (ParaView colours by the active scalars by default)
        rep.SphereRadiusArray = ["POINTS", "Radius"]
        view.ResetCamera()
        Render(view)
        mapper = sightline.vtkSightlineSphereMapper()
        mapper.SetInputDataObject(reader.GetClientSideObject().GetOutputDataObject(0))
        mapper.SetRadiusArrayName("Radius")
        mapper.ScalarVisibilityOff()  # ParaView's default: Solid Color
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().DeepCopy(rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetProperty())
        self.compare_with_vtk(view, reader, rep, actor, "SpheresSwc")

        rep.Representation = "Sightline Tubes"
        rep.TubeRadiusArray = ["POINTS", "Radius"]
        rep.TubePredecessorArray = ["POINTS", "ParentIndex"]
        Render(view)
        tubes = sightline.vtkSightlineTubeMapper()
        tubes.SetInputDataObject(reader.GetClientSideObject().GetOutputDataObject(0))
        tubes.SetRadiusArrayName("Radius")
        tubes.SetPredecessorArrayName("ParentIndex")
        tubes.ScalarVisibilityOff()
        actor = vtkActor()
        actor.SetMapper(tubes)
        actor.GetProperty().DeepCopy(rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetProperty())
        self.compare_with_vtk(view, reader, rep, actor, "TubesSwc")
        Delete(view)

    def test_tensor_glyphs_from_numpy_tensors(self):
        # A 4x4x1 image of random symmetric positive-definite tensors (VTK's 9-component
        # layout), handed to ParaView through a trivial producer as a user's Python source would.
        rng = np.random.default_rng(7)
        tensors = []
        for _ in range(16):
            a = rng.normal(size=(3, 3))
            tensors.append((a @ a.T + 0.3 * np.eye(3)).ravel())
        image = vtkImageData()
        image.SetDimensions(4, 4, 1)
        image.SetSpacing(3.0, 3.0, 3.0)
        array = numpy_to_vtk(np.asarray(tensors), deep=1)
        array.SetName("tensors")
        image.GetPointData().AddArray(array)
        producer = PVTrivialProducer()
        producer.GetClientSideObject().SetOutput(image)
        view = make_view()
        rep = Show(producer, view)
        rep.Representation = "Sightline Tensor Glyphs"
        ColorBy(rep, None)
        rep.TensorArray = ["POINTS", "tensors"]
        rep.TensorShape = "Ellipsoid"
        rep.GlyphScale = 1.2
        view.CameraPosition = [4.5, 4.5, 30]
        view.CameraFocalPoint = [4.5, 4.5, 0]
        view.CameraViewUp = [0, 1, 0]
        view.ResetCamera()
        Render(view)
        mapper = sightline.vtkSightlineTensorGlyphMapper()
        mapper.SetInputDataObject(image)
        mapper.SetTensorArrayName("tensors")
        mapper.SetShapeToEllipsoid()
        mapper.SetScaleFactor(1.2)
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().DeepCopy(rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetProperty())
        self.compare_with_vtk(view, producer, rep, actor, "TensorGlyphs")
        Delete(view)

    def test_multiblock_and_empty_inputs(self):
        # Two SWC neurons grouped into a multiblock, as ParaView's Group Datasets makes them,
        # draw like the two neurons as one data set; an empty input draws nothing, quietly.
        first = OpenDataFile(os.path.join(SWC_DIR, "neuron_three_point_soma.swc"))
        moved = Transform(Input=first)
        moved.Transform.Translate = [30.0, 0.0, 0.0]
        group = GroupDatasets(Input=[first, moved])
        view = make_view()
        rep = Show(group, view)
        rep.Representation = "Sightline Spheres"
        ColorBy(rep, None)
        rep.SphereRadiusArray = ["POINTS", "Radius"]
        view.ResetCamera()
        Render(view)
        from vtkmodules.vtkFiltersCore import vtkAppendPolyData
        append = vtkAppendPolyData()
        append.AddInputData(first.GetClientSideObject().GetOutputDataObject(0))
        append.AddInputData(moved.GetClientSideObject().GetOutputDataObject(0))
        append.Update()
        mapper = sightline.vtkSightlineSphereMapper()
        mapper.SetInputDataObject(append.GetOutput())
        mapper.SetRadiusArrayName("Radius")
        mapper.ScalarVisibilityOff()
        actor = vtkActor()
        actor.SetMapper(mapper)
        actor.GetProperty().DeepCopy(rep.GetClientSideObject().GetActiveRepresentation().GetActor().GetProperty())
        self.compare_with_vtk(view, group, rep, actor, "SpheresMultiblock")

        messages = vtkStringOutputWindow()
        previous = vtkOutputWindow.GetInstance()
        vtkOutputWindow.SetInstance(messages)
        try:
            nothing = Threshold(Input=first, Scalars=["POINTS", "Radius"])
            nothing.LowerThreshold = 1e9
            nothing.UpperThreshold = 2e9
            empty_view = make_view()
            empty = Show(nothing, empty_view)
            empty.Representation = "Sightline Spheres"
            Render(empty_view)
            self.assertEqual(covered_fraction(view_image(empty_view), empty_view.Background), 0.0)
        finally:
            vtkOutputWindow.SetInstance(previous)
        self.assertNotIn("ERROR", messages.GetOutput())
        self.assertNotIn("Warning", messages.GetOutput())
        Delete(empty_view)
        Delete(view)

    def test_selection_names_the_clicked_primitive(self):
        # Clicking a sphere's centre selects its point; clicking the middle of a tube link
        # selects its polyline; clicking an SH glyph's centre selects its voxel.
        reader = OpenDataFile(os.path.join(SWC_DIR, "neuron_three_point_soma.swc"))
        view = make_view()
        rep = Show(reader, view)
        rep.Representation = "Sightline Spheres"
        rep.SphereRadiusArray = ["POINTS", "Radius"]
        view.ResetCamera()
        Render(view)
        neuron = reader.GetClientSideObject().GetOutputDataObject(0)
        for i in range(neuron.GetNumberOfPoints()):
            self.assertEqual(click(view, reader, display_point(view, neuron.GetPoint(i))), [i],
                             f"sphere {i}")
        self.assertEqual(click(view, reader, (2, 2)), [], "the background selects nothing")

        rep.Representation = "Sightline Tubes"
        rep.TubeRadiusArray = ["POINTS", "Radius"]
        Render(view)
        lines = neuron.GetLines()
        self.assertGreater(lines.GetNumberOfCells(), 1)
        first_cell = neuron.GetNumberOfVerts()  # cell ids count vertex cells first
        for c in range(lines.GetNumberOfCells()):
            # The polyline's last link: its first links may lie inside the soma.
            ids = vtkIdList()
            lines.GetCellAtId(c, ids)
            n = ids.GetNumberOfIds()
            a, b = neuron.GetPoint(ids.GetId(n - 2)), neuron.GetPoint(ids.GetId(n - 1))
            middle = [(a[k] + b[k]) / 2 for k in range(3)]
            self.assertEqual(click(view, reader, display_point(view, middle), cells=True),
                             [first_cell + c], f"last link of polyline {c}")
        Delete(view)

        sh = OpenDataFile(os.path.join(SH_DATA, "small_64D_sh_tournier07.mif"))
        view = make_view()
        glyphs = Show(sh, view)
        glyphs.Representation = "Sightline SH Glyphs"
        glyphs.SHBasis = "tournier07 (MRtrix3)"
        glyphs.SHLegacyBasis = 0
        glyphs.GlyphSlice = 5
        view.CameraPosition = [9, 9, 60]
        view.CameraFocalPoint = [9, 9, 10]
        view.CameraViewUp = [0, 1, 0]
        view.ResetCamera()
        Render(view)
        image = sh.GetClientSideObject().GetOutputDataObject(0)
        right = 0
        voxels = [(i, j) for i in range(2, 9, 2) for j in range(2, 9, 2)]
        for i, j in voxels:
            point = image.ComputePointId([i, j, 5])
            picked = click(view, sh, display_point(view, image.GetPoint(point)))
            self.assertIn(picked, ([], [point]), f"voxel {i}, {j}")  # never another voxel
            right += picked == [point]
        self.assertGreaterEqual(right, len(voxels) * 3 // 4)
        Delete(view)

    def test_prem_as_a_spherical_volume(self):
        view = make_view()
        source, rep = support.show_prem(view, SightlineSphericalField)  # noqa: F821  (LoadPlugin)
        lut = GetColorTransferFunction("density")
        opacity = GetOpacityTransferFunction("density")
        view.CameraPosition = [3, -2, 2]
        view.CameraFocalPoint = [0, 0, 0]
        view.CameraViewUp = [0, 0, 1]
        view.ResetCamera()
        Render(view)
        mapper = sightline.vtkSightlineSphericalVolumeMapper()
        mapper.SetInputDataObject(source.GetClientSideObject().GetOutputDataObject(0))
        mapper.SetScalarModeToUseCellFieldData()
        mapper.SelectScalarArray("density")
        prop = vtkVolumeProperty()
        prop.SetColor(lut.GetClientSideObject())
        prop.SetScalarOpacity(opacity.GetClientSideObject())
        prop.SetScalarOpacityUnitDistance(0.05)
        volume = vtkVolume()
        volume.SetMapper(mapper)
        volume.SetProperty(prop)
        self.compare_with_vtk(view, source, rep, volume, "PREMVolume")
        Delete(view)

    def test_netcdf_earth_model_as_a_spherical_volume(self):
        # An EMC-shaped CF model (written by the example the README shows), opened through our
        # reader (one of File > Open's readers for .nc, beside ParaView's own) and drawn as a
        # Sightline Spherical Volume in a diverging map: the same pixels as the VTK mapper.
        sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                        "Examples", "Python"))
        import write_earth_model

        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "model.nc")
            write_earth_model.write_model(path, step=10.0)
            # (GetPossibleReaders would import every Python reader ParaView has, some broken on
            # Debian 12's Python: the hint File > Open reads is checked instead.)
            prototype = servermanager.ActiveConnection.Session.GetSessionProxyManager() \
                .GetPrototypeProxy("sources", "SightlineNetCDFSphericalReader")
            hint = prototype.GetHints().FindNestedElementByName("ReaderFactory")
            self.assertIn("nc", hint.GetAttribute("extensions").split())
            reader = SightlineNetCDFEarthModelReader(FileName=path)  # noqa: F821  (LoadPlugin)
            reader.VariableName = "dvs"
            view = make_view()
            rep = Show(reader, view)
            rep.Representation = "Sightline Spherical Volume"
            ColorBy(rep, ("POINTS", "dvs"))
            lut = GetColorTransferFunction("dvs")
            lut.ApplyPreset("Cool to Warm", True)
            lut.RescaleTransferFunction(-3.5, 3.5)
            opacity = GetOpacityTransferFunction("dvs")
            opacity.Points = [-3.5, 0.8, 0.5, 0.0, 0.0, 0.0, 0.5, 0.0, 3.5, 0.8, 0.5, 0.0]
            rep.ScalarOpacityUnitDistance = 400.0
            view.CameraPosition = [-2.0e4, -3.0e4, 1.2e4]
            view.CameraFocalPoint = [0, 0, 0]
            view.CameraViewUp = [0, 0, 1]
            view.ResetCamera()
            Render(view)
            grid = reader.GetClientSideObject().GetOutputDataObject(0)
            self.assertEqual(grid.GetDimensions(), (17, 19, 37))
            mapper = sightline.vtkSightlineSphericalVolumeMapper()
            mapper.SetInputDataObject(grid)
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectScalarArray("dvs")
            prop = vtkVolumeProperty()
            prop.SetColor(lut.GetClientSideObject())
            prop.SetScalarOpacity(opacity.GetClientSideObject())
            prop.SetScalarOpacityUnitDistance(400.0)
            volume = vtkVolume()
            volume.SetMapper(mapper)
            volume.SetProperty(prop)
            before = covered_fraction(
                self.compare_with_vtk(view, reader, rep, volume, "NetCDFModelVolume"),
                view.Background)
            # The graticule over it: 5 parallels and 12 meridians, drawn as Sightline Tubes.
            graticule = SightlineGraticule(Radius=6400.0)  # noqa: F821  (LoadPlugin)
            graticule.UpdatePipeline()
            self.assertEqual(graticule.GetDataInformation().GetNumberOfCells(), 17)
            lines = Show(graticule, view)
            lines.Representation = "Sightline Tubes"
            lines.TubeRadius = 15.0
            Render(view)
            pixels = view_image(view)
            save_png(pixels, "ParaViewNetCDFModelGraticule.png")
            self.assertGreater(covered_fraction(pixels, view.Background), before + 0.005)
            Delete(view)
            Delete(graticule)
            Delete(reader)


if __name__ == "__main__":
    result = unittest.main(argv=[sys.argv[0], "-v"], exit=False).result
    sys.exit(0 if result.wasSuccessful() else 1)
