# SPDX-License-Identifier: BSD-3-Clause
"""vtkSightlineTubeMapper.StreamedPieces: a tractogram pulled from its reader piece by piece,
each piece turned into chunked tubes and released, draws the image the whole tractogram draws
(the scaled-down form of streaming a 10^9-link tractogram). Real data: DIPY's bundles as .trk,
and converted by our writer to .trx and by nibabel to .tck, each read by its own reader. Picks
name the cells and points of the whole input; the reader's output is released; what a piece
cannot give (another layout, predecessor indices, radii scaled by the whole range) is a named
error."""
import os
import tempfile
import unittest
import zipfile

import numpy as np
import vtk
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand

import sightline

BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"
SIZE = (200, 160)


def errors_of(algorithm):
    found = []

    @calldata_type(VTK_STRING)
    def on_error(caller, event, message):
        found.append(message)

    algorithm.AddObserver(vtkCommand.ErrorEvent, on_error)
    return found


def tractogram_files(folder):
    """DIPY's three bundles of subject 1 as one .trk (nibabel), .trx (our writer, with a
    per-point array "height") and .tck (nibabel)."""
    import nibabel as nib
    with zipfile.ZipFile(BUNDLES) as archive:
        archive.extractall(folder)
    first = None
    streamlines = []
    for bundle in ("AF_L", "CST_R", "CC_ForcepsMajor"):
        loaded = nib.streamlines.load(os.path.join(folder, "sub_1", f"{bundle}.trk"))
        first = first or loaded
        streamlines.extend(loaded.streamlines)
    tractogram = nib.streamlines.Tractogram(streamlines, affine_to_rasmm=np.eye(4))
    trk = os.path.join(folder, "bundles.trk")
    nib.streamlines.save(nib.streamlines.TrkFile(tractogram, header=first.header), trk)
    tck = os.path.join(folder, "bundles.tck")
    nib.streamlines.save(nib.streamlines.TckFile(tractogram), tck)
    reader = sightline.vtkSightlineTrackVisReader()
    reader.SetFileName(trk)
    reader.Update()
    data = vtk.vtkPolyData()
    data.DeepCopy(reader.GetOutput())
    height = numpy_to_vtk(vtk_to_numpy(data.GetPoints().GetData())[:, 2].astype(np.float32), deep=1)
    height.SetName("height")
    data.GetPointData().AddArray(height)
    trx = os.path.join(folder, "bundles.trx")
    writer = sightline.vtkSightlineTRXWriter()
    writer.SetInputData(data)
    writer.SetFileName(trx)
    writer.Write()
    return {"trk": trk, "trx": trx, "tck": tck}, len(streamlines)


def reader_for(path):
    reader = {".trk": sightline.vtkSightlineTrackVisReader, ".tck": sightline.vtkSightlineTCKReader,
              ".trx": sightline.vtkSightlineTRXReader}[os.path.splitext(path)[1]]()
    reader.SetFileName(path)
    return reader


def render(mapper, camera):
    """RGBA and depth of the mapper's tubes, GL-free."""
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    batch = sightline.vtkSightlineImageRenderer()
    batch.AddActor(actor)
    batch.SetActiveCamera(camera)
    batch.SetSize(*SIZE)
    batch.Update()
    image = batch.GetOutput().GetPointData()
    return vtk_to_numpy(image.GetArray(0)).astype(float), vtk_to_numpy(image.GetArray("Depth"))


def tube_mapper(reader, pieces, color=False):
    mapper = sightline.vtkSightlineTubeMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetRadius(0.4)
    mapper.SetLinkLayout(mapper.LINKS_CHUNKED)
    mapper.SetStreamedPieces(pieces)
    if color:
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray("height")
        mapper.SetScalarRange(-40.0, 60.0)
        mapper.ScalarVisibilityOn()
    else:
        mapper.ScalarVisibilityOff()
    return mapper


