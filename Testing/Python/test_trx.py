# SPDX-License-Identifier: BSD-3-Clause
"""vtkSightlineTRXReader and vtkSightlineTRXWriter against trx-python, the TRX format's
reference implementation (PyPI, installed by the TRXPython fixture), and Python's own zipfile:

- files trx-python writes (every positions dtype, stored, deflated and directory form; dpv and
  dps of several dtypes and widths, groups, dpg) read identically: positions bit for bit after
  the dtype conversion, offsets, every array;
- files our writer makes load in trx-python with the same content;
- older files with one offset per streamline (no trailing NB_VERTICES);
- real data: nibabel's test tracks and DIPY's bundles converted by our writer and by trx-python
  give the same tractogram;
- pieces (what MPI ranks ask for) concatenate to the whole;
- broken files, written with zipfile and numpy, fail with a named error, never a crash.
"""
import json
import os
import struct
import tempfile
import unittest
import zipfile

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkCommand

import sightline

from trx.trx_file_memmap import TrxFile, load, save
from nibabel.streamlines import ArraySequence

NIBABEL_DATA = "/usr/lib/python3/dist-packages/nibabel/tests/data"
BUNDLES = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip"


class Messages:
    """Errors and warnings an algorithm reports."""

    def __init__(self, algorithm):
        self.errors, self.warnings = [], []

        @calldata_type(VTK_STRING)
        def on_error(caller, event, message):
            self.errors.append(message)

        @calldata_type(VTK_STRING)
        def on_warning(caller, event, message):
            self.warnings.append(message)

        algorithm.AddObserver(vtkCommand.ErrorEvent, on_error)
        algorithm.AddObserver(vtkCommand.WarningEvent, on_warning)


def read(path, piece=None):
    reader = sightline.vtkSightlineTRXReader()
    reader.SetFileName(path)
    messages = Messages(reader)
    if piece is None:
        reader.Update()
    else:
        reader.UpdatePiece(piece[0], piece[1], 0)
    return reader.GetOutput(), messages


def lines_of(output):
    """Offsets of the output's polylines (start of each and the end)."""
    lines = output.GetLines()
    return vtk_to_numpy(lines.GetOffsetsArray()).astype(np.int64)


def arrays(field):
    return {field.GetArrayName(i): vtk_to_numpy(field.GetArray(i))
            for i in range(field.GetNumberOfArrays())}


def column(values):
    return values.reshape(len(values), -1)


def sequence(lengths, rows):
    """An ArraySequence with the given lengths, empty streamlines included (nibabel's
    constructor drops empty arrays)."""
    result = ArraySequence()
    result._data = rows
    result._offsets = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.uint64)
    result._lengths = np.asarray(lengths, dtype=np.uint32)
    return result


def make_trx(rng, positions_dtype, count=40, short=True):
    lengths = rng.integers(2, 25, size=count)
    if short:
        lengths[3] = 0  # an empty streamline, in group AF_R
        lengths[9] = 1  # a lone vertex
    vertices = int(lengths.sum())
    trx = TrxFile(nb_vertices=vertices, nb_streamlines=count)
    trx.streamlines = sequence(lengths, (rng.normal(size=(vertices, 3)) * 50).astype(positions_dtype))
    trx.header["VOXEL_TO_RASMM"] = [[1.25, 0, 0, -90], [0, 1.25, 0, -126], [0, 0, 1.25, -72],
                                    [0, 0, 0, 1]]
    trx.header["DIMENSIONS"] = [145, 174, 145]
    trx.data_per_vertex["fa"] = sequence(lengths, rng.random((vertices, 1)).astype(np.float32))
    trx.data_per_vertex["rgb"] = sequence(
        lengths, rng.integers(0, 255, size=(vertices, 3)).astype(np.uint8))
    trx.data_per_vertex["curv"] = sequence(
        lengths, rng.normal(size=(vertices, 1)).astype(np.float16))
    trx.data_per_streamline["length"] = lengths.astype(np.uint16).reshape(-1, 1)
    trx.data_per_streamline["mean"] = rng.normal(size=(count, 3)).astype(np.float64)
    trx.data_per_streamline["label"] = rng.integers(-5, 5, size=(count, 1)).astype(np.int32)
    trx.groups["CST_L"] = np.array([0, 5, 7, 39], dtype=np.uint32)
    trx.groups["AF_R"] = np.array([2, 3], dtype=np.uint64)
    trx.data_per_group["CST_L"] = {"colour": np.array([[1.0, 0.5, 0.25]], dtype=np.float32)}
    return trx


