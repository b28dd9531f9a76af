#include "vtkSightlineMIFReader.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include "vtk_zlib.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkSightlineMIFReader);

namespace
{
// The header lines end with this one; the data start at the offset of the `file` entry.
constexpr const char* MIFMagic = "mrtrix image";
// A header is a few hundred bytes; this cap stops a binary file without newlines from being
// read whole as "one line".
constexpr std::size_t MaxHeaderBytes = 16u << 20;
constexpr int MaxAxes = 4;

// One gzFile reads both kinds of file: zlib passes data that is not gzip through unchanged
// ("transparent" mode), so .mif and .mif.gz share every code path.
struct GzCloser
{
  void operator()(gzFile_s* file) const
  {
    if (file)
    {
      gzclose(file);
    }
  }
};
using GzHandle = std::unique_ptr<gzFile_s, GzCloser>;

GzHandle OpenGz(const char* fileName)
{
  GzHandle file(gzopen(fileName, "rb"));
  if (file)
  {
    gzbuffer(file.get(), 1u << 18);
  }
  return file;
}

// Reads one '\n'-terminated line (without it, nor a trailing '\r'); false at end of file or
// when the line exceeds the cap.
bool ReadLine(gzFile file, std::string& line, std::size_t& budget)
{
  line.clear();
  for (;;)
  {
    const int c = gzgetc(file);
    if (c == -1)
    {
      return !line.empty();
    }
    if (c == '\n')
    {
      break;
    }
    if (budget-- == 0)
    {
      return false;
    }
    line.push_back(static_cast<char>(c));
  }
  if (!line.empty() && line.back() == '\r')
  {
    line.pop_back();
  }
  return true;
}

std::string Trim(const std::string& text)
{
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos)
  {
    return std::string();
  }
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

std::vector<std::string> SplitList(const std::string& text)
{
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ','))
  {
    items.push_back(Trim(item));
  }
  return items;
}

bool ParseDouble(const std::string& text, double& value)
{
  if (text.empty())
  {
    return false;
  }
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return end && *end == '\0';
}

bool ParseInteger(const std::string& text, long long& value)
{
  if (text.empty())
  {
    return false;
  }
  char* end = nullptr;
  value = std::strtoll(text.c_str(), &end, 10);
  return end && *end == '\0';
}

