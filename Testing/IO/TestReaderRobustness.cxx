// SPDX-License-Identifier: BSD-3-Clause
// Hostile input for the four readers, one test per class of failure found by mutating real
// files: each must end in a clear error (or a warning where the valid part is kept), never a
// crash, an abort, a huge allocation or silent garbage; and every message must be valid UTF-8
// whatever bytes the file holds.
#include "vtkSightlineMIFReader.h"
#include "vtkSightlineSWCReader.h"
#include "vtkSightlineTCKReader.h"
#include "vtkSightlineTrackVisReader.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkIdList.h"
#include "vtkMatrix4x4.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtk_zlib.h"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace
{
std::string TempFile(const std::string& name)
{
  return std::string(SIGHTLINE_TEST_TEMP_DIR) + "/robust_" + name;
}

void WriteBytes(const std::string& path, const std::string& bytes)
{
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string ReadBytes(const std::string& path)
{
  std::ifstream stream(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>());
}

/// The gzip form of `bytes` (zlib's deflate with a gzip wrapper, as gzip and mrconvert write).
std::string Gzip(const std::string& bytes)
{
  z_stream stream{};
  EXPECT_EQ(deflateInit2(&stream, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
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

/// Strict UTF-8 (RFC 3629): what Python needs to turn a message into str instead of None.
bool ValidUtf8(const std::string& text)
{
  for (std::size_t i = 0; i < text.size();)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const int extra = c < 0x80 ? 0 : (c & 0xE0) == 0xC0 ? 1 : (c & 0xF0) == 0xE0 ? 2
      : (c & 0xF8) == 0xF0                                                         ? 3
                                                                                   : -1;
    if (extra < 0 || i + extra >= text.size() + (extra == 0 ? 1 : 0))
    {
      return false;
    }
    std::uint32_t code = extra == 0 ? c : (c & (0x3F >> extra));
    for (int k = 1; k <= extra; ++k)
    {
      const unsigned char next = static_cast<unsigned char>(text[i + k]);
      if ((next & 0xC0) != 0x80)
      {
        return false;
      }
      code = (code << 6) | (next & 0x3F);
    }
    const std::uint32_t smallest[4] = { 0, 0x80, 0x800, 0x10000 };
    if (code < smallest[extra] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF))
    {
      return false;
    }
    i += extra + 1;
  }
  return true;
}

class Messages : public vtkCommand
{
public:
  static Messages* New() { return new Messages; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    const std::string text = data ? static_cast<const char*>(data) : "";
    (event == vtkCommand::ErrorEvent ? errors : warnings) += text + "\n";
  }
  std::string errors, warnings;
};

/// Runs `reader` on `path` with its errors and warnings collected.
template <class Reader>
void Read(Reader* reader, const std::string& path, Messages* messages)
{
  reader->AddObserver(vtkCommand::ErrorEvent, messages);
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, messages);
  reader->SetFileName(path.c_str());
  reader->Update();
}

/// Peak resident memory of this process so far, in MiB.
long PeakMiB()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

/// A single-file MIF: `keys`, then "file: . OFFSET" (OFFSET just after the header, or `offset`
/// when given) and END, then `data`.
std::string Mif(const std::string& keys, const std::string& data, long offset = -1)
{
  std::string header = "mrtrix image\n" + keys + "file: . ";
  const std::size_t length = header.size() + 6 + 5; // "NNNNNN\nEND\n"
  char number[16];
  std::snprintf(number, sizeof(number), "%06ld", offset >= 0 ? offset : long(length));
  return header + number + "\nEND\n" + data;
}

void ExpectMifError(const std::string& name, const std::string& bytes, const std::string& fragment)
{
  const std::string path = TempFile(name);
  WriteBytes(path, bytes);
  vtkNew<vtkSightlineMIFReader> reader;
  vtkNew<Messages> messages;
  Read(reader.Get(), path, messages);
  EXPECT_NE(messages->errors.find(fragment), std::string::npos)
    << name << ": expected \"" << fragment << "\" in: " << messages->errors;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0) << name;
  EXPECT_TRUE(ValidUtf8(messages->errors)) << name;
}
} // namespace

// ---------------------------------------------------------------------------------------------
// MIF: sizes and products.

