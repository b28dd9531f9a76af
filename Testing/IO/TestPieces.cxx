// SPDX-License-Identifier: BSD-3-Clause
// Piece requests (what each pvbatch/pvserver rank asks for): for n = 1, 2, 3, 4 and more pieces
// than streamlines, the .tck and .trk readers' pieces, in order, are exactly the whole output
// (points, lines, point and cell arrays), disjoint, each with its share of the streamlines;
// the .mif reader's pieces and sub-extents are exactly the corresponding part of the whole
// image; the SWC reader puts the whole file in piece 0. Real files: nibabel's standard.trk and
// standard.tck, DIPY's minimal_bundles (inflated here from the zip), the SHData fixture's
// .mif/.mif.gz; plus small files written here (scalars and properties, no counts, wrong counts,
// Float64 big-endian, a 4-D image with a scrambled layout).
#include "vtkSightlineMIFReader.h"
#include "vtkSightlineSWCReader.h"
#include "vtkSightlineTCKReader.h"
#include "vtkSightlineTrackVisReader.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include "vtk_zlib.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace
{
const std::string TempDir = SIGHTLINE_TEST_TEMP_DIR;
const std::string DataDir = SIGHTLINE_SH_DATA_DIR;
const std::string Nibabel = "/usr/lib/python3/dist-packages/nibabel/tests/data/";
const std::string Bundles = "/usr/lib/python3/dist-packages/dipy/data/files/minimal_bundles.zip";

std::string ReadFile(const std::string& path)
{
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

std::string WriteFile(const std::string& name, const std::string& bytes)
{
  const std::string path = TempDir + "/" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

template <class T>
void Put(std::string& bytes, T value, bool bigEndian = false)
{
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (bigEndian)
    std::reverse(raw, raw + sizeof(T)); // the test machine is little-endian (x86-64)
  bytes.append(raw, sizeof(T));
}

/// Counts warnings so that tests can say none are expected.
class Messages : public vtkCommand
{
public:
  static Messages* New() { return new Messages; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    (event == vtkCommand::ErrorEvent ? errors : warnings) += static_cast<const char*>(data);
  }
  std::string errors, warnings;
};

vtkSmartPointer<vtkPolyData> ReadPiece(vtkAlgorithm* reader, int piece, int pieces)
{
  reader->UpdatePiece(piece, pieces, 0);
  auto copy = vtkSmartPointer<vtkPolyData>::New();
  copy->DeepCopy(vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0)));
  return copy;
}

/// Tuples [from, from + count) of `whole` equal `part`'s, value for value.
void ExpectSameTuples(vtkDataArray* whole, vtkDataArray* part, vtkIdType from, const std::string& what)
{
  ASSERT_NE(part, nullptr) << what;
  ASSERT_EQ(part->GetNumberOfComponents(), whole->GetNumberOfComponents()) << what;
  ASSERT_LE(from + part->GetNumberOfTuples(), whole->GetNumberOfTuples()) << what;
  for (vtkIdType t = 0; t < part->GetNumberOfTuples(); ++t)
    for (int c = 0; c < part->GetNumberOfComponents(); ++c)
      ASSERT_EQ(part->GetComponent(t, c), whole->GetComponent(from + t, c)) << what << " tuple " << t;
}

/// For n = 1..4 and n > the number of streamlines: the pieces, in order, are the whole output,
/// and piece p holds streamlines [p N / n, (p + 1) N / n).
void ExpectPiecesMakeTheWhole(vtkAlgorithm* reader, const std::string& what, bool exactShares = true)
{
  const vtkSmartPointer<vtkPolyData> whole = ReadPiece(reader, 0, 1);
  const vtkIdType cells = whole->GetNumberOfCells();
  ASSERT_GT(cells, 0) << what;
  vtkNew<vtkIdList> wholeIds, pieceIds;
  for (const int pieces : { 1, 2, 3, 4, static_cast<int>(cells) + 3 })
  {
    const std::string label = what + ", " + std::to_string(pieces) + " pieces";
    vtkIdType pointsBefore = 0, cellsBefore = 0;
    for (int p = 0; p < pieces; ++p)
    {
      const std::string at = label + ", piece " + std::to_string(p);
      const vtkSmartPointer<vtkPolyData> piece = ReadPiece(reader, p, pieces);
      const vtkIdType share = cells * (p + 1) / pieces - cells * p / pieces;
      if (exactShares)
      {
        EXPECT_EQ(piece->GetNumberOfCells(), share) << at;
      }
      ASSERT_LE(cellsBefore + piece->GetNumberOfCells(), cells) << at;
      ASSERT_LE(pointsBefore + piece->GetNumberOfPoints(), whole->GetNumberOfPoints()) << at;
      for (vtkIdType k = 0; k < piece->GetNumberOfPoints(); ++k)
      {
        double a[3], b[3];
        piece->GetPoint(k, a);
        whole->GetPoint(pointsBefore + k, b);
        ASSERT_TRUE(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) << at << " point " << k;
      }
      for (vtkIdType c = 0; c < piece->GetNumberOfCells(); ++c)
      {
        piece->GetLines()->GetCellAtId(c, pieceIds);
        whole->GetLines()->GetCellAtId(cellsBefore + c, wholeIds);
        ASSERT_EQ(pieceIds->GetNumberOfIds(), wholeIds->GetNumberOfIds()) << at << " line " << c;
        for (vtkIdType i = 0; i < pieceIds->GetNumberOfIds(); ++i)
          ASSERT_EQ(pieceIds->GetId(i) + pointsBefore, wholeIds->GetId(i)) << at << " line " << c;
      }
      ASSERT_EQ(piece->GetPointData()->GetNumberOfArrays(), whole->GetPointData()->GetNumberOfArrays()) << at;
      ASSERT_EQ(piece->GetCellData()->GetNumberOfArrays(), whole->GetCellData()->GetNumberOfArrays()) << at;
      for (int i = 0; i < whole->GetPointData()->GetNumberOfArrays(); ++i)
      {
        vtkDataArray* array = whole->GetPointData()->GetArray(i);
        ExpectSameTuples(array, piece->GetPointData()->GetArray(array->GetName()), pointsBefore,
          at + " point array " + array->GetName());
        EXPECT_EQ(piece->GetPointData()->GetArray(array->GetName())->GetNumberOfTuples(),
          piece->GetNumberOfPoints());
      }
      for (int i = 0; i < whole->GetCellData()->GetNumberOfArrays(); ++i)
      {
        vtkDataArray* array = whole->GetCellData()->GetArray(i);
        ExpectSameTuples(array, piece->GetCellData()->GetArray(array->GetName()), cellsBefore,
          at + " cell array " + array->GetName());
        EXPECT_EQ(piece->GetCellData()->GetArray(array->GetName())->GetNumberOfTuples(),
          piece->GetNumberOfCells());
      }
      pointsBefore += piece->GetNumberOfPoints();
      cellsBefore += piece->GetNumberOfCells();
    }
    // Consecutive runs that add up to the whole: disjoint, and nothing missing.
    EXPECT_EQ(pointsBefore, whole->GetNumberOfPoints()) << label;
    EXPECT_EQ(cellsBefore, cells) << label;
  }
  // Asking for the whole again after pieces gives the whole again.
  EXPECT_EQ(ReadPiece(reader, 0, 1)->GetNumberOfPoints(), whole->GetNumberOfPoints()) << what;
}

/// The files of a zip archive (deflated or stored), inflated with zlib: name -> bytes.
std::vector<std::pair<std::string, std::string>> Unzip(const std::string& zip)
{
  std::vector<std::pair<std::string, std::string>> files;
  std::size_t at = 0;
  auto u16 = [&](std::size_t i) { return unsigned(std::uint8_t(zip[i])) | unsigned(std::uint8_t(zip[i + 1])) << 8; };
  while (at != std::string::npos && at + 30 <= zip.size() && zip.compare(at, 4, "PK\x03\x04") == 0)
  {
    const unsigned method = u16(at + 8), nameLength = u16(at + 26), extraLength = u16(at + 28);
    const std::string name = zip.substr(at + 30, nameLength);
    std::size_t data = at + 30 + nameLength + extraLength;
    std::string out;
    z_stream stream;
    std::memset(&stream, 0, sizeof(stream));
    EXPECT_EQ(method == 8 ? inflateInit2(&stream, -15) : Z_OK, Z_OK);
    if (method == 8)
    {
      stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(zip.data() + data));
      stream.avail_in = static_cast<uInt>(zip.size() - data);
      int status = Z_OK;
      char buffer[1 << 15];
      while (status == Z_OK)
      {
        stream.next_out = reinterpret_cast<Bytef*>(buffer);
        stream.avail_out = sizeof(buffer);
        status = inflate(&stream, Z_NO_FLUSH);
        out.append(buffer, sizeof(buffer) - stream.avail_out);
      }
      EXPECT_EQ(status, Z_STREAM_END) << name;
      data += stream.total_in;
      inflateEnd(&stream);
    }
    else
    {
      // Stored: the local header's size (DIPY's zip deflates its files; directories are empty).
      const std::size_t size = u16(at + 18) | std::size_t(u16(at + 20)) << 16;
      out = zip.substr(data, size);
      data += size;
    }
    if (!name.empty() && name.back() != '/')
      files.emplace_back(name, out);
    at = zip.find("PK\x03\x04", data);
  }
  return files;
}

