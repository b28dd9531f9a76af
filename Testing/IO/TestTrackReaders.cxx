// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineTCKReader and vtkSightlineTrackVisReader on small files written here, in both
// byte orders and both float widths, and on broken ones. Real files (nibabel's standard.trk,
// standard.LPS.trk, standard.tck and DIPY's bundles) are compared with nibabel in
// Testing/Python/test_track_readers.py.
#include "vtkSightlineTCKReader.h"
#include "vtkSightlineTrackVisReader.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkIdList.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace
{
std::string TempFile(const std::string& name)
{
  return std::string(SIGHTLINE_TEST_TEMP_DIR) + "/" + name;
}

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

template <class T>
void Put(std::string& bytes, T value, bool bigEndian)
{
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (bigEndian)
    std::reverse(raw, raw + sizeof(T)); // the test machine is little-endian (x86-64)
  bytes.append(raw, sizeof(T));
}

const std::vector<std::vector<std::array<double, 3>>> kStreamlines = {
  { { { 1.0, 2.0, 3.0 } }, { { 1.5, 2.5, 3.5 } }, { { 2.0, 3.0, 4.0 } } },
  { { { -1.0, 0.0, 10.0 } }, { { -2.0, 0.25, 11.0 } } },
};

/// A .tck file of kStreamlines; `end` false leaves out the Inf triplet (a cut file).
std::string WriteTCK(const std::string& name, bool doubles, bool bigEndian, bool end = true)
{
  const std::string type = std::string(doubles ? "Float64" : "Float32") + (bigEndian ? "BE" : "LE");
  std::string header = "mrtrix tracks\ncount: 2\ndatatype: " + type + "\nfile: . ";
  const std::size_t offset = header.size() + 8 + 4; // "OFFSET\nEND\n" rounded up below
  std::string data;
  auto triplet = [&](double x, double y, double z)
  {
    for (double v : { x, y, z })
      doubles ? Put(data, v, bigEndian) : Put(data, float(v), bigEndian);
  };
  for (const auto& line : kStreamlines)
  {
    for (const auto& p : line)
      triplet(p[0], p[1], p[2]);
    triplet(NAN, NAN, NAN);
  }
  if (end)
    triplet(INFINITY, INFINITY, INFINITY);
  std::string text = header + std::to_string(offset + 8) + "\nEND\n";
  text.resize(offset + 8, '\n');
  const std::string path = TempFile(name);
  std::ofstream(path, std::ios::binary) << text << data;
  return path;
}

void ExpectStreamlines(vtkPolyData* out, std::size_t count)
{
  ASSERT_EQ(out->GetNumberOfCells(), vtkIdType(count));
  vtkNew<vtkIdList> ids;
  for (std::size_t c = 0; c < count; ++c)
  {
    out->GetLines()->GetCellAtId(vtkIdType(c), ids);
    ASSERT_EQ(ids->GetNumberOfIds(), vtkIdType(kStreamlines[c].size()));
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
    {
      double p[3];
      out->GetPoint(ids->GetId(k), p);
      for (int a = 0; a < 3; ++a)
        EXPECT_FLOAT_EQ(float(p[a]), float(kStreamlines[c][k][a]));
    }
  }
}
} // namespace

TEST(TCKReader, EveryDatatypeReadsTheSameStreamlines)
{
  for (bool doubles : { false, true })
    for (bool bigEndian : { false, true })
    {
      const std::string path = WriteTCK(std::string("tracks-") + (doubles ? "f64" : "f32") +
        (bigEndian ? "be" : "le") + ".tck", doubles, bigEndian);
      EXPECT_TRUE(vtkSightlineTCKReader::CanReadFile(path.c_str()));
      vtkNew<vtkSightlineTCKReader> reader;
      reader->SetFileName(path.c_str());
      reader->Update();
      ExpectStreamlines(reader->GetOutput(), 2);
    }
}

TEST(TCKReader, CutAndBrokenFiles)
{
  {
    // No end marker: the complete streamlines stay, with a warning.
    vtkNew<vtkSightlineTCKReader> reader;
    vtkNew<Messages> messages;
    reader->AddObserver(vtkCommand::WarningEvent, messages);
    reader->SetFileName(WriteTCK("cut.tck", false, false, false).c_str());
    reader->Update();
    ExpectStreamlines(reader->GetOutput(), 2);
    EXPECT_NE(messages->warnings.find("no end marker"), std::string::npos) << messages->warnings;
  }
  const std::string notTracks = TempFile("not-tracks.tck");
  std::ofstream(notTracks) << "mrtrix image\nEND\n";
  const std::string noEnd = TempFile("no-end.tck");
  std::ofstream(noEnd) << "mrtrix tracks\ndatatype: Float32LE\nfile: . 40\n";
  const std::string badType = TempFile("bad-type.tck");
  std::ofstream(badType) << "mrtrix tracks\ndatatype: Int16LE\nfile: . 50\nEND\n";
  const std::string badOffset = TempFile("bad-offset.tck");
  std::ofstream(badOffset) << "mrtrix tracks\ndatatype: Float32LE\nfile: . 5000\nEND\n";
  const std::pair<std::string, const char*> cases[] = { { notTracks, "is not an MRtrix track file" },
    { noEnd, "no END line" }, { badType, "datatype 'Int16LE'" }, { badOffset, "data offset" },
    { TempFile("missing.tck"), "Cannot open" } };
  for (const auto& [path, expected] : cases)
  {
    vtkNew<vtkSightlineTCKReader> reader;
    vtkNew<Messages> messages;
    reader->AddObserver(vtkCommand::ErrorEvent, messages);
    reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, messages);
    reader->SetFileName(path.c_str());
    reader->Update();
    EXPECT_NE(messages->errors.find(expected), std::string::npos) << path << ": " << messages->errors;
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  }
}

