# SPDX-License-Identifier: BSD-3-Clause
"""vtkSightlineTubeMapper.HiddenLinkCulling: a tractogram dense enough that most links lie inside
other links (a ball filled ~160 times over, like a whole-brain tractogram of 10^9 links) draws,
from outside its bounds, exactly the image and depth that every link draws, while tracing only
the outer links; translucent frames, a camera inside the bounds and a clipping Region trace
every link and draw what they drew before; a sparse tractogram is not culled. GL-free."""
import unittest

import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline

SIZE = (120, 90)
RADIUS = 0.3


def ball_tractogram(fill, seed=4):
    """Smooth streamlines of 0.5 mm steps inside a ball of radius 5 mm, filling it `fill` times
    over with tubes of RADIUS; a per-point array "order"."""
    rng = np.random.default_rng(seed)
    target = int(fill * (4 / 3 * np.pi * 125) / (np.pi * RADIUS ** 2 * 0.5))
    batches, links = [], 0
    while links < target:
        count = 20000
        p = rng.uniform(-1, 1, (count * 3, 3))
        p = 5.0 * p[(p ** 2).sum(1) < 1][:count]
        d = rng.normal(size=(count, 3))
        alive = np.ones(count, bool)
        steps = [p.copy()]
        for _ in range(40):
            d += 0.3 * rng.normal(size=d.shape)
            d /= np.linalg.norm(d, axis=1)[:, None]
            q = p + 0.5 * d
            alive &= (q ** 2).sum(1) < 25.0
            p = np.where(alive[:, None], q, p)
            steps.append(np.where(alive[:, None], p, np.nan))
        batch = np.stack(steps, 1)  # streamline, step, xyz
        batch = batch[(~np.isnan(batch[:, :, 0])).sum(1) >= 2]
        batches.append(batch)
        links += int((~np.isnan(batch[:, :, 0])).sum() - len(batch))
    points = np.concatenate(batches)
    lengths = (~np.isnan(points[:, :, 0])).sum(1)
    flat = points[~np.isnan(points[:, :, 0])].astype(np.float32)
    offsets = np.concatenate([[0], np.cumsum(lengths)])
    poly = vtk.vtkPolyData()
    vtk_points = vtk.vtkPoints()
    vtk_points.SetData(numpy_to_vtk(flat, deep=1))
    poly.SetPoints(vtk_points)
    lines = vtk.vtkCellArray()
    lines.SetData(numpy_to_vtk(offsets.astype(np.int64), deep=1),
                  numpy_to_vtk(np.arange(len(flat), dtype=np.int64), deep=1))
    poly.SetLines(lines)
    order = numpy_to_vtk(np.arange(len(flat), dtype=np.float32), deep=1)
    order.SetName("order")
    poly.GetPointData().AddArray(order)
    return poly


def render(poly, culling, position, opacity=1.0, region=None, chunk_links=8, progress=None):
    producer = vtk.vtkTrivialProducer()
    producer.SetOutput(poly)
    mapper = sightline.vtkSightlineTubeMapper()
    mapper.SetInputConnection(producer.GetOutputPort())
    mapper.SetRadius(RADIUS)
    mapper.SetLinkLayout(mapper.LINKS_CHUNKED)
    mapper.SetChunkLinks(chunk_links)
    mapper.SetHiddenLinkCulling(culling)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray("order")
    mapper.SetScalarRange(0, poly.GetNumberOfPoints())
    if region:
        mapper.SetRegion(*region)
    if progress is not None:  # (fraction, progress text) of each ProgressEvent
        mapper.AddObserver(vtk.vtkCommand.ProgressEvent,
                           lambda m, _: progress.append((m.GetProgress(), m.GetProgressText())))
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetOpacity(opacity)
    camera = vtk.vtkCamera()
    camera.SetFocalPoint(0, 0, 0)
    camera.SetPosition(*position)
    camera.SetViewUp(0, 0, 1)
    camera.SetViewAngle(35)
    distance = float(np.linalg.norm(position))
    camera.SetClippingRange(max(distance - 7.0, 0.05), distance + 7.0)
    renderer = sightline.vtkSightlineImageRenderer()
    renderer.AddActor(actor)
    renderer.SetActiveCamera(camera)
    renderer.SetSize(*SIZE)
    renderer.Update()
    data = renderer.GetOutput().GetPointData()
    rgba = vtk_to_numpy(data.GetScalars()).copy()
    depth = vtk_to_numpy(data.GetArray("Depth")).copy()
    return rgba, depth, mapper


