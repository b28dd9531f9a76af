# SPDX-License-Identifier: BSD-3-Clause
"""sightline.figures and sightline-view --mosaic: report mosaics with no X server.
Streamline slabs are checked link by link against a plain loop over nibabel's standard.trk.

The slices a mosaic reads are checked against nibabel (an independent NIfTI reader) for
float, scaled-integer, .nii and .nii.gz files; the mosaic runs with DISPLAY pointing at no
X server (any X connection would fail); each panel shows glyphs, framed and different from
its neighbours; labels are drawn with FreeType; the reading stays bounded (traced peak well
below the image's size); bad requests are named errors."""
import gzip
import os
import shutil
import subprocess
import sys
import tempfile
import tracemalloc
import unittest

import nibabel as nib
import numpy as np
import vtk
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

import sightline
from sightline import figures

VIEW = os.environ.get("SIGHTLINE_VIEW", "sightline-view")
SH_DATA = os.environ.get("SIGHTLINE_SH_DATA_DIR", "")
TENSOR_DATA = os.environ.get("SIGHTLINE_TENSOR_DATA_DIR", "")
NIBABEL_TRK = "/usr/lib/python3/dist-packages/nibabel/tests/data/standard.trk"
NO_X = ":97"  # no X server listens there: a connection attempt would abort the run


def read_png(path):
    """(h, w, 3) uint8, top row first."""
    reader = vtk.vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    width, height, _ = reader.GetOutput().GetDimensions()
    pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
    return pixels.reshape(height, width, -1)[::-1, :, :3]


def synthetic_sh(shape, count=45, seed=3):
    """SH coefficients in a ball: a positive l = 0 term, smaller higher terms (glyphs with
    lobes); zero outside, so the ball is the 'brain'."""
    rng = np.random.default_rng(seed)
    grid = np.stack(np.meshgrid(*[np.linspace(-1, 1, n) for n in shape], indexing="ij"), -1)
    inside = (grid ** 2).sum(-1) < 0.8
    data = np.zeros(shape + (count,), np.float32)
    data[..., 0] = 1.0
    data[..., 1:] = 0.25 * rng.standard_normal(shape + (count - 1,))
    data[~inside] = 0
    return data


