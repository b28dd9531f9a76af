// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineSWCReader.h"

#include "vtkCellArray.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "SightlineReaderInput.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

vtkStandardNewMacro(vtkSightlineSWCReader);

namespace
{
struct Sample
{
  long long id = 0;
  int type = 0;
  double position[3] = { 0, 0, 0 };
  double radius = 0;
  long long parent = -1;
  std::size_t line = 0;
};

/// Parses a whole token as a number; false for anything else ("1.5abc", "", "nan" is a
/// number) and for numbers beyond double range ("1e999"). Numbers below the normal range
/// ("1e-310") underflow gracefully to a subnormal or zero and are accepted.
bool ParseDouble(const std::string& token, double& value)
{
  char* end = nullptr;
  errno = 0;
  value = std::strtod(token.c_str(), &end);
  return end != token.c_str() && *end == '\0' && !(errno == ERANGE && std::isinf(value));
}

const char* const FieldNames[7] = { "id", "type", "x", "y", "z", "radius", "parent" };

bool ParseInteger(const std::string& token, long long& value)
{
  double number;
  if (!ParseDouble(token, number) || !std::isfinite(number) || number != std::floor(number) ||
    std::abs(number) > 9e15)
  {
    return false;
  }
  value = static_cast<long long>(number); // some writers store ids as "12.0"
  return true;
}
} // namespace

vtkSightlineSWCReader::vtkSightlineSWCReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSightlineSWCReader::~vtkSightlineSWCReader()
{
  this->SetFileName(nullptr);
}

void vtkSightlineSWCReader::SetInputString(const std::string& text)
{
  if (text != this->InputString)
  {
    this->InputString = text;
    this->Modified();
  }
}

int vtkSightlineSWCReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  outputVector->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkSightlineSWCReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkPolyData* output = vtkPolyData::GetData(outInfo);
  // SWC files are small (a neuron is thousands of samples): piece 0 reads the whole file and
  // every other piece is empty.
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) &&
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) > 0)
  {
    output->Initialize();
    return 1;
  }
  this->NumberOfRoots = this->NumberOfBranchPoints = this->NumberOfZeroRadii = 0;
  std::string text, error;
  if (!sightline_io::LoadInput(
        this->FileName, this->ReadFromInputString, this->InputString, text, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const std::string name = sightline_io::InputName(this->FileName, this->ReadFromInputString);
  std::istringstream file(text);

  // Samples in file order.
  std::vector<Sample> samples;
  std::unordered_map<long long, std::size_t> indexOfId;
  std::string line;
  std::size_t lineNumber = 0;
  while (std::getline(file, line))
  {
    ++lineNumber;
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos)
    {
      line.erase(hash);
    }
    std::istringstream fields(line);
    std::vector<std::string> tokens;
    for (std::string token; fields >> token;)
    {
      tokens.push_back(token);
    }
    if (tokens.empty())
    {
      continue;
    }
    if (tokens.size() < 7)
    {
      vtkErrorMacro(<< name << " line " << lineNumber << ": " << tokens.size()
                    << " fields; an SWC sample needs 7 (id type x y z radius parent).");
      return 0;
    }
    Sample s;
    s.line = lineNumber;
    long long type = 0;
    double* const numbers[4] = { &s.position[0], &s.position[1], &s.position[2], &s.radius };
    for (int field = 0; field < 7; ++field)
    {
      const bool integer = field == 0 || field == 1 || field == 6;
      long long* const target = field == 0 ? &s.id : (field == 1 ? &type : &s.parent);
      if (integer ? ParseInteger(tokens[field], *target)
                  : ParseDouble(tokens[field], *numbers[field - 2]))
      {
        continue;
      }
      vtkErrorMacro(<< name << " line " << lineNumber << ": the " << FieldNames[field]
                    << " field \"" << sightline_io::Quote(tokens[field]) << "\" is not "
                    << (integer ? "an integer" : "a number in double range")
                    << " (a sample is id type x y z radius parent).");
      return 0;
    }
    s.type = static_cast<int>(type);
    if (!std::isfinite(s.position[0]) || !std::isfinite(s.position[1]) ||
      !std::isfinite(s.position[2]) || !std::isfinite(s.radius))
    {
      vtkErrorMacro(<< name << " line " << lineNumber << ": sample " << s.id
                    << " has a non-finite position or radius.");
      return 0;
    }
    if (s.radius < 0.0)
    {
      vtkErrorMacro(<< name << " line " << lineNumber << ": sample " << s.id
                    << " has the negative radius " << s.radius << ".");
      return 0;
    }
    if (!indexOfId.emplace(s.id, samples.size()).second)
    {
      vtkErrorMacro(<< name << " line " << lineNumber << ": the id " << s.id
                    << " was already used on line " << samples[indexOfId[s.id]].line << ".");
      return 0;
    }
    samples.push_back(s);
  }
  if (samples.empty())
  {
    vtkErrorMacro(<< name << " has no samples.");
    return 0;
  }

  // Parents as point indices; children in CSR form.
  const vtkIdType n = static_cast<vtkIdType>(samples.size());
  std::vector<vtkIdType> parentIndex(n, -1);
  std::vector<vtkIdType> childCount(n + 1, 0);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const Sample& s = samples[i];
    if (s.parent < 0)
    {
      ++this->NumberOfRoots;
      continue;
    }
    const auto parent = indexOfId.find(s.parent);
    if (parent == indexOfId.end())
    {
      vtkErrorMacro(<< name << " line " << s.line << ": the parent " << s.parent
                    << " of sample " << s.id << " is not in the file.");
      return 0;
    }
    parentIndex[i] = static_cast<vtkIdType>(parent->second);
    ++childCount[parentIndex[i] + 1];
  }
  std::vector<vtkIdType> firstChild(childCount);
  for (vtkIdType i = 0; i < n; ++i)
  {
    firstChild[i + 1] += firstChild[i];
  }
  std::vector<vtkIdType> children(n);
  {
    std::vector<vtkIdType> fill(firstChild.begin(), firstChild.end() - 1);
    for (vtkIdType i = 0; i < n; ++i)
    {
      if (parentIndex[i] >= 0)
      {
        children[fill[parentIndex[i]]++] = i;
      }
    }
  }
  auto childrenOf = [&](vtkIdType i) { return firstChild[i + 1] - firstChild[i]; };

  // Every sample must hang from a root: the ones that do not sit on (or below) a cycle.
  std::vector<char> reached(n, 0);
  std::vector<vtkIdType> stack;
  for (vtkIdType i = 0; i < n; ++i)
  {
    if (parentIndex[i] < 0)
    {
      stack.push_back(i);
    }
  }
  vtkIdType reachedCount = 0;
  while (!stack.empty())
  {
    const vtkIdType i = stack.back();
    stack.pop_back();
    reached[i] = 1;
    ++reachedCount;
    for (vtkIdType c = firstChild[i]; c < firstChild[i + 1]; ++c)
    {
      stack.push_back(children[c]);
    }
  }
  if (reachedCount < n)
  {
    // Walk up from an unreached sample until a sample repeats: that one is on the cycle.
    vtkIdType i = 0;
    while (reached[i])
    {
      ++i;
    }
    std::vector<char> seen(n, 0);
    while (!seen[i])
    {
      seen[i] = 1;
      i = parentIndex[i];
    }
    vtkErrorMacro(<< name << ": the parents of sample " << samples[i].id << " (line "
                  << samples[i].line << ") form a cycle; " << (n - reachedCount)
                  << " samples do not descend from a root.");
    return 0;
  }

  // Points and arrays.
  vtkNew<vtkPoints> points;
  points->SetDataType(VTK_DOUBLE); // SWC coordinates keep their precision
  points->SetNumberOfPoints(n);
  vtkNew<vtkFloatArray> radius;
  radius->SetName("Radius");
  radius->SetNumberOfTuples(n);
  vtkNew<vtkIntArray> type;
  type->SetName("Type");
  type->SetNumberOfTuples(n);
  vtkNew<vtkIdTypeArray> sampleId;
  sampleId->SetName("SampleId");
  sampleId->SetNumberOfTuples(n);
  vtkNew<vtkIdTypeArray> parents;
  parents->SetName("ParentIndex");
  parents->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    const Sample& s = samples[i];
    points->SetPoint(i, s.position);
    radius->SetValue(i, static_cast<float>(s.radius));
    type->SetValue(i, s.type);
    sampleId->SetValue(i, static_cast<vtkIdType>(s.id));
    parents->SetValue(i, parentIndex[i]);
    this->NumberOfZeroRadii += s.radius == 0.0;
    this->NumberOfBranchPoints += childrenOf(i) >= 2;
  }

  // Maximal unbranched chains from every root and branch point; childless roots as vertices.
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkCellArray> vertices;
  std::vector<vtkIdType> chain;
  for (vtkIdType start = 0; start < n; ++start)
  {
    if (parentIndex[start] >= 0 && childrenOf(start) < 2)
    {
      continue;
    }
    if (childrenOf(start) == 0)
    {
      vertices->InsertNextCell(1, &start);
      continue;
    }
    for (vtkIdType c = firstChild[start]; c < firstChild[start + 1]; ++c)
    {
      chain.assign({ start, children[c] });
      while (childrenOf(chain.back()) == 1)
      {
        chain.push_back(children[firstChild[chain.back()]]);
      }
      lines->InsertNextCell(static_cast<vtkIdType>(chain.size()), chain.data());
    }
  }

  output->SetPoints(points);
  output->SetLines(lines);
  if (vertices->GetNumberOfCells() > 0)
  {
    output->SetVerts(vertices);
  }
  output->GetPointData()->SetScalars(radius);
  output->GetPointData()->AddArray(type);
  output->GetPointData()->AddArray(sampleId);
  output->GetPointData()->AddArray(parents);
  if (this->NumberOfZeroRadii > 0)
  {
    vtkWarningMacro(<< name << ": " << this->NumberOfZeroRadii << " of " << n
                    << " samples have radius 0.");
  }
  return 1;
}

void vtkSightlineSWCReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ReadFromInputString: " << this->ReadFromInputString << "\n";
  os << indent << "NumberOfRoots: " << this->NumberOfRoots << "\n";
  os << indent << "NumberOfBranchPoints: " << this->NumberOfBranchPoints << "\n";
  os << indent << "NumberOfZeroRadii: " << this->NumberOfZeroRadii << "\n";
}