/// A TrackVis file of `count` streamlines of 1 + (s * 7) % 5 points with two scalars and one
/// property; n_count is `headerCount`.
std::string MakeTRK(int count, int headerCount, bool bigEndian)
{
  std::string h(1000, '\0');
  std::memcpy(&h[0], "TRACK", 5);
  auto put = [&](std::size_t at, auto value) {
    std::string bytes;
    Put(bytes, value, bigEndian);
    std::memcpy(&h[at], bytes.data(), bytes.size());
  };
  for (int a = 0; a < 3; ++a)
  {
    put(6 + 2 * a, std::int16_t(20));
    put(12 + 4 * a, float(1.5));
  }
  put(36, std::int16_t(2));
  std::memcpy(&h[38], "fa", 2);
  std::memcpy(&h[58], "md", 2);
  put(238, std::int16_t(1));
  std::memcpy(&h[240], "length", 6);
  for (int i = 0; i < 4; ++i)
    put(440 + 4 * (4 * i + i), float(i == 3 ? 1.0 : 1.5));
  std::memcpy(&h[948], "LAS", 3);
  put(988, std::int32_t(headerCount));
  put(992, std::int32_t(2));
  put(996, std::int32_t(1000));
  std::string body;
  for (int s = 0; s < count; ++s)
  {
    const int points = 1 + (s * 7) % 5;
    Put(body, std::int32_t(points), bigEndian);
    for (int k = 0; k < points; ++k)
    {
      for (int a = 0; a < 3; ++a)
        Put(body, float(s + 0.25 * k + 0.125 * a), bigEndian);
      Put(body, float(1000 * s + k), bigEndian);
      Put(body, float(-s - 0.5 * k), bigEndian);
    }
    Put(body, float(s * 3.5), bigEndian);
  }
  return h + body;
}

