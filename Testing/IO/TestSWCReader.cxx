// SPDX-License-Identifier: BSD-3-Clause
// vtkSightlineSWCReader on hand-written SWC files (Testing/Data/SWC) that cover what real
// files do: comments and blank lines, NeuroMorpho's three-point soma, unsorted and
// non-contiguous ids, parents after children, several roots, a childless root, zero radii,
// extra columns; and broken files, which must be reported by line or id without output.
// The expected structure is read from the files by a parser of the test's own.
#include "vtkSightlineSWCReader.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkExecutive.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace
{
std::string SWC(const std::string& name)
{
  return std::string(SIGHTLINE_SOURCE_DIR) + "/Testing/Data/SWC/" + name;
}

/// (id, parent id, radius) per data line, in file order: the test's own reading.
struct Line
{
  long long id, parent;
  double radius;
};
std::vector<Line> ReadLines(const std::string& path)
{
  std::vector<Line> lines;
  std::ifstream file(path);
  for (std::string text; std::getline(file, text);)
  {
    text = text.substr(0, text.find('#'));
    std::istringstream in(text);
    double id, type, x, y, z, r, parent;
    if (in >> id >> type >> x >> y >> z >> r >> parent)
      lines.push_back({ (long long)id, (long long)parent, r });
  }
  return lines;
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

/// Checks the output against the file: arrays, parents, every link once in chains that only
/// break at branch points.
void CheckStructure(const std::string& name, vtkSightlineSWCReader* reader)
{
  const std::vector<Line> lines = ReadLines(SWC(name));
  vtkPolyData* out = reader->GetOutput();
  const vtkIdType n = out->GetNumberOfPoints();
  ASSERT_EQ(n, vtkIdType(lines.size())) << name;
  vtkDataArray* ids = out->GetPointData()->GetArray("SampleId");
  vtkDataArray* parents = out->GetPointData()->GetArray("ParentIndex");
  vtkDataArray* radius = out->GetPointData()->GetScalars();
  ASSERT_TRUE(ids && parents && radius && out->GetPointData()->GetArray("Type")) << name;
  EXPECT_STREQ(radius->GetName(), "Radius");
  std::set<std::pair<vtkIdType, vtkIdType>> links; // (parent, child) point indices
  std::map<vtkIdType, int> children;
  int roots = 0;
  for (vtkIdType i = 0; i < n; ++i)
  {
    EXPECT_EQ((long long)ids->GetComponent(i, 0), lines[i].id) << name << " point " << i;
    EXPECT_FLOAT_EQ(radius->GetComponent(i, 0), float(lines[i].radius));
    const vtkIdType p = vtkIdType(parents->GetComponent(i, 0));
    if (lines[i].parent < 0)
    {
      EXPECT_EQ(p, -1);
      ++roots;
      continue;
    }
    ASSERT_GE(p, 0);
    EXPECT_EQ((long long)ids->GetComponent(p, 0), lines[i].parent) << name << " point " << i;
    links.insert({ p, i });
    ++children[p];
  }
  EXPECT_EQ(reader->GetNumberOfRoots(), roots);
  // Polylines: consecutive pairs are exactly the links, each once, parent first; interior
  // points have one child.
  std::multiset<std::pair<vtkIdType, vtkIdType>> drawn;
  vtkNew<vtkIdList> cell;
  for (vtkIdType c = 0; c < out->GetLines()->GetNumberOfCells(); ++c)
  {
    out->GetLines()->GetCellAtId(c, cell);
    for (vtkIdType k = 0; k + 1 < cell->GetNumberOfIds(); ++k)
    {
      drawn.insert({ cell->GetId(k), cell->GetId(k + 1) });
      if (k > 0)
      {
        EXPECT_EQ(children[cell->GetId(k)], 1) << name << ": a chain runs through a branch point";
      }
    }
  }
  EXPECT_EQ(drawn.size(), links.size()) << name;
  for (const auto& link : links)
    EXPECT_EQ(drawn.count(link), 1u) << name << " link " << link.first << "->" << link.second;
}
} // namespace

TEST(SWCReader, ThreePointSomaNeuron)
{
  vtkNew<vtkSightlineSWCReader> reader;
  reader->SetFileName(SWC("neuron_three_point_soma.swc").c_str());
  reader->Update();
  CheckStructure("neuron_three_point_soma.swc", reader);
  EXPECT_EQ(reader->GetNumberOfRoots(), 1);
  // The soma (4 children: two soma points, axon, dendrite) and two dendrite forks.
  EXPECT_EQ(reader->GetNumberOfBranchPoints(), 3);
  EXPECT_EQ(reader->GetOutput()->GetVerts()->GetNumberOfCells(), 0);
  double p[3];
  reader->GetOutput()->GetPoint(10, p); // sample 11
  EXPECT_DOUBLE_EQ(p[0], -24.0);
  EXPECT_DOUBLE_EQ(p[2], 1.0);
}

TEST(SWCReader, UnsortedIdsSeveralRootsAndAChildlessRoot)
{
  vtkNew<vtkSightlineSWCReader> reader;
  reader->SetFileName(SWC("unsorted_two_roots.swc").c_str());
  reader->Update();
  CheckStructure("unsorted_two_roots.swc", reader);
  EXPECT_EQ(reader->GetNumberOfRoots(), 3);
  EXPECT_EQ(reader->GetNumberOfBranchPoints(), 0);
  // The childless root is a vertex, so that it is still drawn.
  ASSERT_EQ(reader->GetOutput()->GetVerts()->GetNumberOfCells(), 1);
  EXPECT_EQ(reader->GetOutput()->GetLines()->GetNumberOfCells(), 2);
}

TEST(SWCReader, ZeroRadiiAreKeptAndCounted)
{
  vtkNew<vtkSightlineSWCReader> reader;
  vtkNew<Messages> messages;
  reader->AddObserver(vtkCommand::WarningEvent, messages);
  reader->SetFileName(SWC("zero_radius.swc").c_str());
  reader->Update();
  CheckStructure("zero_radius.swc", reader);
  EXPECT_EQ(reader->GetNumberOfZeroRadii(), 2);
  EXPECT_NE(messages->warnings.find("2 of 4 samples have radius 0"), std::string::npos) << messages->warnings;
}

TEST(SWCReader, BrokenFilesAreReportedByLineOrId)
{
  const std::pair<const char*, const char*> cases[] = {
    { "bad_cycle.swc", "form a cycle" },
    { "bad_self_parent.swc", "form a cycle" },
    { "bad_missing_parent.swc", "the parent 7 of sample 2 is not in the file" },
    { "bad_duplicate_id.swc", "line 3: the id 2 was already used on line 2" },
    { "bad_negative_radius.swc", "line 2: sample 2 has the negative radius -0.5" },
    { "bad_nan_radius.swc", "line 2: sample 2 has a non-finite position or radius" },
    { "bad_short_line.swc", "line 2: 6 fields" },
    { "bad_not_a_number.swc", "line 2:" },
    { "bad_empty.swc", "has no samples" },
    { "does_not_exist.swc", "Cannot open" },
  };
  for (const auto& [file, expected] : cases)
  {
    vtkNew<vtkSightlineSWCReader> reader;
    vtkNew<Messages> messages;
    reader->AddObserver(vtkCommand::ErrorEvent, messages);
    reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, messages);
    reader->SetFileName(SWC(file).c_str());
    reader->Update();
    EXPECT_NE(messages->errors.find(expected), std::string::npos) << file << ": " << messages->errors;
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0) << file;
  }
}
