# SPDX-License-Identifier: BSD-3-Clause
"""sightline-view as a user runs it, on real files of every kind it opens: DIPY's sform-only
func_coef.nii.gz and the SHData/TensorData fixtures' small_64D SH and tensor images, nibabel's
standard.trk and standard.tck, DIPY's minimal_bundles, the project's SWC test neuron, a .mif
made here with MRtrix3's mrconvert, and a .vtr written here from the spherical field source.
Each image must not be empty and must frame the data (it fills a good part of the picture and
is cut by no border); the EXR output must carry a depth channel that is nearer where the data
is; the window's keys run; bad input gets one line naming the problem, never a traceback."""
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest
import zipfile

import nibabel as nib
import numpy as np
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

import sightline

VIEW = os.environ.get("SIGHTLINE_VIEW", "sightline-view")
DIPY_FILES = "/usr/lib/python3/dist-packages/dipy/data/files"
NIBABEL_DATA = "/usr/lib/python3/dist-packages/nibabel/tests/data"
SWC = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "Data", "SWC",
                   "neuron_three_point_soma.swc")
SH_DATA = os.environ.get("SIGHTLINE_SH_DATA_DIR", "")
TENSOR_DATA = os.environ.get("SIGHTLINE_TENSOR_DATA_DIR", "")
BACKGROUND = np.round(np.array([0.07, 0.075, 0.09]) * 255)
SIZE = (320, 240)


def read_png(path):
    """(h, w, 3 or 4) uint8 pixels of a PNG, bottom row first as VTK reads them."""
    reader = vtk.vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    width, height, _ = reader.GetOutput().GetDimensions()
    return vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).reshape(height, width, -1)


def covered_pixels(path):
    return np.abs(read_png(path)[..., :3].astype(float) - BACKGROUND).max(axis=-1) > 8


def read_exr(path):
    """The channels of an uncompressed scanline float EXR (what sightline-view writes), parsed
    from the OpenEXR layout: header attributes, then one offset per line, then the lines."""
    with open(path, "rb") as stream:
        data = stream.read()
    magic, _ = struct.unpack_from("<ii", data, 0)
    assert magic == 20000630, "not an OpenEXR file"
    position, attributes = 8, {}
    while data[position] != 0:
        name_end = data.index(b"\0", position)
        type_end = data.index(b"\0", name_end + 1)
        size, = struct.unpack_from("<i", data, type_end + 1)
        attributes[data[position:name_end].decode()] = data[type_end + 5:type_end + 5 + size]
        position = type_end + 5 + size
    position += 1
    channels, chlist = [], attributes["channels"]
    while chlist[0] != 0:
        end = chlist.index(b"\0")
        channels.append(chlist[:end].decode())
        chlist = chlist[end + 17:]
    x0, y0, x1, y1 = struct.unpack("<iiii", attributes["dataWindow"])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    offsets = struct.unpack_from(f"<{height}Q", data, position)
    lines = [np.frombuffer(data, "<f4", width * len(channels), offset + 8).reshape(len(channels), width)
             for offset in offsets]
    stack = np.stack(lines, axis=1)  # (channel, y, x)
    return {name: stack[i] for i, name in enumerate(channels)}