/// A .tck file of `count` streamlines (1 + s % 4 points); `countLine` goes into the header.
std::string MakeTCK(int count, const std::string& countLine, bool doubles, bool bigEndian)
{
  std::string data;
  auto triplet = [&](double x, double y, double z) {
    for (double v : { x, y, z })
      doubles ? Put(data, v, bigEndian) : Put(data, float(v), bigEndian);
  };
  for (int s = 0; s < count; ++s)
  {
    for (int k = 0; k <= s % 4; ++k)
      triplet(s, k * 0.5, -s - k);
    triplet(NAN, NAN, NAN);
  }
  triplet(INFINITY, INFINITY, INFINITY);
  const std::string type = std::string(doubles ? "Float64" : "Float32") + (bigEndian ? "BE" : "LE");
  std::string header = "mrtrix tracks\n" + countLine + "datatype: " + type + "\nfile: . ";
  const std::size_t offset = header.size() + 16;
  header += std::to_string(offset) + "\nEND\n";
  header.resize(offset, '\n');
  return header + data;
}
} // namespace

TEST(TrackPieces, NibabelStandardTrk)
{
  const std::string path = Nibabel + "standard.trk";
  if (!std::ifstream(path))
    GTEST_SKIP() << path << " is not installed";
  vtkNew<vtkSightlineTrackVisReader> reader;
  reader->SetFileName(path.c_str());
  ExpectPiecesMakeTheWhole(reader, "standard.trk");
  // n_count 0 (unknown): the streamlines are counted by a scan.
  std::string bytes = ReadFile(path);
  const std::int32_t zero = 0;
  std::memcpy(&bytes[988], &zero, 4);
  vtkNew<vtkSightlineTrackVisReader> unknown;
  unknown->SetFileName(WriteFile("standard-no-count.trk", bytes).c_str());
  ExpectPiecesMakeTheWhole(unknown, "standard.trk with n_count 0");
  EXPECT_EQ(ReadPiece(unknown, 0, 1)->GetNumberOfCells(), 120);
}