def camera_for(bounds):
    center = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    camera = vtk.vtkCamera()
    camera.SetFocalPoint(*center)
    camera.SetPosition(center[0] + 60, center[1] - 200, center[2] + 80)
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(40)
    return camera


class TubeStreaming(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.TemporaryDirectory()
        cls.files, cls.streamlines = tractogram_files(cls.folder.name)
        whole = reader_for(cls.files["trk"])
        whole.Update()
        cls.camera = camera_for(whole.GetOutput().GetBounds())

    @classmethod
    def tearDownClass(cls):
        cls.folder.cleanup()

    def compare(self, path, pieces, color=False):
        whole = tube_mapper(reader_for(path), 1, color)
        reference, reference_depth = render(whole, self.camera)
        reader = reader_for(path)
        streamed = tube_mapper(reader, pieces, color)
        errors = errors_of(streamed)
        image, depth = render(streamed, self.camera)
        self.assertEqual(errors, [])
        self.assertEqual(streamed.GetBuiltLinkLayout(), streamed.LINKS_CHUNKED)
        self.assertEqual(streamed.GetNumberOfLinks(), whole.GetNumberOfLinks())
        # The reader's last piece is released: the whole poly data never existed.
        self.assertEqual(reader.GetOutput().GetNumberOfPoints(), 0)
        hit, streamed_hit = reference_depth < 1.0, depth < 1.0
        self.assertGreater(hit.sum(), 0.05 * hit.size, path)
        # The pieces' points are relative to the first piece's centre, the whole's to its own:
        # the same tubes up to float rounding of the positions (a silhouette pixel may flip).
        self.assertLessEqual((hit != streamed_hit).sum(), 0.001 * hit.sum(), path)
        both = hit & streamed_hit
        self.assertLess(np.abs(depth[both] - reference_depth[both]).max(), 1e-5, path)
        differing = (np.abs(image - reference).max(axis=1) > 2).sum()
        self.assertLessEqual(differing, 0.002 * hit.sum(), path)
        return whole, streamed

    def test_each_reader_streams_the_same_image(self):
        for kind in ("trk", "trx", "tck"):
            for pieces in (2, 7):
                with self.subTest(kind=kind, pieces=pieces):
                    self.compare(self.files[kind], pieces)

    def test_colours_by_a_point_array(self):
        whole, streamed = self.compare(self.files["trx"], 5, color=True)
        image, _ = render(streamed, self.camera)
        # Coloured, not the actor's white: hues vary along the bundles' height.
        covered = image[image[:, 3] > 0]
        self.assertGreater(np.ptp(covered[:, 0] - covered[:, 2]), 100)

    def test_progress_counts_pieces_under_its_own_text(self):
        mapper = tube_mapper(reader_for(self.files["trx"]), 4)
        events = []
        mapper.AddObserver(vtk.vtkCommand.ProgressEvent,
                           lambda m, _: events.append((m.GetProgress(), m.GetProgressText())))
        render(mapper, self.camera)
        expected = [((k + 1) / 4, "reading and building tubes") for k in range(4)]
        self.assertEqual(events[:4], expected)
        # Then the frame's own progress, no longer under the build's text.
        self.assertGreater(len(events), 4)
        self.assertTrue(all(text is None for _, text in events[4:]), events)
        self.assertIsNone(mapper.GetProgressText())

    def test_more_pieces_than_streamlines(self):
        self.compare(self.files["trx"], self.streamlines + 5)

    def test_rebuilds_when_the_reader_changes(self):
        reader = reader_for(self.files["trk"])
        mapper = tube_mapper(reader, 3)
        render(mapper, self.camera)
        links = mapper.GetNumberOfLinks()
        self.assertGreater(links, 0)
        # Another frame of the unchanged pipeline reads nothing again (its pieces are released,
        # which must not look like a change).
        executions = []
        reader.AddObserver(vtkCommand.EndEvent, lambda caller, event: executions.append(1))
        render(mapper, self.camera)
        self.assertEqual(executions, [])
        reader.Modified()
        render(mapper, self.camera)
        self.assertEqual(len(executions), 3)  # a piece each
        reader.SetFileName(os.path.join(self.folder.name, "sub_1", "AF_L.trk"))
        render(mapper, self.camera)
        self.assertGreater(mapper.GetNumberOfLinks(), 0)
        self.assertLess(mapper.GetNumberOfLinks(), links)

    def test_what_a_piece_cannot_give_is_a_named_error(self):
        reader = reader_for(self.files["trx"])
        cases = {
            "LinkLayout": lambda m: m.SetLinkLayout(m.LINKS_COMBINED_ON_THE_FLY),
            "PredecessorArrayName": lambda m: m.SetPredecessorArrayName("parent"),
            "VARY_RADIUS_BY_SCALAR": lambda m: (m.SetRadiusArrayName("height"),
                                                m.SetVaryRadius(m.VARY_RADIUS_BY_SCALAR)),
        }
        for words, edit in cases.items():
            with self.subTest(words):
                mapper = tube_mapper(reader, 3)
                edit(mapper)
                errors = errors_of(mapper)
                image, _ = render(mapper, self.camera)
                self.assertEqual(len(errors), 1, errors)
                self.assertIn(words, errors[0])
                self.assertIn("StreamedPieces", errors[0])
                self.assertEqual(image[:, :3].max(), 0)

    def test_input_given_as_data_is_drawn_whole(self):
        """SetInputData's trivial producer would hand every piece the whole data (drawn N
        times, then released under its owner): it is drawn whole, with a warning."""
        reader = reader_for(self.files["trk"])
        reader.Update()
        data = vtk.vtkPolyData()
        data.DeepCopy(reader.GetOutput())
        whole = tube_mapper(reader, 1)
        reference, _ = render(whole, self.camera)
        mapper = tube_mapper(reader, 3)
        mapper.SetInputDataObject(data)
        warnings = []
        mapper.AddObserver(vtkCommand.WarningEvent, calldata_type(VTK_STRING)(
            lambda caller, event, message: warnings.append(message)))
        image, _ = render(mapper, self.camera)
        self.assertEqual(mapper.GetNumberOfLinks(), whole.GetNumberOfLinks())
        self.assertEqual(data.GetNumberOfPoints(), reader.GetOutput().GetNumberOfPoints())
        self.assertTrue(np.array_equal(image, reference))
        self.assertEqual(len(warnings), 1)
        self.assertIn("given as data", warnings[0])

    def test_picks_name_the_whole_inputs_cells_and_points(self):
        """Hardware selection (a window: the suite runs under Xvfb) at tube pixels names the
        same cell and point streamed as whole."""
        path = self.files["trx"]
        results = []
        for pieces in (1, 4):
            mapper = tube_mapper(reader_for(path), pieces)
            actor = vtk.vtkActor()
            actor.SetMapper(mapper)
            renderer = vtk.vtkRenderer()
            renderer.AddActor(actor)
            renderer.SetActiveCamera(self.camera)
            window = vtk.vtkRenderWindow()
            window.SetOffScreenRendering(1)
            window.SetSize(*SIZE)
            window.AddRenderer(renderer)
            window.Render()
            picks = []
            for association in (vtk.vtkDataObject.FIELD_ASSOCIATION_CELLS,
                                vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS):
                for x, y in ((100, 80), (90, 70), (120, 90), (60, 100), (140, 60)):
                    selector = vtk.vtkHardwareSelector()
                    selector.SetRenderer(renderer)
                    selector.SetArea(x, y, x, y)
                    selector.SetFieldAssociation(association)
                    selection = selector.Select()
                    ids = [vtk_to_numpy(selection.GetNode(n).GetSelectionList()).tolist()
                           for n in range(selection.GetNumberOfNodes())]
                    picks.append(ids)
            results.append(picks)
            window.Finalize()
        self.assertEqual(results[0], results[1])
        self.assertGreater(sum(1 for ids in results[0] if ids), 4)


if __name__ == "__main__":
    unittest.main()