class Reference(unittest.TestCase):
    """Our reader and writer against trx-python."""

    def check_same(self, output, reference, path):
        data = reference.streamlines._data
        points = vtk_to_numpy(output.GetPoints().GetData())
        expected_type = np.float64 if data.dtype == np.float64 else np.float32
        self.assertEqual(points.dtype, expected_type, path)
        # Bit for bit: float16 widens exactly.
        self.assertTrue(np.array_equal(points, data.astype(expected_type)), path)
        # Streamlines of fewer than two vertices are no cells (a VTK line needs two).
        lengths = np.asarray(reference.streamlines._lengths)
        kept = np.flatnonzero(lengths >= 2)
        offsets = lines_of(output)
        self.assertEqual(len(offsets), len(kept) + 1)
        self.assertTrue(np.array_equal(np.diff(offsets), lengths[kept]), path)
        # Each cell's points are its streamline's vertices, in order.
        ids = vtk_to_numpy(output.GetLines().GetConnectivityArray())
        expected = np.concatenate([np.arange(start, start + n) for start, n in zip(
            np.asarray(reference.streamlines._offsets)[kept], lengths[kept])])
        self.assertTrue(np.array_equal(ids, expected), path)
        point_data = arrays(output.GetPointData())
        self.assertEqual(set(point_data), set(reference.data_per_vertex))
        for name, values in reference.data_per_vertex.items():
            self.assertTrue(np.array_equal(column(point_data[name]), values._data), (path, name))
        cell_data = arrays(output.GetCellData())
        self.assertEqual(set(cell_data), set(reference.data_per_streamline) |
                         {"group:" + g for g in reference.groups})
        for name, values in reference.data_per_streamline.items():
            self.assertTrue(np.array_equal(column(cell_data[name]), values[kept]), (path, name))
        for name, members in reference.groups.items():
            flags = np.zeros(len(lengths), bool)
            flags[members] = True
            self.assertTrue(np.array_equal(cell_data["group:" + name] != 0, flags[kept]), name)
        field = arrays(output.GetFieldData())
        for group, data in reference.data_per_group.items():
            for name, values in data.items():
                self.assertTrue(np.array_equal(field[f"dpg:{group}:{name}"].ravel(),
                                               np.asarray(values).ravel()))
        self.assertTrue(np.allclose(field["VOXEL_TO_RASMM"].reshape(4, 4),
                                    reference.header["VOXEL_TO_RASMM"]))
        self.assertTrue(np.array_equal(field["DIMENSIONS"], reference.header["DIMENSIONS"]))

    def test_files_trx_python_writes(self):
        rng = np.random.default_rng(7)
        with tempfile.TemporaryDirectory() as folder:
            for dtype in (np.float16, np.float32, np.float64):
                trx = make_trx(rng, dtype)
                for form, compression in (("stored", zipfile.ZIP_STORED),
                                          ("deflated", zipfile.ZIP_DEFLATED),
                                          ("directory", None)):
                    path = os.path.join(folder, f"{np.dtype(dtype).name}_{form}" +
                                        ("" if compression is None else ".trx"))
                    self.assertEqual(list(trx.streamlines._lengths[[3, 9]]), [0, 1])
                    if compression is None:
                        save(trx, path)
                    else:
                        save(trx, path, compression_standard=compression)
                    self.assertTrue(sightline.vtkSightlineTRXReader.CanReadFile(path), path)
                    output, messages = read(path)
                    self.assertEqual(messages.errors, [], path)
                    self.assertTrue(any("2 streamlines with fewer than two vertices are left out "
                                        "(the first is number 3)" in w for w in messages.warnings),
                                    path)
                    reference = load(path)
                    self.check_same(output, reference, path)
                    reference.close()

    def test_writer_files_load_in_trx_python(self):
        rng = np.random.default_rng(11)
        with tempfile.TemporaryDirectory() as folder:
            source = os.path.join(folder, "source.trx")
            save(make_trx(rng, np.float32, short=False), source)
            output, _ = read(source)
            for name, settings in (("stored.trx", {}), ("deflated.trx", {"Compress": True}),
                                   ("directory", {"WriteToDirectory": True}),
                                   ("half.trx", {"PositionsType": 1})):
                path = os.path.join(folder, name)
                writer = sightline.vtkSightlineTRXWriter()
                for key, value in settings.items():
                    getattr(writer, "Set" + key)(value)
                messages = Messages(writer)
                writer.SetInputData(output)
                writer.SetFileName(path)
                writer.Write()
                self.assertEqual(messages.errors, [], name)
                if not settings.get("WriteToDirectory"):
                    with zipfile.ZipFile(path) as archive:
                        method = zipfile.ZIP_DEFLATED if settings.get("Compress") else \
                            zipfile.ZIP_STORED
                        self.assertTrue(all(i.compress_type == method
                                            for i in archive.infolist()))
                        self.assertIsNone(archive.testzip())  # every CRC right
                written, original = load(path), load(source)
                if name == "half.trx":
                    self.assertEqual(written.streamlines._data.dtype, np.float16)
                    self.assertTrue(np.array_equal(
                        written.streamlines._data,
                        original.streamlines._data.astype(np.float16)))
                else:
                    self.check_same(read(path)[0], original, path)
                    self.assertTrue(np.array_equal(written.streamlines._data,
                                                   original.streamlines._data))
                self.assertTrue(np.array_equal(written.streamlines._offsets,
                                               original.streamlines._offsets))
                for key, values in original.data_per_vertex.items():
                    self.assertTrue(np.array_equal(written.data_per_vertex[key]._data,
                                                   values._data), key)
                    self.assertEqual(written.data_per_vertex[key]._data.dtype,
                                     np.float32 if values._data.dtype == np.float16
                                     else values._data.dtype)
                for key, values in original.data_per_streamline.items():
                    self.assertTrue(np.array_equal(written.data_per_streamline[key], values))
                    self.assertEqual(written.data_per_streamline[key].dtype, values.dtype)
                for key, values in original.groups.items():
                    self.assertTrue(np.array_equal(np.sort(written.groups[key]), np.sort(values)))
                self.assertTrue(np.array_equal(
                    written.data_per_group["CST_L"]["colour"].ravel(),
                    original.data_per_group["CST_L"]["colour"].ravel()))
                self.assertTrue(np.allclose(written.header["VOXEL_TO_RASMM"],
                                            original.header["VOXEL_TO_RASMM"]))
                written.close()
                original.close()

    def test_older_files_with_one_offset_per_streamline(self):
        rng = np.random.default_rng(3)
        with tempfile.TemporaryDirectory() as folder:
            current = os.path.join(folder, "current.trx")
            save(make_trx(rng, np.float32), current)
            older = os.path.join(folder, "older.trx")
            with zipfile.ZipFile(current) as source, zipfile.ZipFile(older, "w") as target:
                for info in source.infolist():
                    data = source.read(info)
                    if info.filename.startswith("offsets."):
                        dtype = np.dtype(info.filename.split(".")[-1])
                        data = np.frombuffer(data, dtype)[:-1].tobytes()
                    target.writestr(info.filename, data)
            whole, messages = read(older)
            self.assertEqual(messages.errors, [])
            reference, _ = read(current)
            self.assertTrue(np.array_equal(lines_of(whole), lines_of(reference)))
            self.assertTrue(np.array_equal(vtk_to_numpy(whole.GetPoints().GetData()),
                                           vtk_to_numpy(reference.GetPoints().GetData())))

    def test_pieces_concatenate_to_the_whole(self):
        rng = np.random.default_rng(5)
        with tempfile.TemporaryDirectory() as folder:
            for compression in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
                path = os.path.join(folder, f"pieces{compression}.trx")
                save(make_trx(rng, np.float16, count=101), path, compression_standard=compression)
                whole, _ = read(path)
                for pieces in (2, 3, 7):
                    points, starts, fa, mean, cst = [], [0], [], [], []
                    for p in range(pieces):
                        part, messages = read(path, (p, pieces))
                        self.assertEqual(messages.errors, [])
                        self.assertLess(part.GetNumberOfPoints(), whole.GetNumberOfPoints())
                        points.append(vtk_to_numpy(part.GetPoints().GetData()))
                        starts.extend((lines_of(part)[1:] + starts[-1]).tolist())
                        fa.append(vtk_to_numpy(part.GetPointData().GetArray("fa")))
                        mean.append(vtk_to_numpy(part.GetCellData().GetArray("mean")))
                        cst.append(vtk_to_numpy(part.GetCellData().GetArray("group:CST_L")))
                    self.assertTrue(np.array_equal(np.concatenate(points),
                                                   vtk_to_numpy(whole.GetPoints().GetData())))
                    self.assertTrue(np.array_equal(starts, lines_of(whole)))
                    for name, parts in (("fa", fa), ("mean", mean)):
                        field = whole.GetPointData() if name == "fa" else whole.GetCellData()
                        self.assertTrue(np.array_equal(np.concatenate(parts),
                                                       vtk_to_numpy(field.GetArray(name))))
                    self.assertTrue(np.array_equal(
                        np.concatenate(cst),
                        vtk_to_numpy(whole.GetCellData().GetArray("group:CST_L"))))