TEST(TrackPieces, NibabelStandardTck)
{
  const std::string path = Nibabel + "standard.tck";
  if (!std::ifstream(path))
    GTEST_SKIP() << path << " is not installed";
  vtkNew<vtkSightlineTCKReader> reader;
  reader->SetFileName(path.c_str());
  ExpectPiecesMakeTheWhole(reader, "standard.tck");
  // Without the count entry (renamed, same length): counted by a scan.
  std::string bytes = ReadFile(path);
  const std::size_t count = bytes.find("\ncount:");
  ASSERT_NE(count, std::string::npos);
  bytes.replace(count + 1, 5, "xount");
  vtkNew<vtkSightlineTCKReader> unknown;
  unknown->SetFileName(WriteFile("standard-no-count.tck", bytes).c_str());
  ExpectPiecesMakeTheWhole(unknown, "standard.tck without count");
  EXPECT_EQ(ReadPiece(unknown, 0, 1)->GetNumberOfCells(), 120);
}

TEST(TrackPieces, DipyBundles)
{
  if (!std::ifstream(Bundles))
    GTEST_SKIP() << Bundles << " is not installed";
  const auto files = Unzip(ReadFile(Bundles));
  ASSERT_EQ(files.size(), 15u);
  for (const auto& [name, bytes] : files)
  {
    std::string flat = name;
    std::replace(flat.begin(), flat.end(), '/', '-');
    vtkNew<vtkSightlineTrackVisReader> reader;
    reader->SetFileName(WriteFile("bundle-" + flat, bytes).c_str());
    ExpectPiecesMakeTheWhole(reader, name);
  }
}