namespace
{
/// A version-2 TrackVis file of kStreamlines (in voxmm) with one scalar and one property.
std::string WriteTRK(const std::string& name, bool bigEndian, int cutBytes = 0)
{
  std::string h(1000, '\0');
  std::memcpy(&h[0], "TRACK", 5);
  auto put = [&](std::size_t at, auto value)
  {
    std::string bytes;
    Put(bytes, value, bigEndian);
    std::memcpy(&h[at], bytes.data(), bytes.size());
  };
  for (int a = 0; a < 3; ++a)
  {
    put(6 + 2 * a, std::int16_t(10));
    put(12 + 4 * a, float(2.0));
  }
  put(36, std::int16_t(1));
  std::memcpy(&h[38], "fa", 2);
  put(238, std::int16_t(1));
  std::memcpy(&h[240], "length", 6);
  for (int i = 0; i < 4; ++i)
    put(440 + 4 * (4 * i + i), float(i == 3 ? 1.0 : 2.0)); // 2 mm voxels, RAS
  std::memcpy(&h[948], "RAS", 3);
  put(988, std::int32_t(2));
  put(992, std::int32_t(2));
  put(996, std::int32_t(1000));
  std::string body;
  int line = 0;
  for (const auto& streamline : kStreamlines)
  {
    Put(body, std::int32_t(streamline.size()), bigEndian);
    int k = 0;
    for (const auto& p : streamline)
    {
      for (double v : p)
        Put(body, float(v), bigEndian);
      Put(body, float(10 * line + k++), bigEndian); // the scalar
    }
    Put(body, float(100 + line++), bigEndian); // the property
  }
  body.resize(body.size() - cutBytes);
  const std::string path = TempFile(name);
  std::ofstream(path, std::ios::binary) << h << body;
  return path;
}
} // namespace

TEST(TrackVisReader, BothByteOrdersScalarsPropertiesAndRASMapping)
{
  for (bool bigEndian : { false, true })
  {
    const std::string path = WriteTRK(bigEndian ? "big.trk" : "little.trk", bigEndian);
    EXPECT_TRUE(vtkSightlineTrackVisReader::CanReadFile(path.c_str()));
    vtkNew<vtkSightlineTrackVisReader> raw;
    raw->SetFileName(path.c_str());
    raw->CoordinatesVoxmmOn();
    raw->Update();
    ExpectStreamlines(raw->GetOutput(), 2);
    vtkDataArray* fa = raw->GetOutput()->GetPointData()->GetArray("fa");
    vtkDataArray* length = raw->GetOutput()->GetCellData()->GetArray("length");
    ASSERT_TRUE(fa && length);
    EXPECT_EQ(fa->GetComponent(4, 0), 11.0); // second streamline, second point
    EXPECT_EQ(length->GetComponent(1, 0), 101.0);
    // RAS mm: voxmm / 2 mm - 0.5 voxel, times the 2 mm RAS matrix: p - 1.
    vtkNew<vtkSightlineTrackVisReader> ras;
    ras->SetFileName(path.c_str());
    ras->Update();
    EXPECT_STREQ(ras->GetVoxelOrder(), "RAS");
    double p[3];
    ras->GetOutput()->GetPoint(0, p);
    EXPECT_FLOAT_EQ(float(p[0]), 0.0f);
    EXPECT_FLOAT_EQ(float(p[1]), 1.0f);
    EXPECT_FLOAT_EQ(float(p[2]), 2.0f);
  }
}

TEST(TrackVisReader, CutAndBrokenFiles)
{
  {
    vtkNew<vtkSightlineTrackVisReader> reader;
    vtkNew<Messages> messages;
    reader->AddObserver(vtkCommand::WarningEvent, messages);
    reader->SetFileName(WriteTRK("cut.trk", false, 6).c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 1);
    EXPECT_NE(messages->warnings.find("cut short"), std::string::npos) << messages->warnings;
  }
  const std::string notTrack = TempFile("not-a-track.trk");
  std::ofstream(notTrack) << std::string(1200, 'x');
  std::string badSize(1000, '\0');
  std::memcpy(&badSize[0], "TRACK", 5);
  const std::string badSizePath = TempFile("bad-size.trk");
  std::ofstream(badSizePath, std::ios::binary) << badSize;
  const std::pair<std::string, const char*> cases[] = { { notTrack, "is not a TrackVis file" },
    { badSizePath, "header size" }, { TempFile("missing.trk"), "Cannot open" } };
  for (const auto& [path, expected] : cases)
  {
    vtkNew<vtkSightlineTrackVisReader> reader;
    vtkNew<Messages> messages;
    reader->AddObserver(vtkCommand::ErrorEvent, messages);
    reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, messages);
    reader->SetFileName(path.c_str());
    reader->Update();
    EXPECT_NE(messages->errors.find(expected), std::string::npos) << path << ": " << messages->errors;
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  }
}
