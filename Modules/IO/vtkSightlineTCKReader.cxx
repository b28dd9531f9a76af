#include "vtkSightlineTCKReader.h"

#include "vtkCellArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSightlineTCKReader);

namespace
{
constexpr const char* kMagic = "mrtrix tracks";

std::string Trim(const std::string& text)
{
  const std::size_t begin = text.find_first_not_of(" \t\r");
  const std::size_t end = text.find_last_not_of(" \t\r");
  return begin == std::string::npos ? std::string() : text.substr(begin, end - begin + 1);
}

/// Reverses the bytes of each `size`-byte value when the file's byte order is not the host's.
void SwapBytes(char* data, std::size_t count, std::size_t size)
{
  for (std::size_t i = 0; i < count; ++i)
  {
    std::reverse(data + i * size, data + (i + 1) * size);
  }
}

bool HostIsLittleEndian()
{
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}
} // namespace

vtkSightlineTCKReader::vtkSightlineTCKReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSightlineTCKReader::~vtkSightlineTCKReader()
{
  this->SetFileName(nullptr);
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
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro(<< "No FileName was set.");
    return 0;
  }
  const std::string name = this->FileName;
  std::ifstream file(name, std::ios::binary);
  if (!file)
  {
    vtkErrorMacro(<< "Cannot open the track file '" << name << "' (missing or unreadable).");
    return 0;
  }
  std::string line;
  if (!std::getline(file, line) || Trim(line) != kMagic)
  {
    vtkErrorMacro(<< "'" << name << "' is not an MRtrix track file: its first line is not \""
                  << kMagic << "\".");
    return 0;
  }
  std::map<std::string, std::string> header;
  bool ended = false;
  while (std::getline(file, line))
  {
    line = Trim(line);
    if (line == "END")
    {
      ended = true;
      break;
    }
    const std::size_t colon = line.find(':');
    if (colon != std::string::npos)
    {
      header[Trim(line.substr(0, colon))] = Trim(line.substr(colon + 1));
    }
  }
  if (!ended)
  {
    vtkErrorMacro(<< "'" << name << "': the header has no END line (truncated file?).");
    return 0;
  }
  const std::string datatype = header["datatype"];
  std::size_t valueSize = 0;
  bool little = true;
  if (datatype == "Float32LE" || datatype == "Float32BE")
  {
    valueSize = 4;
  }
  else if (datatype == "Float64LE" || datatype == "Float64BE")
  {
    valueSize = 8;
  }
  if (valueSize == 0)
  {
    vtkErrorMacro(<< "'" << name << "': datatype '" << datatype
                  << "' is not one of Float32LE, Float32BE, Float64LE, Float64BE.");
    return 0;
  }
  little = datatype.compare(datatype.size() - 2, 2, "LE") == 0;
  const std::string location = header["file"];
  long long offset = -1;
  if (location.size() > 2 && location[0] == '.' && location[1] == ' ')
  {
    offset = std::atoll(location.c_str() + 2);
  }
  file.seekg(0, std::ios::end);
  const long long size = static_cast<long long>(file.tellg());
  if (offset <= 0 || offset > size)
  {
    vtkErrorMacro(<< "'" << name << "': the 'file' entry '" << location
                  << "' does not give a data offset inside the file (" << size << " bytes).");
    return 0;
  }

  // The data: triplets until the Inf triplet.
  file.seekg(offset);
  std::vector<char> raw(static_cast<std::size_t>(size - offset));
  file.read(raw.data(), static_cast<std::streamsize>(raw.size()));
  const std::size_t triplets = raw.size() / (3 * valueSize);
  if (little != HostIsLittleEndian())
  {
    SwapBytes(raw.data(), 3 * triplets, valueSize);
  }
  auto value = [&](std::size_t index)
  {
    if (valueSize == 4)
    {
      float v;
      std::memcpy(&v, raw.data() + 4 * index, 4);
      return static_cast<double>(v);
    }
    double v;
    std::memcpy(&v, raw.data() + 8 * index, 8);
    return v;
  };
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  std::vector<vtkIdType> current;
  bool finished = false;
  for (std::size_t t = 0; t < triplets; ++t)
  {
    const double p[3] = { value(3 * t), value(3 * t + 1), value(3 * t + 2) };
    if (std::isinf(p[0]) || std::isinf(p[1]) || std::isinf(p[2]))
    {
      finished = true;
      break;
    }
    if (std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2]))
    {
      if (!current.empty())
      {
        lines->InsertNextCell(static_cast<vtkIdType>(current.size()), current.data());
      }
      current.clear();
      continue;
    }
    current.push_back(points->InsertNextPoint(p));
  }
  if (!finished)
  {
    vtkWarningMacro(<< "'" << name << "' has no end marker (cut short?); "
                    << lines->GetNumberOfCells() << " complete streamlines read"
                    << (current.empty() ? "" : ", the last incomplete one dropped") << ".");
  }
  if (!current.empty() && finished)
  {
    lines->InsertNextCell(static_cast<vtkIdType>(current.size()), current.data());
  }
  const std::string count = header["count"];
  if (!count.empty() && std::atoll(count.c_str()) != lines->GetNumberOfCells())
  {
    vtkWarningMacro(<< "'" << name << "': the header's count is " << count << " but "
                    << lines->GetNumberOfCells() << " streamlines were read.");
  }
  output->SetPoints(points);
  output->SetLines(lines);
  return 1;
}

void vtkSightlineTCKReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
}