TEST(TrackPieces, ScalarsAndPropertiesGoWithTheirStreamlines)
{
  for (const bool bigEndian : { false, true })
    for (const int headerCount : { 37, 0 })
    {
      const std::string bytes = MakeTRK(37, headerCount, bigEndian);
      const std::string what = std::string(bigEndian ? "big" : "little") + "-endian, n_count " +
        std::to_string(headerCount);
      vtkNew<vtkSightlineTrackVisReader> reader;
      vtkNew<Messages> messages;
      reader->AddObserver(vtkCommand::WarningEvent, messages);
      reader->SetFileName(WriteFile("pieces-" + std::to_string(bigEndian) + "-" +
          std::to_string(headerCount) + ".trk", bytes).c_str());
      ExpectPiecesMakeTheWhole(reader, what);
      EXPECT_EQ(messages->warnings, "");
      const vtkSmartPointer<vtkPolyData> whole = ReadPiece(reader, 0, 1);
      ASSERT_EQ(whole->GetNumberOfCells(), 37);
      ASSERT_TRUE(whole->GetPointData()->GetArray("fa") && whole->GetPointData()->GetArray("md"));
      // Piece 2 of 3 starts at streamline 24: its first point's scalar is 24000.
      const vtkSmartPointer<vtkPolyData> last = ReadPiece(reader, 2, 3);
      EXPECT_EQ(last->GetPointData()->GetArray("fa")->GetComponent(0, 0), 24000.0);
      EXPECT_EQ(last->GetCellData()->GetArray("length")->GetComponent(0, 0), 24 * 3.5);
      // The same bytes as an input string split the same way.
      vtkNew<vtkSightlineTrackVisReader> fromString;
      fromString->SetInputString(bytes);
      fromString->ReadFromInputStringOn();
      ExpectPiecesMakeTheWhole(fromString, what + " from a string");
    }
}

TEST(TrackPieces, TCKWithoutCountInEveryDatatype)
{
  for (const bool doubles : { false, true })
    for (const bool bigEndian : { false, true })
    {
      const std::string what = std::string(doubles ? "Float64" : "Float32") + (bigEndian ? "BE" : "LE");
      vtkNew<vtkSightlineTCKReader> reader;
      vtkNew<Messages> messages;
      reader->AddObserver(vtkCommand::WarningEvent, messages);
      reader->SetFileName(WriteFile("pieces-" + what + ".tck", MakeTCK(29, "", doubles, bigEndian)).c_str());
      ExpectPiecesMakeTheWhole(reader, what);
      EXPECT_EQ(messages->warnings, "");
      EXPECT_EQ(ReadPiece(reader, 0, 1)->GetNumberOfCells(), 29);
      // Piece 3 of 4 starts at streamline 21 (29 * 3 / 4): its first point is (21, 0, -21).
      double p[3];
      ReadPiece(reader, 3, 4)->GetPoint(0, p);
      EXPECT_EQ(p[0], 21.0);
      EXPECT_EQ(p[2], -21.0);
    }
}

// A count that disagrees with the file still splits it without loss or overlap: the last
// piece takes whatever lies beyond the count, and only it (reading to the end) warns.
TEST(TrackPieces, AWrongCountLosesNothing)
{
  for (const int count : { 5, 100 })
  {
    vtkNew<vtkSightlineTCKReader> tck;
    tck->SetFileName(WriteFile("pieces-count-" + std::to_string(count) + ".tck",
      MakeTCK(29, "count: " + std::to_string(count) + "\n", false, false)).c_str());
    vtkNew<vtkSightlineTrackVisReader> trk;
    trk->SetFileName(WriteFile("pieces-count-" + std::to_string(count) + ".trk",
      MakeTRK(29, count, false)).c_str());
    for (vtkAlgorithm* reader : { static_cast<vtkAlgorithm*>(tck), static_cast<vtkAlgorithm*>(trk) })
    {
      vtkNew<Messages> messages;
      reader->AddObserver(vtkCommand::WarningEvent, messages);
      ExpectPiecesMakeTheWhole(reader, reader->GetClassName() + std::string(" count ") +
          std::to_string(count), false);
      EXPECT_NE(messages->warnings.find("count"), std::string::npos) << messages->warnings;
    }
  }
}