class HiddenLinkCulling(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dense = ball_tractogram(160.0)

    def assertSameImage(self, a, b):
        self.assertEqual(int((a[0] != b[0]).any(axis=1).sum()), 0, "pixels whose colour differs")
        self.assertTrue(np.array_equal(a[1], b[1]), "depth differs")

    def test_views_from_outside_are_the_same_with_the_outer_links_only(self):
        for position in [(-20, 3, 2), (1, -2, 21)]:
            whole = render(self.dense, 0, position)
            culled = render(self.dense, 1, position)
            self.assertSameImage(whole, culled)
            mapper = culled[2]
            self.assertTrue(mapper.GetLastFrameOuter())
            self.assertFalse(whole[2].GetLastFrameOuter())
            self.assertEqual(whole[2].GetHiddenLinks(), 0)
            # The core of the ball (radius ~3.3 of 5) is hidden: a third of the links at least.
            self.assertGreater(mapper.GetHiddenLinks(), mapper.GetNumberOfLinks() // 3)
            covered = (whole[0][:, 3] > 0).sum()
            self.assertGreater(covered, SIZE[0] * SIZE[1] // 5)
            # Colours follow the points: the image is not one flat colour.
            self.assertGreater(len(np.unique(culled[0][culled[0][:, 3] > 0][:, 0])), 50)

    def test_the_pass_reports_progress_and_its_time(self):
        events = []
        _, _, mapper = render(self.dense, 1, (-20, 3, 2), progress=events)
        culling = [fraction for fraction, text in events if text == "finding hidden links"]
        self.assertGreaterEqual(len(culling), 3, events)
        self.assertEqual(culling[0], 0.0)
        self.assertEqual(culling[-1], 1.0)
        self.assertEqual(culling, sorted(culling))
        self.assertGreater(mapper.GetHiddenLinks(), 0)
        total = mapper.GetLastCullingSeconds()
        self.assertGreater(total, 0.0)
        self.assertLessEqual(mapper.GetLastCullingMarkSeconds() + mapper.GetLastCullingTestSeconds(), total)
        self.assertGreater(mapper.GetLastCullingMarkSeconds(), 0.0)
        self.assertGreaterEqual(mapper.GetLastGeometrySeconds(), total)
        # Without culling there is no such pass, and no progress under its name.
        events = []
        _, _, whole = render(self.dense, 0, (-20, 3, 2), progress=events)
        self.assertEqual(whole.GetLastCullingSeconds(), 0.0)
        self.assertFalse([e for e in events if e[1] == "finding hidden links"])

    def test_translucent_inside_and_clipped_views_trace_every_link(self):
        cases = [
            dict(position=(-20, 3, 2), opacity=0.4),
            dict(position=(-2, 0.5, 0.3)),  # the camera inside the tubes' bounds
            dict(position=(-20, 3, 2), region=(0, 10, -10, 10, -10, 10)),  # the near half cut away
        ]
        for case in cases:
            whole = render(self.dense, 0, **case)
            culled = render(self.dense, 1, **case)
            self.assertSameImage(whole, culled)
            self.assertFalse(culled[2].GetLastFrameOuter(), case)
            self.assertGreater(culled[2].GetHiddenLinks(), 0)
        # The cut shows the inside: links that the outer view does not need.
        outside = render(self.dense, 1, (-20, 3, 2))
        cut = render(self.dense, 1, (-20, 3, 2), region=(0, 10, -10, 10, -10, 10))
        self.assertGreater(int((outside[0] != cut[0]).any(axis=1).sum()), SIZE[0] * SIZE[1] // 20)

    def test_sparse_tractograms_are_not_culled(self):
        sparse = ball_tractogram(5.0)
        whole = render(sparse, 0, (-20, 3, 2))
        culled = render(sparse, 1, (-20, 3, 2))
        self.assertSameImage(whole, culled)
        self.assertEqual(culled[2].GetHiddenLinks(), 0)
        self.assertFalse(culled[2].GetLastFrameOuter())


if __name__ == "__main__":
    unittest.main()