bool HostIsLittleEndian()
{
  const std::uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

// The stored element types this reader converts to float.
enum class Stored
{
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

// Parses MRtrix's datatype names ("Float32LE", "UInt8", "Int16BE", ...).
bool ParseDataType(const std::string& name, Stored& type, int& bytes, bool& swap)
{
  static const std::array<std::pair<const char*, std::pair<Stored, int>>, 8> types = { {
    { "int8", { Stored::Int8, 1 } },
    { "uint8", { Stored::UInt8, 1 } },
    { "int16", { Stored::Int16, 2 } },
    { "uint16", { Stored::UInt16, 2 } },
    { "int32", { Stored::Int32, 4 } },
    { "uint32", { Stored::UInt32, 4 } },
    { "float32", { Stored::Float32, 4 } },
    { "float64", { Stored::Float64, 8 } },
  } };
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // No suffix means the writing machine's order, which MRtrix assumes is this one.
  bool little = HostIsLittleEndian();
  std::string base = lower;
  if (lower.size() > 2 && (lower.compare(lower.size() - 2, 2, "le") == 0 ||
                            lower.compare(lower.size() - 2, 2, "be") == 0))
  {
    little = lower.compare(lower.size() - 2, 2, "le") == 0;
    base = lower.substr(0, lower.size() - 2);
  }
  for (const auto& entry : types)
  {
    if (base == entry.first)
    {
      type = entry.second.first;
      bytes = entry.second.second;
      // Byte order only matters for multi-byte types (and "UInt8LE" is not a thing).
      swap = bytes > 1 && little != HostIsLittleEndian();
      return bytes > 1 || base == lower;
    }
  }
  return false;
}

/// The value of type T stored in `buffer` (native byte order; memcpy avoids aliasing issues).
template <class T>
double Load(const unsigned char* buffer)
{
  T value;
  std::memcpy(&value, buffer, sizeof(T));
  return static_cast<double>(value);
}

double Convert(const unsigned char* bytes, Stored type, int size, bool swap)
{
  unsigned char buffer[8];
  for (int b = 0; b < size; ++b)
  {
    buffer[b] = swap ? bytes[size - 1 - b] : bytes[b];
  }
  switch (type)
  {
    case Stored::Int8:
      return Load<std::int8_t>(buffer);
    case Stored::UInt8:
      return Load<std::uint8_t>(buffer);
    case Stored::Int16:
      return Load<std::int16_t>(buffer);
    case Stored::UInt16:
      return Load<std::uint16_t>(buffer);
    case Stored::Int32:
      return Load<std::int32_t>(buffer);
    case Stored::UInt32:
      return Load<std::uint32_t>(buffer);
    case Stored::Float32:
      return Load<float>(buffer);
    case Stored::Float64:
      return Load<double>(buffer);
  }
  return 0.0;
}

double Determinant3(const double m[3][3])
{
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
    m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
    m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}
} // namespace

// Everything the data read needs from the header, normalised to 4 axes (missing ones size 1).
struct vtkSightlineMIFReader::Header
{
  std::array<vtkIdType, MaxAxes> Dim{ { 1, 1, 1, 1 } };
  std::array<double, 3> Spacing{ { 1.0, 1.0, 1.0 } };
  // Disk position of each axis: element stride (0 = fastest) and direction.
  std::array<vtkIdType, MaxAxes> Stride{ { 0, 0, 0, 0 } };
  std::array<bool, MaxAxes> Reversed{ { false, false, false, false } };
  double Transform[3][4] = { { 1, 0, 0, 0 }, { 0, 1, 0, 0 }, { 0, 0, 1, 0 } };
  Stored Type = Stored::Float32;
  int Bytes = 4;
  bool Swap = false;
  double ScaleOffset = 0.0;
  double ScaleMultiplier = 1.0;
  std::string DataType;
  long long DataOffset = 0;
};

//------------------------------------------------------------------------------
vtkSightlineMIFReader::vtkSightlineMIFReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkSightlineMIFReader::~vtkSightlineMIFReader()
{
  this->SetFileName(nullptr);
}

//------------------------------------------------------------------------------
vtkMatrix4x4* vtkSightlineMIFReader::GetTransformMatrix()
{
  return this->TransformMatrix;
}

//------------------------------------------------------------------------------
int vtkSightlineMIFReader::CanReadFile(const char* fileName)
{
  if (!fileName)
  {
    return 0;
  }
  GzHandle file = OpenGz(fileName);
  std::string line;
  std::size_t budget = 64;
  return file && ReadLine(file.get(), line, budget) && line == MIFMagic ? 1 : 0;
}

//------------------------------------------------------------------------------
bool vtkSightlineMIFReader::ReadHeader(Header& header)
{
  const std::string name = this->FileName ? this->FileName : "";
  if (name.empty())
  {
    vtkErrorMacro(<< "No FileName was set.");
    return false;
  }
  GzHandle file = OpenGz(name.c_str());
  if (!file)
  {
    vtkErrorMacro(<< "Cannot open the MRtrix image '" << name << "' (missing or unreadable).");
    return false;
  }
  std::size_t budget = MaxHeaderBytes;
  std::string line;
  if (!ReadLine(file.get(), line, budget) || line != MIFMagic)
  {
    vtkErrorMacro(<< "'" << name << "' is not an MRtrix image: its first line is not \""
                  << MIFMagic << "\".");
    return false;
  }

  std::vector<std::string> dim, vox, layout, transform, fileEntries, scaling;
  std::string datatype;
  bool ended = false;
  while (ReadLine(file.get(), line, budget))
  {
    if (line == "END")
    {
      ended = true;
      break;
    }
    const std::string content = Trim(line.substr(0, line.find('#')));
    if (content.empty())
    {
      continue;
    }
    const auto colon = content.find(':');
    if (colon == std::string::npos)
    {
      vtkErrorMacro(<< "'" << name << "': malformed header line \"" << line << "\".");
      return false;
    }
    std::string key = Trim(content.substr(0, colon));
    std::transform(key.begin(), key.end(), key.begin(),
      [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const std::string value = Trim(content.substr(colon + 1));
    if (key == "dim")
    {
      dim = SplitList(value);
    }
    else if (key == "vox")
    {
      vox = SplitList(value);
    }
    else if (key == "layout")
    {
      layout = SplitList(value);
    }
    else if (key == "datatype")
    {
      datatype = value;
    }
    else if (key == "transform")
    {
      // Three lines, one row each, in order.
      for (const auto& item : SplitList(value))
      {
        transform.push_back(item);
      }
    }
    else if (key == "file")
    {
      fileEntries.push_back(value);
    }
    else if (key == "scaling")
    {
      scaling = SplitList(value);
    }
    // Other keys (comments, command_history, dw_scheme, ...) carry nothing the image needs.
  }
  if (!ended)
  {
    vtkErrorMacro(<< "'" << name << "': the header has no END line (truncated file?).");
    return false;
  }

  // dim: at least 2 axes; beyond the 4th only size 1 is accepted (nothing to map it to).
  if (dim.size() < 2)
  {
    vtkErrorMacro(<< "'" << name << "': missing or malformed 'dim' entry.");
    return false;
  }
  const int axes = static_cast<int>(dim.size());
  std::vector<long long> sizes(axes);
  for (int a = 0; a < axes; ++a)
  {
    if (!ParseInteger(dim[a], sizes[a]) || sizes[a] < 1 ||
      sizes[a] > std::numeric_limits<int>::max())
    {
      vtkErrorMacro(<< "'" << name << "': invalid size '" << dim[a] << "' of axis " << a
                    << " in 'dim'.");
      return false;
    }
    if (a >= MaxAxes && sizes[a] != 1)
    {
      vtkErrorMacro(<< "'" << name << "' has " << axes << " axes (dim " << dim[a]
                    << " along axis " << a << "); only images of up to 4 axes are supported.");
      return false;
    }
    if (a < MaxAxes)
    {
      header.Dim[a] = static_cast<vtkIdType>(sizes[a]);
    }
  }

  // vox: the spacing of the three spatial axes (the 4th may be anything, even NaN).
  if (vox.size() != dim.size())
  {
    vtkErrorMacro(<< "'" << name << "': 'vox' has " << vox.size() << " entries for "
                  << dim.size() << " axes.");
    return false;
  }
  for (int a = 0; a < std::min(axes, 3); ++a)
  {
    double spacing = 0.0;
    if (!ParseDouble(vox[a], spacing) || !std::isfinite(spacing) || spacing == 0.0)
    {
      vtkErrorMacro(<< "'" << name << "': invalid voxel size '" << vox[a] << "' of axis " << a
                    << ".");
      return false;
    }
    header.Spacing[a] = std::fabs(spacing);
  }

  // layout: one signed rank per axis ("+0" fastest); the ranks are a permutation of 0..n-1.
  if (layout.size() != dim.size())
  {
    vtkErrorMacro(<< "'" << name << "': 'layout' has " << layout.size() << " entries for "
                  << dim.size() << " axes.");
    return false;
  }
  std::vector<int> rank(axes);
  std::vector<int> axisOfRank(axes, -1);
  for (int a = 0; a < axes; ++a)
  {
    long long value = 0;
    const std::string& item = layout[a];
    if (item.size() < 2 || (item[0] != '+' && item[0] != '-') ||
      !ParseInteger(item.substr(1), value) || value < 0 || value >= axes ||
      axisOfRank[value] != -1 || !std::isdigit(static_cast<unsigned char>(item[1])))
    {
      vtkErrorMacro(<< "'" << name << "': invalid 'layout' entry '" << item << "'.");
      return false;
    }
    rank[a] = static_cast<int>(value);
    axisOfRank[value] = a;
    if (a < MaxAxes)
    {
      header.Reversed[a] = item[0] == '-';
    }
  }
  vtkIdType stride = 1;
  for (int r = 0; r < axes; ++r)
  {
    const int a = axisOfRank[r];
    if (a < MaxAxes)
    {
      header.Stride[a] = stride;
    }
    stride *= static_cast<vtkIdType>(sizes[a]);
  }

  if (!ParseDataType(datatype, header.Type, header.Bytes, header.Swap))
  {
    vtkErrorMacro(<< "'" << name << "': unsupported datatype '" << datatype
                  << "' (supported: [U]Int8, [U]Int16, [U]Int32, Float32, Float64, "
                     "with LE/BE suffix).");
    return false;
  }
  header.DataType = datatype;

  if (!scaling.empty())
  {
    if (scaling.size() != 2 || !ParseDouble(scaling[0], header.ScaleOffset) ||
      !ParseDouble(scaling[1], header.ScaleMultiplier))
    {
      vtkErrorMacro(<< "'" << name << "': malformed 'scaling' entry.");
      return false;
    }
  }

  if (!transform.empty())
  {
    if (transform.size() != 12)
    {
      vtkErrorMacro(<< "'" << name << "': 'transform' has " << transform.size()
                    << " numbers; 3 rows of 4 are needed.");
      return false;
    }
    for (int i = 0; i < 12; ++i)
    {
      if (!ParseDouble(transform[i], header.Transform[i / 4][i % 4]) ||
        !std::isfinite(header.Transform[i / 4][i % 4]))
      {
        vtkErrorMacro(<< "'" << name << "': invalid 'transform' value '" << transform[i]
                      << "'.");
        return false;
      }
    }
  }

  // file: ". OFFSET" is the only form this reader handles (data in this file, after the header).
  if (fileEntries.size() != 1)
  {
    vtkErrorMacro(<< "'" << name << "' has " << fileEntries.size()
                  << " 'file' entries; exactly one (\". OFFSET\") is supported.");
    return false;
  }
  std::istringstream entry(fileEntries[0]);
  std::string dataFile, extra;
  if (!(entry >> dataFile >> header.DataOffset) || dataFile != "." || header.DataOffset < 0 ||
    (entry >> extra))
  {
    vtkErrorMacro(<< "'" << name << "': unsupported 'file' entry '" << fileEntries[0]
                  << "': only data in the same file (\". OFFSET\") is supported.");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkSightlineMIFReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  Header header;
  this->TransformMatrix->Identity();
  this->SlicesReversed = false;
  this->DataTypeName.clear();
  if (!this->ReadHeader(header))
  {
    return 0;
  }
  this->DataTypeName = header.DataType;

  // Left-handed grid: reverse z so that the matrix stays a rotation (vtkNIFTIImageReader's
  // convention for qfac = -1), with the translation moved to the slice that is now first.
  double m[3][3];
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
    {
      m[r][c] = header.Transform[r][c];
    }
  }
  const double determinant = Determinant3(m);
  this->SlicesReversed = determinant < 0.0;
  for (int r = 0; r < 3; ++r)
  {
    double translation = header.Transform[r][3];
    if (this->SlicesReversed)
    {
      translation += header.Transform[r][2] * header.Spacing[2] * (header.Dim[2] - 1);
    }
    for (int c = 0; c < 3; ++c)
    {
      const double flip = (this->SlicesReversed && c == 2) ? -1.0 : 1.0;
      this->TransformMatrix->SetElement(r, c, flip * header.Transform[r][c]);
    }
    this->TransformMatrix->SetElement(r, 3, translation);
  }

  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int extent[6] = { 0, static_cast<int>(header.Dim[0] - 1), 0,
    static_cast<int>(header.Dim[1] - 1), 0, static_cast<int>(header.Dim[2] - 1) };
  const double origin[3] = { 0.0, 0.0, 0.0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkDataObject::SPACING(), header.Spacing.data(), 3);
  outInfo->Set(vtkDataObject::ORIGIN(), origin, 3);
  vtkDataObject::SetPointDataActiveScalarInfo(
    outInfo, VTK_FLOAT, static_cast<int>(header.Dim[3]));
  return 1;
}

//------------------------------------------------------------------------------
int vtkSightlineMIFReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkImageData* output = vtkImageData::GetData(outInfo);
  if (!output)
  {
    return 0;
  }
  output->Initialize();

  // The header is read again: the file may have changed since RequestInformation, and the
  // two must agree for the data to be read correctly.
  Header header;
  if (!this->ReadHeader(header))
  {
    return 0;
  }
  const vtkIdType nx = header.Dim[0], ny = header.Dim[1], nz = header.Dim[2],
                  nc = header.Dim[3];
  const vtkIdType count = nx * ny * nz * nc;
  const std::size_t bytes = static_cast<std::size_t>(count) * header.Bytes;

  GzHandle file = OpenGz(this->FileName);
  if (!file || gzseek(file.get(), static_cast<z_off_t>(header.DataOffset), SEEK_SET) < 0)
  {
    vtkErrorMacro(<< "'" << this->FileName << "': cannot seek to the data at offset "
                  << header.DataOffset << " (truncated file?).");
    return 0;
  }
  std::vector<unsigned char> raw(bytes);
  std::size_t done = 0;
  while (done < bytes)
  {
    // gzread takes an unsigned int length: read large images in chunks.
    const unsigned chunk =
      static_cast<unsigned>(std::min<std::size_t>(bytes - done, 1u << 30));
    const int got = gzread(file.get(), raw.data() + done, chunk);
    if (got <= 0)
    {
      break;
    }
    done += static_cast<std::size_t>(got);
  }
  if (done < bytes)
  {
    int zerror = Z_OK;
    const char* message = gzerror(file.get(), &zerror);
    vtkErrorMacro(<< "'" << this->FileName << "' is truncated: the header promises " << bytes
                  << " bytes of " << header.DataType << " data at offset " << header.DataOffset
                  << ", but only " << done << " could be read"
                  << (zerror != Z_OK && message ? std::string(" (") + message + ")" : "")
                  << ".");
    return 0;
  }

  int extent[6] = { 0, static_cast<int>(nx - 1), 0, static_cast<int>(ny - 1), 0,
    static_cast<int>(nz - 1) };
  output->SetExtent(extent);
  output->SetSpacing(header.Spacing.data());
  output->SetOrigin(0.0, 0.0, 0.0);
  vtkNew<vtkFloatArray> values;
  values->SetName("SHCoefficients");
  values->SetNumberOfComponents(static_cast<int>(nc));
  values->SetNumberOfTuples(nx * ny * nz);
  float* out = values->GetPointer(0);

  // Disk position of MRtrix voxel index n along axis a: n, or (size-1-n) for a reversed axis.
  auto position = [&](int a, vtkIdType n) {
    return (header.Reversed[a] ? header.Dim[a] - 1 - n : n) * header.Stride[a];
  };
  for (vtkIdType k = 0; k < nz; ++k)
  {
    // VTK slice k is MRtrix slice nz-1-k when the slices are reversed (see the class comment).
    const vtkIdType sourceK = this->SlicesReversed ? nz - 1 - k : k;
    const vtkIdType baseK = position(2, sourceK);
    for (vtkIdType j = 0; j < ny; ++j)
    {
      const vtkIdType baseJ = baseK + position(1, j);
      for (vtkIdType i = 0; i < nx; ++i)
      {
        const vtkIdType baseI = baseJ + position(0, i);
        float* tuple = out + ((k * ny + j) * nx + i) * nc;
        for (vtkIdType c = 0; c < nc; ++c)
        {
          const vtkIdType element = baseI + position(3, c);
          const double stored = Convert(raw.data() + static_cast<std::size_t>(element) *
              header.Bytes,
            header.Type, header.Bytes, header.Swap);
          tuple[c] =
            static_cast<float>(header.ScaleOffset + header.ScaleMultiplier * stored);
        }
      }
    }
  }
  output->GetPointData()->SetScalars(values);
  return 1;
}

//------------------------------------------------------------------------------
void vtkSightlineMIFReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "DataTypeName: " << (this->DataTypeName.empty() ? "(none)" : this->DataTypeName)
     << "\n";
  os << indent << "SlicesReversed: " << (this->SlicesReversed ? "true" : "false") << "\n";
  os << indent << "TransformMatrix:\n";
  this->TransformMatrix->PrintSelf(os, indent.GetNextIndent());
}