TEST(SWCPieces, TheWholeFileIsPieceZero)
{
  vtkNew<vtkSightlineSWCReader> reader;
  reader->SetFileName((std::string(SIGHTLINE_SOURCE_DIR) + "/Testing/Data/SWC/unsorted_two_roots.swc").c_str());
  const vtkSmartPointer<vtkPolyData> whole = ReadPiece(reader, 0, 1);
  ASSERT_GT(whole->GetNumberOfPoints(), 0);
  for (const int pieces : { 2, 3 })
    for (int p = 0; p < pieces; ++p)
    {
      const vtkSmartPointer<vtkPolyData> piece = ReadPiece(reader, p, pieces);
      EXPECT_EQ(piece->GetNumberOfPoints(), p == 0 ? whole->GetNumberOfPoints() : 0);
      EXPECT_EQ(piece->GetNumberOfCells(), p == 0 ? whole->GetNumberOfCells() : 0);
    }
}

// ---------------------------------------------------------------------------------------------
// MIF: every piece and sub-extent is the corresponding part of the whole image.
namespace
{
vtkSmartPointer<vtkImageData> Copy(vtkAlgorithm* reader)
{
  auto copy = vtkSmartPointer<vtkImageData>::New();
  copy->DeepCopy(vtkImageData::SafeDownCast(reader->GetOutputDataObject(0)));
  return copy;
}

void ExpectPartOfTheWhole(vtkImageData* whole, vtkImageData* part, const std::string& what)
{
  int extent[6];
  part->GetExtent(extent);
  vtkDataArray* all = whole->GetPointData()->GetScalars();
  vtkDataArray* some = part->GetPointData()->GetScalars();
  ASSERT_TRUE(all && some) << what;
  ASSERT_EQ(some->GetNumberOfComponents(), all->GetNumberOfComponents()) << what;
  ASSERT_EQ(some->GetNumberOfTuples(), part->GetNumberOfPoints()) << what;
  double spacing[3], wholeSpacing[3];
  part->GetSpacing(spacing);
  whole->GetSpacing(wholeSpacing);
  for (int a = 0; a < 3; ++a)
    EXPECT_EQ(spacing[a], wholeSpacing[a]) << what;
  for (int k = extent[4]; k <= extent[5]; ++k)
    for (int j = extent[2]; j <= extent[3]; ++j)
      for (int i = extent[0]; i <= extent[1]; ++i)
      {
        int ijk[3] = { i, j, k };
        const vtkIdType a = whole->ComputePointId(ijk), b = part->ComputePointId(ijk);
        for (int c = 0; c < all->GetNumberOfComponents(); ++c)
          ASSERT_EQ(some->GetComponent(b, c), all->GetComponent(a, c))
            << what << " voxel " << i << "," << j << "," << k << " component " << c;
      }
}

void ExpectMIFPieces(const std::string& path)
{
  vtkNew<vtkSightlineMIFReader> reader;
  vtkNew<Messages> messages;
  reader->AddObserver(vtkCommand::ErrorEvent, messages);
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->SetFileName(path.c_str());
  reader->UpdatePiece(0, 1, 0);
  const vtkSmartPointer<vtkImageData> whole = Copy(reader);
  ASSERT_GT(whole->GetNumberOfPoints(), 0) << path << messages->errors;
  for (const int pieces : { 1, 2, 3, 4, 7 })
  {
    vtkIdType cells = 0, points = 0;
    for (int p = 0; p < pieces; ++p)
    {
      reader->Modified(); // a piece inside the last output would not be read again
      reader->UpdatePiece(p, pieces, 0);
      const vtkSmartPointer<vtkImageData> piece = Copy(reader);
      const std::string what = path + ", piece " + std::to_string(p) + " of " + std::to_string(pieces);
      if (piece->GetNumberOfPoints() == 0)
        continue; // more pieces than the translator can cut
      ExpectPartOfTheWhole(whole, piece, what);
      cells += piece->GetNumberOfCells();
      points += piece->GetNumberOfPoints();
      if (pieces > 1 && pieces <= 4)
      {
        EXPECT_LT(piece->GetNumberOfPoints(), whole->GetNumberOfPoints()) << what;
      }
    }
    // The pieces split the cells (and share only the points of their common faces).
    EXPECT_EQ(cells, whole->GetNumberOfCells()) << path << ", " << pieces << " pieces";
    EXPECT_GE(points, whole->GetNumberOfPoints()) << path << ", " << pieces << " pieces";
  }
  int wholeExtent[6];
  whole->GetExtent(wholeExtent);
  const int sub[][6] = { { 0, 0, 0, 0, 0, 0 },
    { wholeExtent[1], wholeExtent[1], wholeExtent[3], wholeExtent[3], wholeExtent[5], wholeExtent[5] },
    { 1, wholeExtent[1] - 1, 0, wholeExtent[3] / 2, wholeExtent[5] / 3, wholeExtent[5] },
    { wholeExtent[1] / 2, wholeExtent[1] / 2, 1, 1, 0, wholeExtent[5] } };
  for (const auto& extent : sub)
  {
    reader->Modified();
    reader->UpdateExtent(extent);
    const vtkSmartPointer<vtkImageData> part = Copy(reader);
    int got[6];
    part->GetExtent(got);
    for (int a = 0; a < 6; ++a)
      EXPECT_EQ(got[a], extent[a]) << path;
    ExpectPartOfTheWhole(whole, part, path + " sub-extent");
  }
  EXPECT_EQ(messages->errors, "");
  EXPECT_EQ(messages->warnings, "");
}

std::string Gzip(const std::string& bytes)
{
  z_stream stream;
  std::memset(&stream, 0, sizeof(stream));
  EXPECT_EQ(deflateInit2(&stream, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&stream, static_cast<uLong>(bytes.size())), '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  stream.avail_in = static_cast<uInt>(bytes.size());
  stream.next_out = reinterpret_cast<Bytef*>(&out[0]);
  stream.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&stream, Z_FINISH), Z_STREAM_END);
  out.resize(stream.total_out);
  deflateEnd(&stream);
  return out;
}
} // namespace