// 65536 in four axes is 2^64: the product wrapped to 0, the buffer stayed empty and the
// conversion loop read from it (SIGSEGV).
TEST(ReaderRobustness, MIFDimProductThatWrapsIsAnError)
{
  ExpectMifError("wrap.mif",
    Mif("dim: 65536,65536,65536,65536\nvox: 1,1,1,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n",
      std::string(64, '\0')),
    "overflows 64-bit integers");
}

// Signed overflow of the stride product and the voxel count (undefined behaviour, UBSan).
TEST(ReaderRobustness, MIFStrideProductOverflowIsAnError)
{
  ExpectMifError("stride.mif",
    Mif("dim: 2147483647,2147483647,2147483647,3\nvox: 1,1,1,1\nlayout: +3,+2,+1,+0\n"
        "datatype: UInt8\n",
      std::string(64, '\0')),
    "overflows 64-bit integers");
  // The count fits but its bytes do not: 2^61 Float64 values.
  ExpectMifError("bytes.mif",
    Mif("dim: 2097152,1048576,1048576,1\nvox: 1,1,1,1\nlayout: +0,+1,+2,+3\n"
        "datatype: Float64LE\n",
      std::string(64, '\0')),
    "overflows 64-bit byte counts");
}

// A 272-byte file asking for 4e15 bytes: std::bad_alloc (or length_error) escaped the reader.
TEST(ReaderRobustness, MIFHugeRequestFromATinyFileIsAnError)
{
  const std::string bytes =
    Mif("dim: 100000,100000,100000,1\nvox: 1,1,1,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n",
      std::string(128, '\0'));
  ExpectMifError("huge.mif", bytes, "the file is truncated: the header promises 4000000000000000 bytes");
  ExpectMifError("huge.mif.gz", Gzip(bytes), "a gzip stream of this length cannot hold them");
}

// A small file that promises 1 GiB: the reader filled a 1 GiB buffer before it found the data
// missing. It must now refuse before allocating: the peak memory stays far below 1 GiB.
TEST(ReaderRobustness, MIFTruncationIsFoundBeforeAllocating)
{
  const std::string bytes =
    Mif("dim: 1024,1024,256,1\nvox: 1,1,1,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n",
      std::string(160, '\x01'));
  const long before = PeakMiB();
  ExpectMifError("gigabyte.mif", bytes, "only 160 bytes there");
  ExpectMifError("gigabyte.mif.gz", Gzip(bytes), "cannot hold them");
  EXPECT_LT(PeakMiB() - before, 256) << "MiB allocated for a file of " << bytes.size() << " bytes";
  // A compressed file that could hold the data but does not (2 MiB of incompressible bytes):
  // inflated in steps, so the memory taken follows what is actually there.
  std::string noise(2u << 20, '\0');
  std::uint32_t state = 12345;
  for (char& c : noise)
  {
    state = state * 1664525u + 1013904223u;
    c = static_cast<char>(state >> 24);
  }
  const std::string compressed = Gzip(Mif(
    "dim: 1024,1024,256,1\nvox: 1,1,1,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n", noise));
  ASSERT_GT(compressed.size() * 1032, 1u << 30); // the bound alone does not refuse it
  ExpectMifError("noise.mif.gz", compressed, "is truncated");
  EXPECT_LT(PeakMiB() - before, 512);
}

// `file: . 0` made the reader read its own header text as voxel values.
TEST(ReaderRobustness, MIFDataOffsetInsideTheHeaderIsAnError)
{
  ExpectMifError("offset0.mif",
    Mif("dim: 2,2,2\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: UInt8\n", std::string(8, '\0'), 0),
    "lies inside the header");
}

