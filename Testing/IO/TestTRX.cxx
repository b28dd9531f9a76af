// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineTRXWriter and vtkSightlineTRXReader together: every array type VTK users hold
// survives a round trip in each TRX form (zip stored, zip deflated, directory; file and input
// string), and hostile TRX directories fail before allocating. The comparison with trx-python,
// the format's reference implementation, and broken zip archives written by Python's zipfile are
// in Testing/Python/test_trx.py.
#include "vtkSightlineTRXReader.h"
#include "vtkSightlineTRXWriter.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

namespace
{
std::string TempPath(const std::string& name)
{
  return std::string(SIGHTLINE_TEST_TEMP_DIR) + "/trx_" + name;
}

class Messages : public vtkCommand
{
public:
  static Messages* New() { return new Messages; }
  void Execute(vtkObject*, unsigned long event, void* data) override
  {
    (event == vtkCommand::ErrorEvent ? this->Errors : this->Warnings) +=
      std::string(data ? static_cast<const char*>(data) : "") + "\n";
  }
  std::string Errors, Warnings;
};

long PeakMiB()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024;
}

// Lines over shared points, a vertex cell (left out by the writer), and point,
// cell, group and field arrays of every numeric VTK type.
vtkSmartPointer<vtkPolyData> Tractogram()
{
  std::mt19937 random(42);
  std::normal_distribution<double> normal(0.0, 40.0);
  auto data = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (int i = 0; i < 200; ++i)
  {
    points->InsertNextPoint(normal(random), normal(random), normal(random));
  }
  data->SetPoints(points);
  vtkNew<vtkCellArray> verts;
  verts->InsertNextCell(1);
  verts->InsertCellPoint(7);
  data->SetVerts(verts);
  vtkNew<vtkCellArray> lines;
  for (int s = 0; s < 30; ++s)
  {
    const int count = 2 + static_cast<int>(random() % 20);
    lines->InsertNextCell(count);
    for (int k = 0; k < count; ++k)
    {
      lines->InsertCellPoint(static_cast<vtkIdType>(random() % 200)); // shared points
    }
  }
  data->SetLines(lines);
  const int types[] = { VTK_SIGNED_CHAR, VTK_SHORT, VTK_INT, VTK_LONG_LONG, VTK_UNSIGNED_CHAR,
    VTK_UNSIGNED_SHORT, VTK_UNSIGNED_INT, VTK_UNSIGNED_LONG_LONG, VTK_FLOAT, VTK_DOUBLE };
  for (int type : types)
  {
    for (int components : { 1, 3 })
    {
      for (bool perPoint : { true, false })
      {
        vtkSmartPointer<vtkDataArray> array;
        array.TakeReference(vtkDataArray::CreateDataArray(type));
        array->SetNumberOfComponents(components);
        const vtkIdType tuples = perPoint ? 200 : 31; // cells: the vertex, then 30 lines
        array->SetNumberOfTuples(tuples);
        for (vtkIdType t = 0; t < tuples; ++t)
        {
          for (int c = 0; c < components; ++c)
          {
            array->SetComponent(t, c, static_cast<double>(random() % 100) - (type == VTK_UNSIGNED_CHAR || type == VTK_UNSIGNED_SHORT || type == VTK_UNSIGNED_INT || type == VTK_UNSIGNED_LONG_LONG ? 0 : 50) + (type >= VTK_FLOAT ? 0.25 : 0.0));
          }
        }
        const std::string name = std::string(array->GetDataTypeAsString()) + "x" +
          std::to_string(components);
        array->SetName(name.c_str());
        (perPoint ? static_cast<vtkFieldData*>(data->GetPointData()) : data->GetCellData())
          ->AddArray(array);
      }
    }
  }
  vtkNew<vtkUnsignedCharArray> group;
  group->SetName("group:CST_left");
  group->SetNumberOfValues(31);
  for (vtkIdType c = 0; c < 31; ++c)
  {
    group->SetValue(c, c % 3 == 1);
  }
  data->GetCellData()->AddArray(group);
  vtkNew<vtkFloatArray> colour;
  colour->SetName("dpg:CST_left:colour");
  colour->SetNumberOfComponents(3);
  colour->InsertNextTuple3(1.0, 0.5, 0.25);
  data->GetFieldData()->AddArray(colour);
  vtkNew<vtkDoubleArray> affine;
  affine->SetName("VOXEL_TO_RASMM");
  for (int k = 0; k < 16; ++k)
  {
    affine->InsertNextValue(k % 5 == 0 ? 2.0 : (k == 3 ? -90.5 : 0.0));
  }
  data->GetFieldData()->AddArray(affine);
  return data;
}