TEST(MIFPieces, SHDataPiecesAndSubExtentsArePartsOfTheWhole)
{
  for (const char* name : { "small_64D_sh_tournier07.mif", "small_64D_sh_tournier07.mif.gz",
         "small_64D_sh_tournier07_realigned.mif" })
    ExpectMIFPieces(DataDir + "/" + name);
}

// A 4-D image with every axis in a different disk position and two reversed (the 4th, the
// components, slowest), a left-handed transform (slices reversed), big-endian Int16 and
// scaling; plain and gzip. Any layout splits correctly.
TEST(MIFPieces, ScrambledLayoutsAndLeftHandedGrids)
{
  const int dim[4] = { 5, 4, 7, 3 };
  const char* layouts[] = { "-1,+0,-3,+2", "+2,-3,+1,+0", "+0,+1,+2,+3", "+3,+2,+1,+0" };
  int n = 0;
  for (const char* layout : layouts)
    for (const bool gzip : { false, true })
    {
      std::string data;
      for (int e = 0; e < dim[0] * dim[1] * dim[2] * dim[3]; ++e)
        Put(data, std::int16_t(e * 7 - 300), true);
      std::string header = std::string("mrtrix image\ndim: 5,4,7,3\nvox: 1,2,3,nan\nlayout: ") +
        layout + "\ndatatype: Int16BE\nscaling: 1,0.5\ntransform: 1,0,0,0\ntransform: 0,1,0,0\n"
                 "transform: 0,0,-1,0\nfile: . ";
      const std::size_t offset = header.size() + 16;
      header += std::to_string(offset) + "\nEND\n";
      header.resize(offset, '\n');
      const std::string bytes = header + data;
      const std::string path = WriteFile("pieces-" + std::to_string(n++) + (gzip ? ".mif.gz" : ".mif"),
        gzip ? Gzip(bytes) : bytes);
      ExpectMIFPieces(path);
    }
}
