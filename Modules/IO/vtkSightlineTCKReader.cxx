// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTCKReader.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include "SightlineMRtrixHeader.h"
#include "SightlineReaderInput.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSightlineTCKReader);

namespace
{
using namespace sightline_io;

constexpr const char* kMagic = "mrtrix tracks";
} // namespace

vtkSightlineTCKReader::vtkSightlineTCKReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSightlineTCKReader::~vtkSightlineTCKReader()
{
  this->SetFileName(nullptr);
}

void vtkSightlineTCKReader::SetInputString(const std::string& bytes)
{
  if (bytes != this->InputString)
  {
    this->InputString = bytes;
    this->Modified();
  }
}

int vtkSightlineTCKReader::CanReadFile(const char* fileName)
{
  std::ifstream file(fileName ? fileName : "", std::ios::binary);
  std::string first;
  return file && std::getline(file, first) && Trim(first) == kMagic;
}

int vtkSightlineTCKReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  std::string bytes, error;
  if (!LoadInput(this->FileName, this->ReadFromInputString, this->InputString, bytes, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const std::string name = InputName(this->FileName, this->ReadFromInputString);
  std::size_t at = 0;
  MRtrixHeader header;
  if (!ReadMRtrixHeader(
        [&] { return at < bytes.size() ? static_cast<unsigned char>(bytes[at++]) : -1; },
        kMagic, "MRtrix track file", header, error))
  {
    vtkErrorMacro(<< name << ": " << error);
    return 0;
  }
  const std::string datatype = header.Value("datatype");
  MRtrixDataType type;
  if (!ParseDataType(datatype, type) ||
    (type.Type != MRtrixType::Float32 && type.Type != MRtrixType::Float64))
  {
    vtkErrorMacro(<< name << ": datatype '" << Quote(datatype)
                  << "' is not one of Float32LE, Float32BE, Float64LE, Float64BE.");
    return 0;
  }
  const std::string location = header.Value("file");
  long long offset = -1;
  const long long size = static_cast<long long>(bytes.size());
  if (!ParseDataFileEntry(location, offset) || offset < static_cast<long long>(header.Size) ||
    offset > size)
  {
    vtkErrorMacro(<< name << ": the 'file' entry '" << Quote(location)
                  << "' does not give a data offset inside the file (" << size
                  << " bytes) and after the header (" << header.Size << " bytes).");
    return 0;
  }

  // The data: triplets until the Inf triplet, converted in place to the host's byte order.
  const std::size_t valueSize = static_cast<std::size_t>(type.Bytes);
  const std::size_t triplets = (bytes.size() - offset) / (3 * valueSize);
  char* raw = &bytes[offset];
  ToHostByteOrder(raw, 3 * triplets, type);
  auto value = [&](std::size_t index) {
    if (valueSize == 4)
    {
      float v;
      std::memcpy(&v, raw + 4 * index, 4);
      return static_cast<double>(v);
    }
    double v;
    std::memcpy(&v, raw + 8 * index, 8);
    return v;
  };
  // Points are stored in single precision: a finite Float64 value beyond its range would
  // become an infinity.
  constexpr double largest = std::numeric_limits<float>::max();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  std::vector<double> current; // the streamline being read, added once it is complete
  bool finished = false, outOfRange = false;
  vtkIdType skipped = 0, firstSkipped = -1;
  double badValue = 0.0;
  auto endStreamline = [&] {
    if (outOfRange)
    {
      firstSkipped = skipped == 0 ? lines->GetNumberOfCells() : firstSkipped;
      ++skipped;
    }
    else if (!current.empty())
    {
      const vtkIdType first = points->GetNumberOfPoints();
      const vtkIdType count = static_cast<vtkIdType>(current.size() / 3);
      lines->InsertNextCell(count);
      for (vtkIdType k = 0; k < count; ++k)
      {
        points->InsertNextPoint(&current[3 * k]);
        lines->InsertCellPoint(first + k);
      }
    }
    current.clear();
    outOfRange = false;
  };
  for (std::size_t t = 0; t < triplets; ++t)
  {
    const double p[3] = { value(3 * t), value(3 * t + 1), value(3 * t + 2) };
    if (std::isinf(p[0]) || std::isinf(p[1]) || std::isinf(p[2]))
    {
      finished = true;
      endStreamline();
      break;
    }
    if (std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2]))
    {
      endStreamline();
      continue;
    }
    for (const double v : p)
    {
      if (std::fabs(v) > largest && !outOfRange)
      {
        outOfRange = true;
        badValue = skipped == 0 ? v : badValue;
      }
    }
    current.insert(current.end(), p, p + 3);
  }
  if (!finished)
  {
    vtkWarningMacro(<< name << " has no end marker (cut short?); " << lines->GetNumberOfCells()
                    << " complete streamlines read"
                    << (current.empty() ? "" : ", the last incomplete one dropped") << ".");
  }
  if (skipped > 0)
  {
    vtkWarningMacro(<< name << ": " << skipped << " streamlines (the first is number "
                    << firstSkipped << ", with the value " << badValue
                    << ") have coordinates beyond single precision and were left out.");
  }
  const std::string count = header.Value("count");
  long long expected = 0;
  if (!count.empty() &&
    (!ParseInteger(count, expected) || expected != lines->GetNumberOfCells() + skipped))
  {
    vtkWarningMacro(<< name << ": the header's count is " << Quote(count) << " but "
                    << lines->GetNumberOfCells() + skipped << " streamlines were read.");
  }
  output->SetPoints(points);
  output->SetLines(lines);
  return 1;
}

void vtkSightlineTCKReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ReadFromInputString: " << this->ReadFromInputString << "\n";
}