class Figures(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="sightline_figures_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, ignore_errors=True)

    def write_nifti(self, name, data, affine=None, dtype=None, slope=None):
        image = nib.Nifti1Image(data if dtype is None else data.astype(dtype),
                                np.diag([1.5, 1.5, 2.0, 1.0]) if affine is None else affine)
        if slope is not None:
            image.header.set_slope_inter(slope, 0.25)
        path = os.path.join(self.folder, name)
        nib.save(image, path)
        return path

    # -- reading ----------------------------------------------------------------------------
    def test_planes_equal_nibabels_slices(self):
        data = synthetic_sh((9, 11, 7), count=6)
        cases = [("float.nii.gz", data, None, None), ("float.nii", data, None, None),
                 ("scaled.nii", (data * 1000).round(), np.int16, 0.5)]
        for name, values, dtype, slope in cases:
            path = self.write_nifti(name, values, dtype=dtype, slope=slope)
            expected = np.asarray(nib.load(path).get_fdata(), dtype=np.float64)
            planes = figures.NiftiPlanes(path).planes([(0, 3), (1, 0), (2, 6), (2, 2)])
            for (axis, index), image in planes.items():
                got = vtk_to_numpy(image.GetPointData().GetScalars())
                reference = np.take(expected, index, axis=axis)  # (other axes..., components)
                # VTK orders points x fastest: the reference's axes reversed, flattened.
                reference = np.moveaxis(reference, (0, 1), (1, 0)).reshape(-1, expected.shape[3])
                np.testing.assert_allclose(got, reference, rtol=1e-6, atol=1e-6,
                                           err_msg=f"{name} axis {axis} slice {index}")
                extent = image.GetExtent()
                self.assertEqual(extent[2 * axis], index)
                self.assertEqual(extent[2 * axis + 1], index)

    def test_reading_is_bounded_by_the_slices(self):
        data = synthetic_sh((40, 48, 36))  # 12 MB of float32 coefficients
        path = self.write_nifti("bounded.nii", data)
        tracemalloc.start()
        figures.mosaic(path, panels="axial:2,coronal:2,sagittal:2", size=(300, 240),
                       verbose=False)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        self.assertLess(peak, 0.35 * data.nbytes,
                        f"traced peak {peak / 1e6:.1f} MB for a {data.nbytes / 1e6:.1f} MB image")

    # -- image slices without OpenGL ---------------------------------------------------------
    def test_slice_plane_cuts_a_glyph_at_exact_depth(self):
        """An SH glyph with an oblique image slice through its centre, GL-free: the slice
        alone has the plane's analytic window depth (from the camera's projection matrix), and
        the scene shows at each pixel whichever of glyph and plane is nearer."""
        coefficients = vtk.vtkImageData()
        coefficients.SetDimensions(1, 1, 1)
        values = np.zeros((1, 15), np.float32)
        values[0, 0], values[0, 3], values[0, 10] = 1.0, 0.6, -0.3  # lobed, lmax 4
        array = numpy_to_vtk(values, deep=True)
        coefficients.GetPointData().SetScalars(array)
        glyph = sightline.vtkSightlineSHGlyphMapper()
        glyph.SetInputDataObject(coefficients)
        glyph.SetScaleFactor(2.0)
        glyph_actor = vtk.vtkActor()
        glyph_actor.SetMapper(glyph)
        grey = vtk.vtkImageData()
        grey.SetDimensions(6, 6, 1)
        grey.SetSpacing(0.5, 0.5, 1.0)
        grey.SetOrigin(-1.25, -1.25, 0.0)
        grey.GetPointData().SetScalars(numpy_to_vtk(np.linspace(0, 255, 36), deep=True))
        slice_mapper = vtk.vtkImageSliceMapper()
        slice_mapper.SetInputData(grey)
        slice_mapper.BorderOn()
        plane = vtk.vtkImageSlice()
        plane.SetMapper(slice_mapper)
        plane.RotateX(35)
        plane.RotateY(-20)
        camera = vtk.vtkCamera()
        camera.SetPosition(1.5, -2.5, 4.0)
        camera.SetFocalPoint(0, 0, 0)
        camera.SetViewUp(0, 0, 1)
        camera.SetClippingRange(1.0, 10.0)

        def render(actors, slices):
            renderer = sightline.vtkSightlineImageRenderer()
            for actor in actors:
                renderer.AddActor(actor)
            for item in slices:
                renderer.AddImageSlice(item)
            renderer.SetActiveCamera(camera)
            renderer.SetSize(160, 120)
            renderer.Update()
            output = renderer.GetOutput()
            return (vtk_to_numpy(output.GetPointData().GetArray("Depth")).copy(),
                    vtk_to_numpy(output.GetPointData().GetScalars())[:, :3].copy())

        both, both_rgb = render([glyph_actor], [plane])
        glyph_depth, glyph_rgb = render([glyph_actor], [])
        plane_depth, plane_rgb = render([], [plane])
        self.assertTrue(np.array_equal(both, np.minimum(glyph_depth, plane_depth)))
        glyph_wins = glyph_depth < plane_depth
        cut = (glyph_depth < 1) & ~glyph_wins
        self.assertGreater(glyph_wins.sum(), 100)
        self.assertGreater(cut.sum(), 100, "the plane should hide part of the glyph")
        self.assertTrue(np.array_equal(both_rgb[glyph_wins], glyph_rgb[glyph_wins]))
        self.assertTrue(np.array_equal(both_rgb[cut], plane_rgb[cut]))
        # The plane's depth: where the pixel ray meets the plane n.x = 0, projected by the
        # camera's own matrix (in numpy, independent of the kernel's camera).
        matrix = np.array([[camera.GetCompositeProjectionTransformMatrix(160 / 120, -1, 1)
                            .GetElement(r, c) for c in range(4)] for r in range(4)])
        inverse = np.linalg.inv(matrix)
        normal = np.array(plane.GetMatrix().MultiplyPoint((0, 0, 1, 0))[:3])
        hit = plane_depth < 1
        self.assertGreater(hit.sum(), 1000)
        ys, xs = np.divmod(np.nonzero(hit)[0], 160)
        ndc_x, ndc_y = (xs + 0.5) / 160 * 2 - 1, (ys + 0.5) / 120 * 2 - 1
        near = inverse @ np.stack([ndc_x, ndc_y, -np.ones_like(ndc_x), np.ones_like(ndc_x)])
        far = inverse @ np.stack([ndc_x, ndc_y, np.ones_like(ndc_x), np.ones_like(ndc_x)])
        near, far = near[:3] / near[3], far[:3] / far[3]
        t = -(normal @ near) / (normal @ (far - near))
        point = near + t * (far - near)
        clip = matrix @ np.vstack([point, np.ones(point.shape[1])])
        expected = 0.5 * clip[2] / clip[3] + 0.5
        self.assertLess(np.abs(plane_depth[hit] - expected).max(), 1e-6)

    # -- the figure --------------------------------------------------------------------------
    def panels(self, picture, rows, columns):
        height, width = picture.shape[0] // rows, picture.shape[1] // columns
        return [[picture[r * height:(r + 1) * height, c * width:(c + 1) * width]
                 for c in range(columns)] for r in range(rows)]

    def test_mosaic_panels_show_framed_distinct_slices(self):
        path = self.write_nifti("ball.nii.gz", synthetic_sh((30, 34, 26)))
        picture = figures.mosaic(path, panels="axial:3,coronal:3,sagittal:3", size=(600, 450),
                                 labels=False, verbose=False)
        self.assertEqual(picture.shape, (450, 600, 3))
        grid = self.panels(picture, 3, 3)
        for r, row in enumerate(grid):
            for c, panel in enumerate(row):
                covered = panel.max(axis=-1) > 8  # the background is black
                rows, cols = np.nonzero(covered.any(axis=1))[0], np.nonzero(covered.any(axis=0))[0]
                self.assertGreater(covered.mean(), 0.05, f"panel {r},{c} is (nearly) empty")
                # Framed on the ball: not cut by the panel's edges ...
                self.assertTrue(rows[0] > 0 and cols[0] > 0 and rows[-1] < panel.shape[0] - 1
                                and cols[-1] < panel.shape[1] - 1, f"panel {r},{c} is cut")
            # ... and the middle slice (through the ball's centre) is the widest.
            widths = [np.ptp(np.nonzero(p.max(axis=-1).max(axis=0) > 8)[0]) for p in row]
            self.assertEqual(int(np.argmax(widths)), 1, f"row {r}: widths {widths}")
            self.assertGreater(np.abs(row[0].astype(int) - row[2].astype(int)).mean(), 1.0)

    def test_labels_are_drawn_without_opengl(self):
        path = self.write_nifti("labels.nii.gz", synthetic_sh((20, 22, 18)))
        plain = figures.mosaic(path, panels="axial:2", size=(400, 200), labels=False,
                               verbose=False)
        labelled = figures.mosaic(path, panels="axial:2", size=(400, 200), verbose=False)
        changed = np.abs(plain.astype(int) - labelled.astype(int)).max(axis=-1) > 60
        # Letters at the first panel's four edges and a position under each panel.
        self.assertTrue(changed[:, :20].any(), "no letter on the left edge")
        self.assertTrue(changed[:30, 60:140].any(), "no letter at the top")
        self.assertTrue(changed[170:, 200:300].any(), "no slice position under panel 2")
        self.assertTrue((labelled[changed] > 200).all(axis=-1).mean() > 0.3, "text is white")
        # The direction key at the top right: red, green and blue words.
        key = labelled[:24, 260:400].astype(int)
        for channel in range(3):
            others = [c for c in range(3) if c != channel]
            saturated = (key[..., channel] > 180) & (key[..., others].max(axis=-1) < 150)
            self.assertTrue(saturated.any(), f"no key word in colour channel {channel}")

    @unittest.skipUnless(SH_DATA, "needs the SH test data (SHData fixture)")
    def test_scalar_bar_shows_the_underlay_window(self):
        sh = os.path.join(SH_DATA, "small_64D_sh_descoteaux07.nii.gz")
        fa = os.path.join(SH_DATA, "small_64D_fa.nii.gz")
        picture = figures.mosaic(sh, underlay=fa, panels="axial:2", size=(400, 200),
                                 scalar_bar=True, verbose=False)
        # A grey ramp in the last panel's right edge: grey, brighter towards the top.
        column = picture[2 * 11:2 * 11 + 100, 400 - 6 - 3].astype(int)
        self.assertTrue((np.abs(column[:, 0] - column[:, 1]) <= 1).all(), "not grey")
        self.assertTrue((np.diff(column[:, 0]) <= 0).all(), "not darker downwards")
        self.assertGreater(column[0, 0] - column[-1, 0], 200)

    @unittest.skipUnless(SH_DATA, "needs the SH test data (SHData fixture)")
    def test_command_line_with_no_x_server(self):
        sh = os.path.join(SH_DATA, "small_64D_sh_descoteaux07.nii.gz")
        fa = os.path.join(SH_DATA, "small_64D_fa.nii.gz")
        mif = os.path.join(SH_DATA, "small_64D_sh_tournier07.mif")
        environment = dict(os.environ, DISPLAY=NO_X)
        # With the underlay most of each panel is covered; glyphs alone cover a few per cent.
        for name, files, fill in (("nifti", [sh, "--underlay", fa], 0.3), ("mif", [mif], 0.02)):
            output = os.path.join(self.folder, f"report-{name}.png")
            result = subprocess.run(
                [sys.executable, VIEW, *files, "--mosaic", "axial:3,coronal:3,sagittal:3",
                 "--size", "600", "450", "--output", output],
                capture_output=True, text=True, env=environment, timeout=300)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            self.assertIn("9 panels", result.stdout)
            positions = [float(line.split("= ")[1].split()[0])
                         for line in result.stdout.splitlines() if line.strip().startswith("panel")]
            self.assertEqual(len(positions), 9)
            for row in range(3):  # each row runs from low to high world coordinates
                self.assertEqual(positions[3 * row:3 * row + 3],
                                 sorted(positions[3 * row:3 * row + 3]), name)
            picture = read_png(output)
            self.assertEqual(picture.shape, (450, 600, 3))
            for row in self.panels(picture, 3, 3):
                for panel in row:
                    background = np.round(np.array([0.07, 0.075, 0.09]) * 255)
                    covered = np.abs(panel.astype(float) - background).max(axis=-1) > 8
                    self.assertGreater(covered.mean(), fill, name)

    @unittest.skipUnless(TENSOR_DATA, "needs the tensor test data (TensorData fixture)")
    def test_tensor_mosaic(self):
        tensors = [f for f in sorted(os.listdir(TENSOR_DATA)) if f.endswith(".nii.gz")]
        self.assertTrue(tensors, TENSOR_DATA)
        picture = figures.mosaic(os.path.join(TENSOR_DATA, tensors[0]), panels="axial:2",
                                 size=(400, 200), verbose=False)
        self.assertGreater((picture.max(axis=-1) > 8).mean(), 0.05)

    def test_slab_keeps_exactly_the_links_inside_it(self):
        tracts = figures.Tractogram(NIBABEL_TRK)
        points = vtk_to_numpy(tracts.data.GetPoints().GetData())
        offsets, ids = tracts.offsets, tracts.ids
        for axis, position, slab in ((2, 1.5, 2.0), (0, 5.0, 3.0), (1, -40.0, 1.0)):
            inside = lambda p: abs(points[p, axis] - position) <= 0.5 * slab
            expected = {(ids[k], ids[k + 1]) for line in range(len(offsets) - 1)
                        for k in range(offsets[line], offsets[line + 1] - 1)
                        if inside(ids[k]) and inside(ids[k + 1])}
            actor = tracts.actor(axis, position, slab)
            got = set()
            if actor is not None:
                piece = actor.GetMapper().GetInput()
                o = vtk_to_numpy(piece.GetLines().GetOffsetsArray())
                c = vtk_to_numpy(piece.GetLines().GetConnectivityArray())
                self.assertTrue((np.diff(o) >= 2).all(), "a run of one point")
                got = {(c[k], c[k + 1]) for run in range(len(o) - 1) for k in range(o[run], o[run + 1] - 1)}
            self.assertEqual(got, expected, f"axis {axis} at {position}")
            if axis == 2:
                self.assertTrue(expected, "the slab should hold some links")

    def test_tractogram_mosaic_whole_and_slab(self):
        whole = figures.mosaic(tractogram=NIBABEL_TRK, panels="axial:3,coronal:3",
                               size=(600, 400), verbose=False)
        slab = figures.mosaic(tractogram=NIBABEL_TRK, panels="axial:3,coronal:3",
                              size=(600, 400), slab=2.0, verbose=False)
        for picture in (whole, slab):
            for row in self.panels(picture, 2, 3):
                for panel in row:
                    self.assertGreater((panel.max(axis=-1) > 8).mean(), 0.001)  # not empty
        # A slab shows less of the tractogram than the whole (cut only by the far clip).
        self.assertLess((slab.max(axis=-1) > 8).mean(), (whole.max(axis=-1) > 8).mean())

    def test_broken_headers_are_named_before_vtk_reads_them(self):
        """sightline.nifti.check_header (used by the mosaic and by sightline-view's reads) names
        what VTK's NIfTI reader can crash on or misread."""
        from sightline import nifti
        good = self.write_nifti("good.nii", synthetic_sh((5, 6, 4), count=6))
        with open(good, "rb") as stream:
            seed = bytearray(stream.read())
        nifti.check_header(good)
        cases = [(344, b"%+1\0", "not a single-file NIfTI"), (40, b"\x09\x00", r"dim\[0\] is 9"),
                 (42, b"\xfe\xff", "not all positive"), (70, b"\x46\x00", "unknown NIfTI datatype"),
                 (72, b"\x08\x00", "bitpix 8 does not match"), (0, b"\x00\x01\x00\x00", "header size")]
        for offset, patch, message in cases:
            broken = bytearray(seed)
            broken[offset:offset + len(patch)] = patch
            path = os.path.join(self.folder, "broken.nii")
            with open(path, "wb") as stream:
                stream.write(broken)
            with self.assertRaisesRegex(nifti.NiftiError, message):
                nifti.check_header(path)
            with self.assertRaisesRegex(figures.FigureError, message):
                figures.mosaic(path, panels="axial:1", size=(64, 64), verbose=False)
        with open(os.path.join(self.folder, "short.nii"), "wb") as stream:
            stream.write(seed[:-8])
        with self.assertRaisesRegex(nifti.NiftiError, "need"):
            nifti.check_header(os.path.join(self.folder, "short.nii"))

    def test_mutated_headers_never_crash(self):
        """300 seeded mutations of a small file's header (and truncations): each mosaic draws
        or raises FigureError; a crash (VTK's reader on a broken magic, Embree on rays of a
        corrupt affine beyond float range) would end this process."""
        import random
        with open(self.write_nifti("seed.nii", synthetic_sh((6, 7, 5), count=6)), "rb") as stream:
            seed = stream.read()
        rng, outcomes = random.Random(36), {"drawn": 0, "named": 0}
        for case in range(300):
            mutated = bytearray(seed)
            for _ in range(rng.randint(1, 6)):
                mutated[rng.randrange(352)] = rng.randrange(256)
            if rng.random() < 0.2:
                mutated = mutated[:rng.randrange(len(mutated))]
            path = os.path.join(self.folder, "mutated.nii")
            with open(path, "wb") as stream:
                stream.write(mutated)
            try:
                figures.mosaic(path, panels="axial:2,coronal:1", size=(90, 90), labels=False,
                               verbose=False)
                outcomes["drawn"] += 1
            except figures.FigureError:
                outcomes["named"] += 1
        self.assertGreater(outcomes["drawn"], 50)
        self.assertGreater(outcomes["named"], 50)

    def test_named_errors(self):
        path = self.write_nifti("scalar.nii", np.ones((5, 6, 4), np.float32))
        with self.assertRaisesRegex(figures.FigureError, "scalar image"):
            figures.mosaic(path, panels="axial:2", size=(200, 100), verbose=False)
        sh = self.write_nifti("few.nii", synthetic_sh((8, 8, 8), count=6))
        for panels, message in (("oblique:3", "not axial"), ("axial:x", "whole number"),
                                ("axial:0", "1 to 64")):
            with self.assertRaisesRegex(figures.FigureError, message):
                figures.mosaic(sh, panels=panels, size=(200, 100), verbose=False)
        with self.assertRaisesRegex(figures.FigureError, "panels of"):
            figures.mosaic(sh, panels="axial:64", size=(200, 100), verbose=False)
        with self.assertRaisesRegex(figures.FigureError, "needs an SH or tensor image"):
            figures.mosaic(verbose=False)
        with self.assertRaisesRegex(figures.FigureError, "slab must be"):
            figures.mosaic(tractogram=NIBABEL_TRK, slab=-1, verbose=False)
        with self.assertRaisesRegex(figures.FigureError, "no such file"):
            figures.mosaic(os.path.join(self.folder, "missing.nii.gz"), verbose=False)
        broken = os.path.join(self.folder, "short.nii")
        with open(sh, "rb") as source, open(broken, "wb") as target:
            target.write(source.read()[:-100])
        with self.assertRaisesRegex(figures.FigureError, "need .* bytes, the file has"):
            figures.mosaic(broken, panels="axial:2", size=(200, 100), verbose=False)
        gz = self.write_nifti("whole.nii.gz", synthetic_sh((8, 8, 8), count=6))
        for cut, message in ((-30, "cannot read its voxel data|ends inside"), (600, "ends inside")):
            with open(gz, "rb") as source, open(broken + ".gz", "wb") as target:
                data = source.read()
                target.write(data[:cut] if cut < 0 else gzip.compress(gzip.decompress(data)[:cut]))
            with self.assertRaisesRegex(figures.FigureError, message):
                figures.mosaic(broken + ".gz", panels="axial:2", size=(200, 100), verbose=False)
        result = subprocess.run([sys.executable, VIEW, sh, "--mosaic", "axial:2"],
                                capture_output=True, text=True, timeout=120,
                                env=dict(os.environ, DISPLAY=NO_X))
        self.assertEqual(result.returncode, 2)
        self.assertIn("--output FILE.png", result.stderr)


if __name__ == "__main__":
    unittest.main()