vtkPolyData* ReadBack(vtkSightlineTRXReader* reader, Messages* messages)
{
  reader->AddObserver(vtkCommand::ErrorEvent, messages);
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->Update();
  return reader->GetOutput();
}

void ExpectSameTractogram(vtkPolyData* input, vtkPolyData* output)
{
  // Line s of the input is streamline s: its points, in order, and every array's values.
  vtkCellArray* lines = input->GetLines();
  ASSERT_EQ(output->GetNumberOfCells(), lines->GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  vtkIdType vertex = 0;
  for (vtkIdType s = 0; s < lines->GetNumberOfCells(); ++s)
  {
    lines->GetCellAtId(s, ids);
    ASSERT_EQ(output->GetCell(s)->GetNumberOfPoints(), ids->GetNumberOfIds()) << s;
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k, ++vertex)
    {
      double a[3], b[3];
      input->GetPoint(ids->GetId(k), a);
      output->GetPoint(vertex, b);
      EXPECT_EQ(a[0], b[0]);
      EXPECT_EQ(a[1], b[1]);
      EXPECT_EQ(a[2], b[2]);
      for (int i = 0; i < input->GetPointData()->GetNumberOfArrays(); ++i)
      {
        vtkDataArray* in = input->GetPointData()->GetArray(i);
        vtkDataArray* out = output->GetPointData()->GetArray(in->GetName());
        ASSERT_NE(out, nullptr) << in->GetName();
        ASSERT_EQ(out->GetDataType(), in->GetDataType()) << in->GetName();
        ASSERT_EQ(out->GetNumberOfComponents(), in->GetNumberOfComponents());
        for (int c = 0; c < in->GetNumberOfComponents(); ++c)
        {
          EXPECT_EQ(out->GetComponent(vertex, c), in->GetComponent(ids->GetId(k), c));
        }
      }
    }
    for (int i = 0; i < input->GetCellData()->GetNumberOfArrays(); ++i)
    {
      vtkDataArray* in = input->GetCellData()->GetArray(i);
      vtkDataArray* out = output->GetCellData()->GetArray(in->GetName());
      ASSERT_NE(out, nullptr) << in->GetName();
      ASSERT_EQ(out->GetDataType(), in->GetDataType()) << in->GetName();
      for (int c = 0; c < in->GetNumberOfComponents(); ++c)
      {
        EXPECT_EQ(out->GetComponent(s, c) != 0, in->GetComponent(s + 1, c) != 0);
        if (std::string(in->GetName()).compare(0, 6, "group:") != 0)
        {
          EXPECT_EQ(out->GetComponent(s, c), in->GetComponent(s + 1, c)) << in->GetName();
        }
      }
    }
  }
  EXPECT_EQ(output->GetNumberOfPoints(), vertex);
  vtkDataArray* colour = output->GetFieldData()->GetArray("dpg:CST_left:colour");
  ASSERT_NE(colour, nullptr);
  EXPECT_EQ(colour->GetNumberOfValues(), 3);
  EXPECT_EQ(colour->GetComponent(0, 1), 0.5);
  vtkDataArray* affine = output->GetFieldData()->GetArray("VOXEL_TO_RASMM");
  ASSERT_NE(affine, nullptr);
  EXPECT_EQ(affine->GetComponent(3, 0), -90.5);
  EXPECT_EQ(affine->GetComponent(5, 0), 2.0);
}
} // namespace

TEST(TRX, EveryArrayTypeRoundTripsInEveryForm)
{
  vtkSmartPointer<vtkPolyData> input = Tractogram();
  struct Form
  {
    const char* Name;
    bool Compress, Directory;
  };
  for (const Form& form : { Form{ "stored.trx", false, false }, Form{ "deflated.trx", true, false },
         Form{ "folder", false, true } })
  {
    SCOPED_TRACE(form.Name);
    const std::string path = TempPath(form.Name);
    std::filesystem::remove_all(path);
    vtkNew<vtkSightlineTRXWriter> writer;
    vtkNew<Messages> written;
    writer->AddObserver(vtkCommand::ErrorEvent, written);
    writer->AddObserver(vtkCommand::WarningEvent, written);
    writer->SetInputData(input);
    writer->SetFileName(path.c_str());
    writer->SetCompress(form.Compress);
    writer->SetWriteToDirectory(form.Directory);
    writer->Write();
    EXPECT_EQ(written->Errors, "");
    EXPECT_NE(written->Warnings.find("1 vertex, 0 polygon and 0 strip cells are left out"),
      std::string::npos)
      << written->Warnings;
    EXPECT_TRUE(vtkSightlineTRXReader::CanReadFile(path.c_str()));
    vtkNew<vtkSightlineTRXReader> reader;
    vtkNew<Messages> messages;
    reader->SetFileName(path.c_str());
    vtkPolyData* output = ReadBack(reader, messages);
    EXPECT_EQ(messages->Errors, "");
    EXPECT_EQ(output->GetPoints()->GetDataType(), VTK_DOUBLE); // float64 positions as input
    ExpectSameTractogram(input, output);
    if (!form.Directory)
    {
      std::ifstream file(path, std::ios::binary);
      vtkNew<vtkSightlineTRXReader> fromString;
      fromString->SetInputString(
        std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()));
      fromString->ReadFromInputStringOn();
      vtkNew<Messages> stringMessages;
      ExpectSameTractogram(input, ReadBack(fromString, stringMessages));
      EXPECT_EQ(stringMessages->Errors, "");
    }
  }
}