// ---------------------------------------------------------------------------------------------
// Messages quote file content; bytes that are not UTF-8 made the message unusable from Python.
TEST(ReaderRobustness, MessagesStayValidUtf8WhateverTheFileHolds)
{
  const std::string junk = "\xff\xfe\xc3\x28\xed\xa0\x80\x01";
  {
    SCOPED_TRACE("MIF");
    ExpectMifError("junk.mif",
      Mif("dim: 2,2,2\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: " + junk + "\n", ""),
      "unsupported datatype '\\xFF\\xFE\\xC3(\\xED\\xA0\\x80\\x01'");
  }
  {
    const std::string path = TempFile("junk.tck");
    WriteBytes(path, "mrtrix tracks\ndatatype: Float32LE\nfile: " + junk + "\nEND\n");
    vtkNew<vtkSightlineTCKReader> reader;
    vtkNew<Messages> messages;
    Read(reader.Get(), path, messages);
    EXPECT_NE(messages->errors.find("\\xFF\\xFE"), std::string::npos) << messages->errors;
    EXPECT_TRUE(ValidUtf8(messages->errors)) << "TCK";
  }
  {
    const std::string path = TempFile("junk.swc");
    WriteBytes(path, "1 1 0 0 0 1 -1\n2 3 " + junk + " 0 0 1 1\n");
    vtkNew<vtkSightlineSWCReader> reader;
    vtkNew<Messages> messages;
    Read(reader.Get(), path, messages);
    EXPECT_NE(messages->errors.find("line 2: the x field \"\\xFF\\xFE"), std::string::npos)
      << messages->errors;
    EXPECT_TRUE(ValidUtf8(messages->errors)) << "SWC";
  }
  // Valid UTF-8 in the file is kept as it is.
  {
    const std::string path = TempFile("utf8.swc");
    WriteBytes(path, "1 1 0 0 0 1 -1\n2 3 \xc3\xa9t\xc3\xa9 0 0 1 1\n");
    vtkNew<vtkSightlineSWCReader> reader;
    vtkNew<Messages> messages;
    Read(reader.Get(), path, messages);
    EXPECT_NE(messages->errors.find("\"\xc3\xa9t\xc3\xa9\""), std::string::npos) << messages->errors;
  }
}

// ---------------------------------------------------------------------------------------------
// TCK.
namespace
{
std::string Tck(const std::string& type, const std::string& data)
{
  const std::string head = "mrtrix tracks\ndatatype: " + type + "\nfile: . ";
  const std::size_t offset = head.size() + 4 + 5; // "NNNN\nEND\n"
  char number[8];
  std::snprintf(number, sizeof(number), "%04zu", offset);
  return head + number + "\nEND\n" + data;
}

void PutDouble(std::string& data, std::initializer_list<double> values)
{
  for (const double v : values)
  {
    data.append(reinterpret_cast<const char*>(&v), sizeof(v)); // x86-64: little-endian
  }
}

/// Every point of `output` is used by exactly one line (no stray points outside any line).
void ExpectEveryPointOnALine(vtkPolyData* output)
{
  vtkIdType used = 0;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < output->GetLines()->GetNumberOfCells(); ++c)
  {
    output->GetLines()->GetCellAtId(c, ids);
    used += ids->GetNumberOfIds();
  }
  EXPECT_EQ(used, output->GetNumberOfPoints());
}
} // namespace

// A Float64 coordinate beyond float range turned into an infinity in the single-precision
// points: the streamline is left out with a warning, the others are kept.
TEST(ReaderRobustness, TCKFloat64BeyondFloatRangeIsLeftOutWithAWarning)
{
  std::string data;
  PutDouble(data, { 1, 2, 3, 4, 5, 6, NAN, NAN, NAN });
  PutDouble(data, { 1, 2, 3, 1e300, 5, 6, NAN, NAN, NAN });
  PutDouble(data, { 7, 8, 9, 10, 11, 12, NAN, NAN, NAN, INFINITY, INFINITY, INFINITY });
  const std::string path = TempFile("far.tck");
  WriteBytes(path, Tck("Float64LE", data));
  vtkNew<vtkSightlineTCKReader> reader;
  vtkNew<Messages> messages;
  Read(reader.Get(), path, messages);
  EXPECT_TRUE(messages->errors.empty()) << messages->errors;
  EXPECT_NE(messages->warnings.find("1 streamlines (the first is number 1, with the value 1e+300)"),
    std::string::npos)
    << messages->warnings;
  vtkPolyData* output = reader->GetOutput();
  ASSERT_EQ(output->GetNumberOfCells(), 2);
  ASSERT_EQ(output->GetNumberOfPoints(), 4);
  for (vtkIdType i = 0; i < 4; ++i)
  {
    double p[3];
    output->GetPoint(i, p);
    EXPECT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) << i;
  }
  double last[3];
  output->GetPoint(3, last);
  EXPECT_EQ(last[0], 10.0);
}

// A file cut inside its last streamline: that streamline's points stayed in the output as
// points outside any line.
TEST(ReaderRobustness, TCKIncompleteLastStreamlineLeavesNoStrayPoints)
{
  std::string data;
  PutDouble(data, { 1, 2, 3, 4, 5, 6, NAN, NAN, NAN, 7, 8, 9, 10, 11, 12 });
  const std::string path = TempFile("cut.tck");
  WriteBytes(path, Tck("Float64LE", data));
  vtkNew<vtkSightlineTCKReader> reader;
  vtkNew<Messages> messages;
  Read(reader.Get(), path, messages);
  EXPECT_NE(messages->warnings.find("the last incomplete one dropped"), std::string::npos)
    << messages->warnings;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 1);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 2);
  ExpectEveryPointOnALine(reader->GetOutput());
}