class RealData(unittest.TestCase):
    """Real tractograms converted by our writer and by trx-python agree."""

    def convert_both(self, path, folder):
        import nibabel as nib
        reader = (sightline.vtkSightlineTCKReader() if path.endswith(".tck")
                  else sightline.vtkSightlineTrackVisReader())
        reader.SetFileName(path)
        ours = os.path.join(folder, "ours.trx")
        writer = sightline.vtkSightlineTRXWriter()
        writer.SetInputConnection(reader.GetOutputPort())
        writer.SetFileName(ours)
        writer.Write()
        theirs = os.path.join(folder, "theirs.trx")
        tractogram = nib.streamlines.load(path).tractogram
        # .tck carries no reference space: a 1 mm identity image stands in (points are RAS mm).
        reference = path if path.endswith(".trk") else nib.Nifti1Image(
            np.zeros((1, 1, 1), np.uint8), np.eye(4))
        save(TrxFile.from_tractogram(tractogram, reference), theirs)
        a, b = load(ours), load(theirs)
        self.assertEqual(len(a.streamlines), len(b.streamlines), path)
        self.assertTrue(np.array_equal(a.streamlines._lengths, b.streamlines._lengths), path)
        if len(b.streamlines):
            # Both float32 RAS mm; ours comes through the reader's own voxel-to-RAS arithmetic.
            scale = 1 + np.abs(b.streamlines._data).max()
            self.assertLess(np.abs(a.streamlines._data - b.streamlines._data).max(), 1e-5 * scale)
        for key, values in b.data_per_vertex.items():
            self.assertTrue(np.allclose(a.data_per_vertex[key]._data, values._data), key)
        for key, values in b.data_per_streamline.items():
            self.assertTrue(np.allclose(a.data_per_streamline[key], values), key)
        # And our reader reads trx-python's conversion exactly as trx-python does.
        output, messages = read(theirs)
        self.assertEqual(messages.errors, [])
        if len(b.streamlines):
            self.assertTrue(np.array_equal(vtk_to_numpy(output.GetPoints().GetData()),
                                           b.streamlines._data))
        a.close()
        b.close()

    def test_nibabel_tracks(self):
        for name in ("standard.trk", "complex.trk", "standard.tck", "empty.trk"):
            with tempfile.TemporaryDirectory() as folder:
                self.convert_both(os.path.join(NIBABEL_DATA, name), folder)

    def test_dipy_bundles(self):
        with tempfile.TemporaryDirectory() as folder:
            with zipfile.ZipFile(BUNDLES) as archive:
                archive.extractall(folder)
            for bundle in ("AF_L", "CST_R", "CC_ForcepsMajor"):
                with tempfile.TemporaryDirectory() as work:
                    self.convert_both(os.path.join(folder, "sub_1", f"{bundle}.trk"), work)