TEST(TRX, Float16PositionsRoundToNearestAndOverflowIsAnError)
{
  vtkNew<vtkPolyData> data;
  vtkNew<vtkPoints> points;
  // 1 + 2^-11 is halfway between two halves: it rounds to even (1); 65519 rounds to 65504,
  // 2^-24 is the smallest subnormal half, 3 * 2^-26 rounds up to it.
  points->InsertNextPoint(1.0 + std::ldexp(1.0, -11), 65519.0, std::ldexp(1.0, -24));
  points->InsertNextPoint(3.0 * std::ldexp(1.0, -26), -2049.0, 0.1);
  data->SetPoints(points);
  vtkNew<vtkCellArray> lines;
  lines->InsertNextCell({ 0, 1 });
  data->SetLines(lines);
  const std::string path = TempPath("half.trx");
  vtkNew<vtkSightlineTRXWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(path.c_str());
  writer->SetPositionsType(vtkSightlineTRXWriter::POSITIONS_FLOAT16);
  writer->Write();
  vtkNew<vtkSightlineTRXReader> reader;
  vtkNew<Messages> messages;
  reader->SetFileName(path.c_str());
  vtkPolyData* output = ReadBack(reader, messages);
  ASSERT_EQ(output->GetNumberOfPoints(), 2);
  double a[3], b[3];
  output->GetPoint(0, a);
  output->GetPoint(1, b);
  EXPECT_EQ(a[0], 1.0);
  EXPECT_EQ(a[1], 65504.0);
  EXPECT_EQ(a[2], std::ldexp(1.0, -24));
  EXPECT_EQ(b[0], std::ldexp(1.0, -24));
  EXPECT_EQ(b[1], -2048.0); // halves step by 2 there: -2049 is a tie, to even
  EXPECT_EQ(b[2], 0.0999755859375);

  points->SetPoint(1, 0.0, 70000.0, 0.0);
  points->Modified();
  vtkNew<Messages> errors;
  writer->AddObserver(vtkCommand::ErrorEvent, errors);
  writer->Write();
  EXPECT_NE(errors->Errors.find("beyond float16's range"), std::string::npos) << errors->Errors;
}

// A directory that claims 2^40 vertices with a 36-byte positions file: refused from the sizes,
// before anything is allocated; and names that are not UTF-8 are quoted as valid UTF-8.
TEST(TRX, HugeClaimsFailBeforeAllocatingAndMessagesStayUtf8)
{
  const std::string folder = TempPath("claims");
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder + "/dpv");
  auto write = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(folder + "/" + name, std::ios::binary) << bytes;
  };
  write("header.json", "{\"NB_VERTICES\": 1099511627776, \"NB_STREAMLINES\": 1}");
  write("positions.3.float32", std::string(36, '\0'));
  write("offsets.uint64", std::string(8, '\0'));
  const long before = PeakMiB();
  vtkNew<vtkSightlineTRXReader> reader;
  vtkNew<Messages> messages;
  reader->SetFileName(folder.c_str());
  ReadBack(reader, messages);
  EXPECT_NE(messages->Errors.find("holds 3 rows, not 1099511627776"), std::string::npos)
    << messages->Errors;
  EXPECT_LT(PeakMiB() - before, 64);

  write("header.json", "{\"NB_VERTICES\": 3, \"NB_STREAMLINES\": 1}");
  write("dpv/\xff\xfe\xc3\x28.float32", std::string(4, '\0'));
  vtkNew<vtkSightlineTRXReader> again;
  vtkNew<Messages> quoted;
  again->SetFileName(folder.c_str());
  ReadBack(again, quoted);
  EXPECT_NE(quoted->Errors.find("dpv/\\xFF\\xFE\\xC3("), std::string::npos) << quoted->Errors;
}