// ---------------------------------------------------------------------------------------------
// TrackVis.
namespace
{
/// A little-endian version-2 file of 2 mm voxels, RAS matrix (diagonal `scale`, 1), 3
/// streamlines of 2 points; the middle streamline's second point is `middle`.
std::string Trk(const char* order, float middle, float scale = 2.0f)
{
  std::string h(1000, '\0');
  std::memcpy(&h[0], "TRACK", 5);
  auto put = [&](std::size_t at, auto value) { std::memcpy(&h[at], &value, sizeof(value)); };
  for (int a = 0; a < 3; ++a)
  {
    put(6 + 2 * a, std::int16_t(10));
    put(12 + 4 * a, 2.0f);
  }
  for (int i = 0; i < 4; ++i)
  {
    put(440 + 4 * (4 * i + i), i == 3 ? 1.0f : scale);
  }
  std::memcpy(&h[948], order, std::strlen(order));
  put(988, std::int32_t(3));
  put(992, std::int32_t(2));
  put(996, std::int32_t(1000));
  std::string body;
  auto add = [&](auto value) { body.append(reinterpret_cast<const char*>(&value), sizeof(value)); };
  for (int s = 0; s < 3; ++s)
  {
    add(std::int32_t(2));
    for (float v : { 1.0f, 2.0f, 3.0f, s == 1 ? middle : 4.0f, 5.0f, 6.0f })
    {
      add(v);
    }
  }
  return h + body;
}
} // namespace

// NaN and infinite coordinates passed through into the output points.
TEST(ReaderRobustness, TrackVisNonFiniteCoordinatesAreLeftOutWithAWarning)
{
  for (const bool voxmm : { false, true })
  {
    for (const float bad : { std::numeric_limits<float>::quiet_NaN(),
           std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity() })
    {
      const std::string path = TempFile("nonfinite.trk");
      WriteBytes(path, Trk("RAS", bad));
      vtkNew<vtkSightlineTrackVisReader> reader;
      reader->SetCoordinatesVoxmm(voxmm);
      vtkNew<Messages> messages;
      Read(reader.Get(), path, messages);
      EXPECT_TRUE(messages->errors.empty()) << messages->errors;
      EXPECT_NE(messages->warnings.find("1 streamlines have NaN or infinite coordinates"),
        std::string::npos)
        << messages->warnings;
      EXPECT_NE(messages->warnings.find("were left out (the first is streamline 1)"),
        std::string::npos)
        << messages->warnings;
      vtkPolyData* output = reader->GetOutput();
      EXPECT_EQ(output->GetNumberOfCells(), 2);
      ASSERT_EQ(output->GetNumberOfPoints(), 4);
      for (vtkIdType i = 0; i < 4; ++i)
      {
        double p[3];
        output->GetPoint(i, p);
        EXPECT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) << i;
      }
      ExpectEveryPointOnALine(output);
    }
  }
}

// Finite coordinates whose voxel-to-RAS image is beyond single precision became infinite
// output points (found by the fuzz campaign: huge voxel sizes in the matrix).
TEST(ReaderRobustness, TrackVisCoordinatesBeyondFloatAfterMappingAreLeftOut)
{
  const std::string path = TempFile("overflow.trk");
  WriteBytes(path, Trk("RAS", 1e33f, 2e6f));
  vtkNew<vtkSightlineTrackVisReader> reader;
  vtkNew<Messages> messages;
  Read(reader.Get(), path, messages);
  EXPECT_TRUE(messages->errors.empty()) << messages->errors;
  EXPECT_NE(messages->warnings.find("1 streamlines have NaN or infinite coordinates, or "
                                    "coordinates beyond single precision in RAS"),
    std::string::npos)
    << messages->warnings;
  vtkPolyData* output = reader->GetOutput();
  EXPECT_EQ(output->GetNumberOfCells(), 2);
  for (vtkIdType i = 0; i < output->GetNumberOfPoints(); ++i)
  {
    double p[3];
    output->GetPoint(i, p);
    EXPECT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) << i;
  }
  ExpectEveryPointOnALine(output);
}