def minimal_members(vertices=6, offsets=(0, 2, 6)):
    positions = np.arange(vertices * 3, dtype=np.float32).reshape(-1, 3)
    return {
        "header.json": json.dumps({"NB_VERTICES": vertices, "NB_STREAMLINES": len(offsets) - 1,
                                   "DIMENSIONS": [1, 1, 1],
                                   "VOXEL_TO_RASMM": np.eye(4).tolist()}).encode(),
        "positions.3.float32": positions.tobytes(),
        "offsets.uint64": np.array(offsets, dtype=np.uint64).tobytes(),
    }


def write_zip(path, members, compression=zipfile.ZIP_STORED):
    with zipfile.ZipFile(path, "w", compression=compression) as archive:
        for name, data in members.items():
            archive.writestr(name, data)


class BadFiles(unittest.TestCase):
    """Each broken file fails with an error naming what is wrong, and no output."""

    def expect_error(self, path, words):
        output, messages = read(path)
        self.assertTrue(messages.errors, path)
        text = " ".join(messages.errors)
        for word in words:
            self.assertIn(word, text, path)
        self.assertEqual(output.GetNumberOfPoints(), 0, path)

    def test_inconsistent_members(self):
        cases = {
            "no_header": ({"header.json": None}, ["no header.json"]),
            "not_json": ({"header.json": b"{NB_VERTICES: 6"}, ["not a JSON object"]),
            "no_count": ({"header.json": json.dumps({"NB_VERTICES": 6}).encode()},
                         ["NB_STREAMLINES"]),
            "negative": ({"header.json": json.dumps({"NB_VERTICES": -6,
                                                     "NB_STREAMLINES": 2}).encode()},
                         ["NB_VERTICES"]),
            "bad_matrix": ({"header.json": json.dumps({"NB_VERTICES": 6, "NB_STREAMLINES": 2,
                                                       "VOXEL_TO_RASMM": [[1, 0], [0, 1]]}
                                                      ).encode()}, ["VOXEL_TO_RASMM"]),
            "short_positions": ({"positions.3.float32": np.zeros(15, np.float32).tobytes()},
                                ["positions.3.float32", "NB_VERTICES"]),
            "two_columns": ({"positions.3.float32": None,
                             "positions.2.float32": np.zeros(12, np.float32).tobytes()},
                            ["positions must be 3 columns"]),
            "unknown_dtype": ({"dpv/fa.float128": np.zeros(12, np.float64).tobytes()},
                              ["unknown dtype", "float128"]),
            "bad_columns": ({"dps/x.0.float32": b""}, ["bad column count"]),
            "decreasing": ({"offsets.uint64": np.array([0, 4, 2], np.uint64).tobytes()},
                           ["smaller than the one before"]),
            "past_end": ({"offsets.uint64": np.array([0, 2, 9], np.uint64).tobytes()},
                         ["past NB_VERTICES"]),
            "wrong_end": ({"offsets.uint64": np.array([0, 2, 5], np.uint64).tobytes()},
                          ["not at NB_VERTICES"]),
            "not_zero": ({"offsets.uint64": np.array([1, 2, 6], np.uint64).tobytes()},
                         ["does not start at 0"]),
            "offset_count": ({"offsets.uint64": np.array([0], np.uint64).tobytes()},
                             ["offsets for NB_STREAMLINES"]),
            "float_offsets": ({"offsets.uint64": None,
                               "offsets.float32": np.array([0, 2, 6], np.float32).tobytes()},
                              ["offsets must be one column of integers"]),
            "negative_offset": ({"offsets.uint64": None,
                                 "offsets.int32": np.array([0, -2, 6], np.int32).tobytes()},
                                ["negative"]),
            "dpv_rows": ({"dpv/fa.float32": np.zeros(5, np.float32).tobytes()},
                         ["dpv/fa.float32", "NB_VERTICES"]),
            "dps_rows": ({"dps/len.float32": np.zeros(3, np.float32).tobytes()},
                         ["dps/len.float32", "NB_STREAMLINES"]),
            "ragged": ({"dpv/rgb.3.uint8": np.zeros(17, np.uint8).tobytes()},
                       ["not whole rows"]),
            "group_index": ({"groups/CST.uint32": np.array([0, 2], np.uint32).tobytes()},
                            ["groups/CST.uint32", "streamline 2"]),
            "float_group": ({"groups/CST.float32": np.array([0], np.float32).tobytes()},
                            ["integer streamline indices"]),
            "undeclared_group": ({"dpg/AF/mean.float32": np.zeros(1, np.float32).tobytes()},
                                 ["undeclared group"]),
            "not_finite": ({"positions.3.float32": np.array(
                [0, 0, 0, 1, 1, 1, 2, np.nan, 2, 3, 3, 3, 4, 4, 4, 5, 5, 5],
                np.float32).tobytes()}, ["vertex 2 is not finite"]),
            "duplicate_dpv": ({"dpv/fa.float32": np.zeros(6, np.float32).tobytes(),
                               "dpv/fa.float64": np.zeros(6, np.float64).tobytes()},
                              ["two members named"]),
        }
        with tempfile.TemporaryDirectory() as folder:
            for name, (changes, words) in cases.items():
                members = minimal_members()
                for member, data in changes.items():
                    if data is None:
                        members.pop(member, None)
                    else:
                        members[member] = data
                path = os.path.join(folder, name + ".trx")
                write_zip(path, members)
                with self.subTest(name):
                    self.expect_error(path, words)

    def test_zip_entries_that_are_not_what_they_claim(self):
        with tempfile.TemporaryDirectory() as folder:
            good = os.path.join(folder, "good.trx")
            write_zip(good, minimal_members(), zipfile.ZIP_DEFLATED)
            self.assertEqual(read(good)[1].errors, [])
            data = bytearray(open(good, "rb").read())
            end = data.rfind(b"PK\x05\x06")
            directory = struct.unpack_from("<I", data, end + 16)[0]
            entries = []
            at = directory
            while data[at:at + 4] == b"PK\x01\x02":
                name_length, extra, comment = struct.unpack_from("<HHH", data, at + 28)
                name = bytes(data[at + 46:at + 46 + name_length]).decode()
                entries.append((name, at))
                at += 46 + name_length + extra + comment
            positions = dict(entries)["positions.3.float32"]

            def variant(label, edit):
                copy = bytearray(data)
                edit(copy)
                path = os.path.join(folder, label + ".trx")
                open(path, "wb").write(copy)
                return path

            # A zip bomb's claim: 2^32-1 bytes from a few dozen deflated ones.
            bomb = variant("bomb", lambda d: struct.pack_into("<I", d, positions + 24, 0xFFFFFFF0))
            self.expect_error(bomb, ["more than deflate can hold"])
            # Declares more bytes than its deflate stream holds (and the header agrees).
            bigger = minimal_members(vertices=9, offsets=(0, 2, 9))
            bigger["positions.3.float32"] = bigger["positions.3.float32"][:72]
            lying = os.path.join(folder, "lying.trx")
            write_zip(lying, bigger, zipfile.ZIP_DEFLATED)
            raw = bytearray(open(lying, "rb").read())
            end2 = raw.rfind(b"PK\x05\x06")
            at = struct.unpack_from("<I", raw, end2 + 16)[0]
            while raw[at:at + 4] == b"PK\x01\x02":
                name_length, extra, comment = struct.unpack_from("<HHH", raw, at + 28)
                if bytes(raw[at + 46:at + 46 + name_length]) == b"positions.3.float32":
                    struct.pack_into("<I", raw, at + 24, 108)
                at += 46 + name_length + extra + comment
            open(lying, "wb").write(raw)
            self.expect_error(lying, ["inflates to 72 bytes"])
            # Local header naming another member.
            local = struct.unpack_from("<I", data, positions + 42)[0]
            renamed = variant("renamed", lambda d: d.__setitem__(slice(local + 30, local + 31), b"q"))
            self.expect_error(renamed, ["local header names another member"])
            # Encrypted, and an unsupported method.
            self.expect_error(variant("encrypted", lambda d: struct.pack_into(
                "<H", d, positions + 8, 1)), ["encrypted"])
            self.expect_error(variant("method", lambda d: struct.pack_into(
                "<H", d, positions + 10, 12)), ["compression method 12"])
            # Corrupt deflate data.
            offset = local + 30 + len("positions.3.float32")
            self.expect_error(variant("corrupt", lambda d: d.__setitem__(
                slice(offset, offset + 4), b"\xff\xff\xff\xff")), ["not valid deflate data"])
            # Cut short: no central directory.
            self.expect_error(variant("cut", lambda d: d.__delitem__(slice(end - 10, None))),
                              ["no zip end-of-central-directory"])

    def test_unknown_members_are_skipped_with_a_warning(self):
        with tempfile.TemporaryDirectory() as folder:
            members = minimal_members()
            members["notes/readme.float32"] = np.zeros(2, np.float32).tobytes()
            path = os.path.join(folder, "extra.trx")
            write_zip(path, members)
            output, messages = read(path)
            self.assertEqual(messages.errors, [])
            self.assertTrue(any("notes/readme.float32" in w for w in messages.warnings))
            self.assertEqual(output.GetNumberOfPoints(), 6)
            self.assertEqual(output.GetNumberOfCells(), 2)


if __name__ == "__main__":
    unittest.main()