class View(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="sightline_view_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, ignore_errors=True)

    def run_view(self, *arguments, expect_ok=True, display=False):
        environment = dict(os.environ)
        if not display:
            environment.pop("DISPLAY", None)  # --output needs no X server
        result = subprocess.run([sys.executable, VIEW, *arguments], capture_output=True,
                                text=True, env=environment, timeout=300)
        if expect_ok:
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.assertNotIn("Traceback", result.stderr)
        return result

    def render(self, name, *files_and_options, min_fill=0.5, display=False):
        """Renders to a PNG (without a window unless display); checks the picture is not empty
        and frames the data."""
        output = os.path.join(self.folder, name + ".png")
        result = self.run_view(*files_and_options, "--output", output, "--size", *map(str, SIZE),
                               display=display)
        covered = covered_pixels(output)
        self.assertGreater(covered.mean(), 0.01, f"{name}: (nearly) empty image\n{result.stdout}")
        rows, columns = np.nonzero(covered.any(axis=1))[0], np.nonzero(covered.any(axis=0))[0]
        height, width = covered.shape
        # Framed: inside the picture (no border cuts the data) ...
        self.assertGreater(rows[0], 0, f"{name}: data cut by the top edge")
        self.assertLess(rows[-1], height - 1, f"{name}: data cut by the bottom edge")
        self.assertGreater(columns[0], 0, f"{name}: data cut by the left edge")
        self.assertLess(columns[-1], width - 1, f"{name}: data cut by the right edge")
        # ... filling it along at least one direction, and roughly centred.
        fill = max((rows[-1] - rows[0] + 1) / height, (columns[-1] - columns[0] + 1) / width)
        self.assertGreater(fill, min_fill, f"{name}: data fills only {fill:.0%} of the picture")
        centre = np.array([(columns[0] + columns[-1]) / 2 / width, (rows[0] + rows[-1]) / 2 / height])
        self.assertLess(np.abs(centre - 0.5).max(), 0.2, f"{name}: data off centre {centre}")
        return result, covered

    # -- each file type --------------------------------------------------------------------
    def test_sform_only_sh_nifti(self):
        result, _ = self.render("func_coef", os.path.join(DIPY_FILES, "func_coef.nii.gz"),
                                "--basis", "dipy", "--legacy")
        self.assertIn("SH lmax 8", result.stdout)
        self.assertIn("affine from the sform", result.stdout)

    @unittest.skipUnless(SH_DATA, "needs the SHData fixture (SIGHTLINE_SH_DATA_DIR)")
    def test_small_64d_sh_nifti(self):
        sh = os.path.join(SH_DATA, "small_64D_sh_descoteaux07.nii.gz")
        result, covered = self.render("small_64D_sh", sh, "--frame", "voxel")
        self.assertIn("SH lmax 8, basis descoteaux07", result.stdout)
        # Another slice shows other glyphs.
        _, other = self.render("small_64D_sh_coronal", sh, "--frame", "voxel", "--slice",
                               "coronal", "--index", "2")
        self.assertGreater((covered != other).mean(), 0.01)

    @unittest.skipUnless(TENSOR_DATA, "needs the TensorData fixture (SIGHTLINE_TENSOR_DATA_DIR)")
    def test_small_64d_tensor_nifti(self):
        result, _ = self.render("small_64D_dti", os.path.join(TENSOR_DATA, "small_64D_dti.nii.gz"),
                                "--frame", "voxel")
        self.assertIn("6 components, tensors, layout fsl", result.stdout)
        # 15 components read as SH lmax 4 unless --layout says tensor.
        gdti4 = os.path.join(TENSOR_DATA, "small_64D_gdti4.nii.gz")
        result, tensor = self.render("small_64D_gdti4", gdti4, "--layout", "unique")
        self.assertIn("15 components, tensors, layout unique", result.stdout)
        result, sh = self.render("small_64D_gdti4_as_sh", gdti4)
        self.assertIn("SH lmax 4", result.stdout)
        self.assertGreater((tensor != sh).mean(), 0.01)

    def test_trk_and_tck(self):
        for name in ("standard.trk", "standard.tck"):
            result, _ = self.render(name, os.path.join(NIBABEL_DATA, name))
            self.assertIn("120 streamlines, 360 points", result.stdout)

    def test_tck_with_track_scalars(self):
        """--tsf: MRtrix3 tcksample's values (here each point's height) colour the tubes."""
        tck = os.path.join(NIBABEL_DATA, "standard.tck")
        points = np.concatenate(list(nib.streamlines.load(tck).streamlines))
        low = np.floor(points.min(0)) - 3
        shape = (np.ceil(points.max(0)) + 3 - low).astype(int) + 1
        affine = np.eye(4)
        affine[:3, 3] = low
        height = (np.indices(shape)[2] + low[2]).astype(np.float32)
        image = os.path.join(self.folder, "height.nii")
        nib.save(nib.Nifti1Image(height, affine), image)
        tsf = os.path.join(self.folder, "height.tsf")
        subprocess.run(["tcksample", "-quiet", "-force", tck, image, tsf], check=True)
        result, _ = self.render("tck_tsf", tck, "--tsf", tsf)
        low_z, high_z = points[:, 2].min(), points[:, 2].max()
        self.assertIn(f"coloured by height (per point, {low_z:.3g} to {high_z:.3g})",
                      result.stdout)
        # Streamed in pieces, each piece's tracks take their own values; the range is the file's.
        result, _ = self.render("tck_tsf_streamed", tck, "--tsf", tsf, "--pieces", "3")
        self.assertIn(f"coloured by height (per point, {low_z:.3g} to {high_z:.3g})",
                      result.stdout)
        self.assertIn(f"{len(points)} points streamed in 3 pieces", result.stdout)
        bad = self.run_view(os.path.join(NIBABEL_DATA, "standard.trk"), "--tsf", tsf,
                            "--output", os.path.join(self.folder, "x.png"), expect_ok=False)
        self.assertIn("--tsf gives a .tck's track scalars", bad.stderr)

    def test_minimal_bundles(self):
        with zipfile.ZipFile(os.path.join(DIPY_FILES, "minimal_bundles.zip")) as archive:
            archive.extractall(self.folder)
        bundles = [os.path.join(self.folder, "sub_1", f"{name}.trk")
                   for name in ("AF_L", "CST_R", "CC_ForcepsMajor")]
        result, covered = self.render("minimal_bundles", *bundles)
        self.assertEqual(result.stdout.count("50 streamlines"), 3)
        # --radius is honoured: thicker tubes cover more of the picture.
        _, thick = self.render("minimal_bundles_thick", *bundles, "--radius", "1.5")
        self.assertGreater(thick.mean(), covered.mean() * 1.3)

    def test_trx_groups_and_colour_arrays(self):
        """A .trx of DIPY's three bundles (each a group, a per-streamline 'bundle' number and a
        per-point 'height'): --group shows only its streamlines, --color colours by a dps (one
        colour per streamline, so per bundle) or a dpv, and the directory form opens too."""
        with zipfile.ZipFile(os.path.join(DIPY_FILES, "minimal_bundles.zip")) as archive:
            archive.extractall(self.folder)
        append = vtk.vtkAppendPolyData()
        names = ("AF_L", "CST_R", "CC_ForcepsMajor")
        for index, name in enumerate(names):
            reader = sightline.vtkSightlineTrackVisReader()
            reader.SetFileName(os.path.join(self.folder, "sub_1", f"{name}.trk"))
            reader.Update()
            data = vtk.vtkPolyData()
            data.DeepCopy(reader.GetOutput())
            cells = data.GetNumberOfCells()
            for other in names:
                flag = vtk.vtkUnsignedCharArray()
                flag.SetName("group:" + other)
                flag.SetNumberOfValues(cells)
                flag.Fill(1 if other == name else 0)
                data.GetCellData().AddArray(flag)
            bundle = vtk.vtkFloatArray()
            bundle.SetName("bundle")
            bundle.SetNumberOfValues(cells)
            bundle.Fill(index)
            data.GetCellData().AddArray(bundle)
            height = vtk.vtkFloatArray()
            height.SetName("height")
            height.SetNumberOfValues(data.GetNumberOfPoints())
            for point in range(data.GetNumberOfPoints()):
                height.SetValue(point, data.GetPoint(point)[2])
            data.GetPointData().AddArray(height)
            append.AddInputData(data)
        trx = os.path.join(self.folder, "bundles.trx")
        folder = os.path.join(self.folder, "bundles_trx")
        for path, directory in ((trx, False), (folder, True)):
            writer = sightline.vtkSightlineTRXWriter()
            writer.SetInputConnection(append.GetOutputPort())
            writer.SetFileName(path)
            writer.SetWriteToDirectory(directory)
            writer.Write()
        result, everything = self.render("trx_all", trx)
        self.assertIn("150 streamlines", result.stdout)
        result, _ = self.render("trx_directory", folder)
        self.assertIn("150 streamlines", result.stdout)
        result, one = self.render("trx_cst", trx, "--group", "CST_R", "--color", "bundle")
        self.assertIn("50 streamlines", result.stdout)
        self.assertIn("coloured by bundle (per streamline, 0 to 2)", result.stdout)
        self.assertLess(one.mean(), 0.6 * everything.mean())
        # Per-streamline colours: two groups coloured by bundle show exactly two hues, read
        # whole or streamed in pieces (each piece's groups selected, the range the whole file's).
        output = os.path.join(self.folder, "trx_two.png")
        for pieces in ("1", "5"):
            result = self.run_view(trx, "--group", "AF_L", "--group", "CST_R", "--color", "bundle",
                                   "--pieces", pieces, "--output", output, "--size", *map(str, SIZE))
            self.assertIn("coloured by bundle (per streamline, 0 to 2)", result.stdout)
            reader = vtk.vtkPNGReader()
            reader.SetFileName(output)
            reader.Update()
            rgb = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3].astype(float)
            covered = np.abs(rgb - BACKGROUND).max(axis=1) > 8
            hue = np.argmax(rgb[covered], axis=1)  # blue (bundle 0) or red (1 of 0..2: green)
            self.assertGreater(np.mean(hue == 2), 0.2)  # AF_L, bundle 0: the table's blue end
            self.assertGreater(np.mean(hue == 1), 0.2)  # CST_R, bundle 1: its green middle
            self.assertLess(np.mean(hue == 0), 0.05)    # no red: bundle 2 is not shown
        self.assertIn("2000 points streamed in 5 pieces", result.stdout)  # 100 streamlines of 20
        result, _ = self.render("trx_height", trx, "--color", "height")
        self.assertIn("coloured by height (per point", result.stdout)
        streamed, _ = self.render("trx_height_streamed", trx, "--color", "height", "--pieces", "4")
        colouring = result.stdout.split("coloured by height")[1].split(")")[0]
        self.assertIn("coloured by height" + colouring + ")", streamed.stdout)
        for pieces in ("1", "3"):
            bad = self.run_view(trx, "--group", "nope", "--pieces", pieces, "--output", output,
                                expect_ok=False)
            self.assertEqual(bad.returncode, 2)
            self.assertIn("no group 'nope' (its groups: AF_L, CC_ForcepsMajor, CST_R)", bad.stderr)
            bad = self.run_view(trx, "--color", "nope", "--pieces", pieces, "--output", output,
                                expect_ok=False)
            self.assertIn("no array 'nope' to colour by (its arrays: bundle, group:AF_L",
                          bad.stderr)
        bad = self.run_view(trx, "--pieces", "-2", "--output", output, expect_ok=False)
        self.assertIn("--pieces must be 1 or more", bad.stderr)
        bad = self.run_view(os.path.join(NIBABEL_DATA, "standard.trk"), "--group", "x",
                            "--output", output, expect_ok=False)
        self.assertIn("--group selects TRX groups; this is not a .trx", bad.stderr)

    def test_swc(self):
        result, _ = self.render("neuron", SWC, min_fill=0.4)
        self.assertIn("12 samples", result.stdout)
        self.assertIn("radii from the file", result.stdout)

    @unittest.skipUnless(shutil.which("mrconvert"), "needs MRtrix3's mrconvert")
    def test_mif_from_mrconvert(self):
        mif = os.path.join(self.folder, "func_coef.mif")
        subprocess.run(["mrconvert", "-quiet", "-force",
                        os.path.join(DIPY_FILES, "func_coef.nii.gz"), mif], check=True)
        result, covered = self.render("func_coef_mif", mif, "--basis", "dipy", "--legacy")
        self.assertIn("SH lmax 8, basis descoteaux07", result.stdout)
        # The same glyphs as from the NIfTI itself: MRtrix3 keeps the sform-only affine.
        _, reference = self.render("func_coef_nifti", os.path.join(DIPY_FILES, "func_coef.nii.gz"),
                                   "--basis", "dipy", "--legacy")
        self.assertLess((covered != reference).mean(), 0.01)

    def test_spherical_grid_vtr_and_exr_depth(self):
        source = sightline.vtkSightlineSphericalFieldSource()
        source.SetFieldToPREMDensity()
        source.SetRadiusRange(1221.5, 6371.0)
        source.SetRadialResolution(24)
        source.SetPolarResolution(16)
        source.SetAzimuthalResolution(24)
        path = os.path.join(self.folder, "earth.vtr")
        writer = vtk.vtkXMLRectilinearGridWriter()
        writer.SetInputConnection(source.GetOutputPort())
        writer.SetFileName(path)
        self.assertEqual(writer.Write(), 1)
        result, covered = self.render("earth", path)
        self.assertIn("spherical grid", result.stdout)
        exr = os.path.join(self.folder, "earth.exr")
        self.run_view(path, "--output", exr, "--size", *map(str, SIZE))
        channels = read_exr(exr)
        self.assertEqual(sorted(channels), ["A", "B", "G", "R", "Z"])
        self.assertEqual(channels["Z"].shape, (SIZE[1], SIZE[0]))
        # The PNG's covered pixels are where the EXR's depth is nearer than the background's.
        near = channels["Z"] < channels["Z"].max() - 1e-6
        self.assertGreater((near == covered).mean(), 0.97)
        colour = np.stack([channels[c] for c in "RGB"], -1) * 255
        self.assertGreater((np.abs(colour - BACKGROUND).max(axis=-1) > 8).mean(), 0.01)

    def test_window_keys_and_underlay(self):
        if not os.environ.get("DISPLAY"):
            self.skipTest("needs an X display (run under xvfb-run)")
        sh = os.path.join(DIPY_FILES, "func_coef.nii.gz")
        result = self.run_view(sh, "--basis", "dipy", "--size", *map(str, SIZE),
                               "--keys", "Up,Down,c,h,o,p,a,p",
                               "--screenshot-dir", self.folder, display=True)
        self.assertIn("[c] coronal slice", result.stdout)
        self.assertIn("[h] shadows", result.stdout)
        shots = [os.path.join(self.folder, f"sightline-view-00{i}.png") for i in (1, 2)]
        for shot in shots:
            self.assertGreater(covered_pixels(shot).mean(), 0.01, shot)
        self.assertGreater((covered_pixels(shots[0]) != covered_pixels(shots[1])).mean(), 0.01,
                           "the coronal and axial screenshots are the same")
    @unittest.skipUnless(SH_DATA, "needs the SH test data (SHData fixture)")
    def test_underlay_without_x(self):
        """--underlay with --output runs with DISPLAY unset: the grey slice is traced beneath
        the glyphs, fills the frame around them and is cut by nothing above it."""
        sh = os.path.join(SH_DATA, "small_64D_sh_descoteaux07.nii.gz")
        fa = os.path.join(SH_DATA, "small_64D_fa.nii.gz")
        _, plain = self.render("plain", sh)
        result, under = self.render("underlay", sh, "--underlay", fa)
        self.assertIn("GL-free", result.stdout)
        self.assertGreater(under.mean(), plain.mean() + 0.1)
        self.assertFalse(under[0].any() or under[-1].any(), "no background above and below")
        # The glyph pixels are the same with and without the slice beneath them: the plane lies
        # below every glyph, so it hides none.
        with_slice, without = read_png(os.path.join(self.folder, "underlay.png")), \
            read_png(os.path.join(self.folder, "plain.png"))
        glyph = covered_pixels(os.path.join(self.folder, "plain.png"))
        same = (np.abs(with_slice.astype(int) - without.astype(int)).max(axis=-1) <= 2)[glyph]
        self.assertGreater(same.mean(), 0.97)

    # -- bad input ------------------------------------------------------------------------------
    def expect_error(self, message, *arguments, output="x.png"):
        result = self.run_view(*arguments, "--output", os.path.join(self.folder, output),
                               expect_ok=False)
        self.assertEqual(result.returncode, 2, result.stdout + result.stderr)
        self.assertIn(message, result.stderr)

    def test_bad_input(self):
        text = os.path.join(self.folder, "notes.txt")
        with open(text, "w") as stream:
            stream.write("hello\n")
        self.expect_error("notes.txt: unknown file type '.txt'", text)
        self.expect_error("missing.trk: no such file", os.path.join(self.folder, "missing.trk"))
        self.expect_error("missing.nii.gz: no such file",
                          os.path.join(self.folder, "missing.nii.gz"))
        seven = os.path.join(self.folder, "seven.nii.gz")
        nib.save(nib.Nifti1Image(np.ones((3, 3, 3, 7), np.float32), np.eye(4)), seven)
        self.expect_error("seven.nii.gz: 7 components per voxel is neither an SH series", seven)
        scalar = os.path.join(self.folder, "scalar.nii.gz")
        nib.save(nib.Nifti1Image(np.ones((3, 3, 3), np.float32), np.eye(4)), scalar)
        self.expect_error("scalar.nii.gz: one value per voxel is a scalar image", scalar)
        self.expect_error("--layout fsl is for 6 components, the file has 45",
                          os.path.join(DIPY_FILES, "func_coef.nii.gz"), "--layout", "fsl")
        broken = os.path.join(self.folder, "broken.trk")
        with open(broken, "wb") as stream:
            stream.write(b"TRACK\0" + b"\1" * 100)
        self.expect_error("broken.trk: could not read it as a TrackVis .trk file", broken)
        self.expect_error("--underlay draws beneath glyphs",
                          os.path.join(NIBABEL_DATA, "standard.trk"), "--underlay", scalar)
        self.expect_error("the image must be .png or .exr",
                          os.path.join(NIBABEL_DATA, "standard.trk"), output="picture.jpg")


if __name__ == "__main__":
    unittest.main()