// Voxel orders naming an axis twice were accepted and the voxmm-to-RAS matrix degenerated.
TEST(ReaderRobustness, TrackVisVoxelOrderWithARepeatedAxisIsAnError)
{
  for (const char* order : { "RRR", "RAR", "LLL", "RLS", "SAI" })
  {
    const std::string path = TempFile("order.trk");
    WriteBytes(path, Trk(order, 4.0f));
    vtkNew<vtkSightlineTrackVisReader> reader;
    vtkNew<Messages> messages;
    Read(reader.Get(), path, messages);
    EXPECT_NE(messages->errors.find(std::string("voxel order '") + order + "' names the axis"),
      std::string::npos)
      << order << ": " << messages->errors;
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0) << order;
  }
  // The valid orders of the same file still read (LAS flips x about the grid's centre).
  const std::string path = TempFile("order.trk");
  WriteBytes(path, Trk("LAS", 4.0f));
  vtkNew<vtkSightlineTrackVisReader> reader;
  vtkNew<Messages> messages;
  Read(reader.Get(), path, messages);
  EXPECT_TRUE(messages->errors.empty()) << messages->errors;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 3);
  EXPECT_EQ(reader->GetVoxmmToRASMatrix()->Determinant(), -1.0);
}

// ---------------------------------------------------------------------------------------------
// SWC: a subnormal value such as 1e-310 was refused as "not id type x y z ...".
TEST(ReaderRobustness, SWCSubnormalNumbersAreReadAndOverflowIsNamed)
{
  {
    const std::string path = TempFile("subnormal.swc");
    WriteBytes(path, "1 1 0 0 0 1 -1\n2 3 1e-310 0 0 1e-310 1\n");
    vtkNew<vtkSightlineSWCReader> reader;
    vtkNew<Messages> messages;
    Read(reader.Get(), path, messages);
    EXPECT_TRUE(messages->errors.empty()) << messages->errors;
    ASSERT_EQ(reader->GetOutput()->GetNumberOfPoints(), 2);
    double p[3];
    reader->GetOutput()->GetPoint(1, p);
    EXPECT_EQ(p[0], 1e-310);
  }
  {
    const std::string path = TempFile("overflow.swc");
    WriteBytes(path, "1 1 0 0 0 1 -1\n2 3 0 1e999 0 1 1\n");
    vtkNew<vtkSightlineSWCReader> reader;
    vtkNew<Messages> messages;
    Read(reader.Get(), path, messages);
    EXPECT_NE(messages->errors.find("line 2: the y field \"1e999\" is not a number in double range"),
      std::string::npos)
      << messages->errors;
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  }
}

// ---------------------------------------------------------------------------------------------
// The in-memory entry point (used by the fuzz targets) reads exactly what the file reads.
TEST(ReaderRobustness, InputStringReadsLikeTheFile)
{
  const std::string mif = Mif("dim: 2,1,1\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Int16BE\n",
    std::string("\x01\x02\xff\xfe", 4));
  for (const std::string& bytes : { mif, Gzip(mif) })
  {
    vtkNew<vtkSightlineMIFReader> reader;
    reader->SetInputString(bytes);
    reader->ReadFromInputStringOn();
    reader->Update();
    vtkDataArray* values = reader->GetOutput()->GetPointData()->GetScalars();
    ASSERT_NE(values, nullptr);
    ASSERT_EQ(values->GetNumberOfTuples(), 2);
    EXPECT_EQ(values->GetComponent(0, 0), 258.0);
    EXPECT_EQ(values->GetComponent(1, 0), -2.0);
  }
  const std::string trk = Trk("RAS", 4.0f);
  vtkNew<vtkSightlineTrackVisReader> fromFile, fromString;
  const std::string path = TempFile("same.trk");
  WriteBytes(path, trk);
  fromFile->SetFileName(path.c_str());
  fromFile->Update();
  fromString->SetInputString(ReadBytes(path));
  fromString->ReadFromInputStringOn();
  fromString->Update();
  ASSERT_EQ(fromString->GetOutput()->GetNumberOfPoints(), 6);
  for (vtkIdType i = 0; i < 6; ++i)
  {
    double a[3], b[3];
    fromFile->GetOutput()->GetPoint(i, a);
    fromString->GetOutput()->GetPoint(i, b);
    EXPECT_EQ(a[0], b[0]);
    EXPECT_EQ(a[1], b[1]);
    EXPECT_EQ(a[2], b[2]);
  }
}
