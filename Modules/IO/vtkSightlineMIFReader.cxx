// SPDX-License-Identifier: BSD-3-Clause
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

#include "SightlineMRtrixHeader.h"
#include "SightlineReaderInput.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSightlineMIFReader);

namespace
{
using namespace sightline_io;

constexpr const char* MIFMagic = "mrtrix image";
constexpr int MaxAxes = 4;
// Deflate never compresses more than about 1032:1, so a gzip stream of n bytes inflates to at
// most 1032 n (plus a little for tiny streams): a bound on what a .mif.gz can hold, known
// before anything is inflated.
constexpr long long MaxDeflateRatio = 1032;
// Compressed data are inflated into the buffer this many bytes at a time, so that a file that
// promises more than it holds is found out before much memory is taken.
constexpr std::size_t InflateStep = 16u << 20;

/// The file's bytes as a stream: as they are, or inflated on the fly when they are gzip
/// (one member or several, as gzip and MRtrix write them).
class Source
{
public:
  explicit Source(const std::string& bytes)
    : Bytes(bytes)
    , Compressed(bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
        static_cast<unsigned char>(bytes[1]) == 0x8b)
  {
    if (this->Compressed)
    {
      std::memset(&this->Stream, 0, sizeof(this->Stream));
      this->Initialized = inflateInit2(&this->Stream, 15 + 16) == Z_OK;
      this->Ready = this->Initialized;
      this->Stream.next_in =
        reinterpret_cast<Bytef*>(const_cast<char*>(this->Bytes.data()));
      this->Stream.avail_in = static_cast<uInt>(
        std::min<std::size_t>(this->Bytes.size(), std::numeric_limits<uInt>::max()));
      this->Window.resize(1u << 16);
    }
  }
  ~Source()
  {
    if (this->Initialized)
    {
      inflateEnd(&this->Stream);
    }
  }
  Source(const Source&) = delete;
  Source& operator=(const Source&) = delete;

  bool IsCompressed() const { return this->Compressed; }
  /// Bytes consumed so far (inflated bytes for gzip).
  std::size_t Position() const { return this->At; }
  /// What the stored bytes could hold at most.
  long long MaxSize() const
  {
    const long long stored = static_cast<long long>(this->Bytes.size());
    return this->Compressed ? stored * MaxDeflateRatio + 1024 : stored;
  }
  /// A message from zlib when the stream is damaged, else "".
  const std::string& Error() const { return this->ZError; }

  /// The next byte, or -1 at the end.
  int Next()
  {
    if (!this->Compressed)
    {
      return this->At < this->Bytes.size() ? static_cast<unsigned char>(this->Bytes[this->At++])
                                           : -1;
    }
    if (this->WindowAt == this->WindowEnd && !this->Fill())
    {
      return -1;
    }
    ++this->At;
    return this->Window[this->WindowAt++];
  }

  /// Up to `size` bytes into `data`; fewer only at the end of the input.
  std::size_t Read(unsigned char* data, std::size_t size)
  {
    std::size_t done = 0;
    while (done < size)
    {
      if (!this->Compressed)
      {
        const std::size_t n = std::min(size - done, this->Bytes.size() - this->At);
        std::memcpy(data + done, this->Bytes.data() + this->At, n);
        this->At += n;
        return done + n;
      }
      if (this->WindowAt == this->WindowEnd && !this->Fill())
      {
        break;
      }
      const std::size_t n = std::min(size - done, this->WindowEnd - this->WindowAt);
      std::memcpy(data + done, this->Window.data() + this->WindowAt, n);
      this->WindowAt += n;
      this->At += n;
      done += n;
    }
    return done;
  }

  /// Skips forward to `offset` (at or after the current position); false past the end.
  bool SkipTo(std::size_t offset)
  {
    unsigned char scratch[4096];
    while (this->At < offset)
    {
      if (this->Read(scratch, std::min(sizeof(scratch), offset - this->At)) == 0)
      {
        return false;
      }
    }
    return true;
  }

  /// Uncompressed data may be used in place: the stored bytes from `offset`.
  const unsigned char* StoredBytes(std::size_t offset) const
  {
    return reinterpret_cast<const unsigned char*>(this->Bytes.data()) + offset;
  }

private:
  bool Fill()
  {
    this->WindowAt = this->WindowEnd = 0;
    while (this->Ready && this->WindowEnd == 0)
    {
      if (this->Stream.avail_in == 0)
      {
        return false;
      }
      this->Stream.next_out = this->Window.data();
      this->Stream.avail_out = static_cast<uInt>(this->Window.size());
      const int status = inflate(&this->Stream, Z_NO_FLUSH);
      this->WindowEnd = this->Window.size() - this->Stream.avail_out;
      if (status == Z_STREAM_END)
      {
        // Another gzip member may follow; anything else after the stream is not data.
        const bool member = this->Stream.avail_in >= 2 && this->Stream.next_in[0] == 0x1f &&
          this->Stream.next_in[1] == 0x8b;
        if (!member || inflateReset(&this->Stream) != Z_OK)
        {
          this->Ready = false;
        }
      }
      else if (status != Z_OK)
      {
        this->ZError = this->Stream.msg ? this->Stream.msg : "damaged gzip stream";
        this->Ready = false;
      }
    }
    return this->WindowEnd > 0;
  }

  const std::string& Bytes;
  const bool Compressed;
  bool Initialized = false; // inflateEnd is owed
  bool Ready = false;       // more can be inflated
  z_stream Stream;
  std::vector<unsigned char> Window;
  std::size_t WindowAt = 0;
  std::size_t WindowEnd = 0;
  std::size_t At = 0;
  std::string ZError;
};

/// The value of type T stored in `buffer` (host byte order; memcpy avoids alignment issues).
template <class T>
double Load(const unsigned char* buffer)
{
  T value;
  std::memcpy(&value, buffer, sizeof(T));
  return static_cast<double>(value);
}

double Convert(const unsigned char* bytes, const MRtrixDataType& type)
{
  unsigned char buffer[8];
  std::memcpy(buffer, bytes, static_cast<std::size_t>(type.Bytes));
  ToHostByteOrder(buffer, 1, type);
  switch (type.Type)
  {
    case MRtrixType::Int8:
      return Load<std::int8_t>(buffer);
    case MRtrixType::UInt8:
      return Load<std::uint8_t>(buffer);
    case MRtrixType::Int16:
      return Load<std::int16_t>(buffer);
    case MRtrixType::UInt16:
      return Load<std::uint16_t>(buffer);
    case MRtrixType::Int32:
      return Load<std::int32_t>(buffer);
    case MRtrixType::UInt32:
      return Load<std::uint32_t>(buffer);
    case MRtrixType::Float32:
      return Load<float>(buffer);
    case MRtrixType::Float64:
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

// Everything the data read needs from the header, normalised to 4 axes (missing ones size 1).
struct Header
{
  std::array<vtkIdType, MaxAxes> Dim{ { 1, 1, 1, 1 } };
  std::array<double, 3> Spacing{ { 1.0, 1.0, 1.0 } };
  // Disk position of each axis: element stride (0 = fastest) and direction.
  std::array<vtkIdType, MaxAxes> Stride{ { 0, 0, 0, 0 } };
  std::array<bool, MaxAxes> Reversed{ { false, false, false, false } };
  double Transform[3][4] = { { 1, 0, 0, 0 }, { 0, 1, 0, 0 }, { 0, 0, 1, 0 } };
  MRtrixDataType Type;
  double ScaleOffset = 0.0;
  double ScaleMultiplier = 1.0;
  std::string DataType;
  long long DataOffset = 0;
  // Voxel values (product of all dims) and their bytes, both checked against overflow.
  long long Count = 0;
  long long Bytes = 0;
};

// Parses and checks the header of the stream; false with `error` (without the input's name).
bool ParseHeader(Source& source, Header& header, std::string& error)
{
  MRtrixHeader text;
  if (!ReadMRtrixHeader([&source] { return source.Next(); }, MIFMagic, "MRtrix image", text, error))
  {
    if (source.IsCompressed() && !source.Error().empty())
    {
      error += " (gzip: " + source.Error() + ")";
    }
    return false;
  }
  const std::vector<std::string> dim = SplitList(text.Value("dim"));
  const std::vector<std::string> vox = SplitList(text.Value("vox"));
  const std::vector<std::string> layout = SplitList(text.Value("layout"));
  const std::string datatype = text.Value("datatype");
  const std::vector<std::string> fileEntries = text.Values("file");
  std::vector<std::string> transform;
  for (const auto& row : text.Values("transform"))
  {
    for (const auto& item : SplitList(row))
    {
      transform.push_back(item);
    }
  }

  // dim: at least 2 axes; beyond the 4th only size 1 is accepted (nothing to map it to).
  if (dim.size() < 2)
  {
    error = "missing or malformed 'dim' entry.";
    return false;
  }
  const int axes = static_cast<int>(dim.size());
  std::vector<long long> sizes(axes);
  for (int a = 0; a < axes; ++a)
  {
    if (!ParseInteger(dim[a], sizes[a]) || sizes[a] < 1 ||
      sizes[a] > std::numeric_limits<int>::max())
    {
      error = "invalid size '" + Quote(dim[a]) + "' of axis " + std::to_string(a) +
        " in 'dim' (1 to 2147483647).";
      return false;
    }
    if (a >= MaxAxes && sizes[a] != 1)
    {
      error = "the image has " + std::to_string(axes) + " axes (dim " + dim[a] + " along axis " +
        std::to_string(a) + "); only images of up to 4 axes are supported.";
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
    error = "'vox' has " + std::to_string(vox.size()) + " entries for " +
      std::to_string(dim.size()) + " axes.";
    return false;
  }
  for (int a = 0; a < std::min(axes, 3); ++a)
  {
    double spacing = 0.0;
    if (!ParseDouble(vox[a], spacing) || !std::isfinite(spacing) || spacing == 0.0)
    {
      error = "invalid voxel size '" + Quote(vox[a]) + "' of axis " + std::to_string(a) + ".";
      return false;
    }
    header.Spacing[a] = std::fabs(spacing);
  }

  // layout: one signed rank per axis ("+0" fastest); the ranks are a permutation of 0..n-1.
  if (layout.size() != dim.size())
  {
    error = "'layout' has " + std::to_string(layout.size()) + " entries for " +
      std::to_string(dim.size()) + " axes.";
    return false;
  }
  std::vector<int> axisOfRank(axes, -1);
  for (int a = 0; a < axes; ++a)
  {
    long long value = 0;
    const std::string& item = layout[a];
    if (item.size() < 2 || (item[0] != '+' && item[0] != '-') ||
      !std::isdigit(static_cast<unsigned char>(item[1])) ||
      !ParseInteger(item.substr(1), value) || value < 0 || value >= axes ||
      axisOfRank[value] != -1)
    {
      error = "invalid 'layout' entry '" + Quote(item) + "'.";
      return false;
    }
    axisOfRank[value] = a;
    if (a < MaxAxes)
    {
      header.Reversed[a] = item[0] == '-';
    }
  }
  // Strides and the voxel count, checked: a product that wraps (65536 in four axes is 2^64)
  // would leave a buffer too small for the indices computed from the sizes.
  long long stride = 1;
  for (int r = 0; r < axes; ++r)
  {
    const int a = axisOfRank[r];
    if (a < MaxAxes)
    {
      header.Stride[a] = static_cast<vtkIdType>(stride);
    }
    if (__builtin_mul_overflow(stride, sizes[a], &stride))
    {
      error = "the image size " + text.Value("dim") + " overflows 64-bit integers.";
      return false;
    }
  }
  header.Count = stride;

  if (!ParseDataType(datatype, header.Type))
  {
    error = "unsupported datatype '" + Quote(datatype) +
      "' (supported: [U]Int8, [U]Int16, [U]Int32, Float32, Float64, with LE/BE suffix).";
    return false;
  }
  header.DataType = datatype;
  if (__builtin_mul_overflow(header.Count, static_cast<long long>(header.Type.Bytes),
        &header.Bytes))
  {
    error = "the image size " + text.Value("dim") + " in " + datatype +
      " overflows 64-bit byte counts.";
    return false;
  }

  const std::vector<std::string> scaling = SplitList(text.Value("scaling"));
  if (!scaling.empty() &&
    (scaling.size() != 2 || !ParseDouble(scaling[0], header.ScaleOffset) ||
      !ParseDouble(scaling[1], header.ScaleMultiplier)))
  {
    error = "malformed 'scaling' entry '" + Quote(text.Value("scaling")) + "'.";
    return false;
  }

  if (!transform.empty())
  {
    if (transform.size() != 12)
    {
      error = "'transform' has " + std::to_string(transform.size()) +
        " numbers; 3 rows of 4 are needed.";
      return false;
    }
    for (int i = 0; i < 12; ++i)
    {
      if (!ParseDouble(transform[i], header.Transform[i / 4][i % 4]) ||
        !std::isfinite(header.Transform[i / 4][i % 4]))
      {
        error = "invalid 'transform' value '" + Quote(transform[i]) + "'.";
        return false;
      }
    }
  }

  // file: ". OFFSET" is the only form this reader handles (data in this file, after the header).
  if (fileEntries.size() != 1)
  {
    error = std::to_string(fileEntries.size()) +
      " 'file' entries; exactly one (\". OFFSET\") is supported.";
    return false;
  }
  if (!ParseDataFileEntry(fileEntries[0], header.DataOffset))
  {
    error = "unsupported 'file' entry '" + Quote(fileEntries[0]) +
      "': only data in the same file (\". OFFSET\") is supported.";
    return false;
  }
  if (header.DataOffset < static_cast<long long>(text.Size))
  {
    error = "the data offset " + std::to_string(header.DataOffset) +
      " lies inside the header, which ends at byte " + std::to_string(text.Size) + ".";
    return false;
  }
  // Checked against what the file can hold before any buffer is allocated.
  const long long available = source.MaxSize() - header.DataOffset;
  if (header.Bytes > available)
  {
    error = "the file is truncated: the header promises " + std::to_string(header.Bytes) + " bytes of " +
      Quote(datatype) + " data at offset " + std::to_string(header.DataOffset) + ", but " +
      (source.IsCompressed() ? "a gzip stream of this length cannot hold them"
                             : "the file has only " +
            std::to_string(std::max(0LL, available)) + " bytes there") +
      " (truncated file?).";
    return false;
  }
  return true;
}

// The input's bytes, the stream over them, positioned after the header, and the header.
struct Input
{
  std::string Bytes;
  std::unique_ptr<Source> Stream;
  Header Parsed;
};

// Loads the file (or the input string) and parses its header; false with the whole message.
bool OpenInput(const char* fileName, bool fromString, const std::string& inputString,
  Input& input, std::string& error)
{
  if (!LoadInput(fileName, fromString, inputString, input.Bytes, error))
  {
    return false;
  }
  input.Stream.reset(new Source(input.Bytes));
  if (!ParseHeader(*input.Stream, input.Parsed, error))
  {
    error = InputName(fileName, fromString) + ": " + error;
    return false;
  }
  return true;
}
} // namespace

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
void vtkSightlineMIFReader::SetInputString(const std::string& bytes)
{
  if (bytes != this->InputString)
  {
    this->InputString = bytes;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkMatrix4x4* vtkSightlineMIFReader::GetTransformMatrix()
{
  return this->TransformMatrix;
}

//------------------------------------------------------------------------------
int vtkSightlineMIFReader::CanReadFile(const char* fileName)
{
  std::string bytes, error;
  if (!fileName || !LoadInput(fileName, false, std::string(), bytes, error))
  {
    return 0;
  }
  Source source(bytes);
  std::string line;
  for (int c = source.Next(); c >= 0 && c != '\n' && line.size() < 64; c = source.Next())
  {
    line.push_back(static_cast<char>(c));
  }
  return Trim(line) == MIFMagic ? 1 : 0;
}

//------------------------------------------------------------------------------
int vtkSightlineMIFReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  this->TransformMatrix->Identity();
  this->SlicesReversed = false;
  this->DataTypeName.clear();
  Input input;
  std::string error;
  if (!OpenInput(this->FileName, this->ReadFromInputString, this->InputString, input, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const Header& header = input.Parsed;
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
  const std::string name = InputName(this->FileName, this->ReadFromInputString);
  Input input;
  std::string error;
  if (!OpenInput(this->FileName, this->ReadFromInputString, this->InputString, input, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const Header& header = input.Parsed;
  Source& source = *input.Stream;
  const vtkIdType nx = header.Dim[0], ny = header.Dim[1], nz = header.Dim[2],
                  nc = header.Dim[3];
  const std::size_t size = static_cast<std::size_t>(header.Bytes);
  const std::size_t offset = static_cast<std::size_t>(header.DataOffset);

  // Uncompressed data are used where they lie (ParseHeader checked that they are all there);
  // compressed ones are inflated step by step, so that the buffer never runs far ahead of the
  // data actually present.
  const unsigned char* raw = nullptr;
  std::vector<unsigned char> inflated;
  if (!source.IsCompressed())
  {
    raw = source.StoredBytes(offset);
  }
  else
  {
    std::size_t done = 0;
    if (source.SkipTo(offset))
    {
      while (done < size)
      {
        const std::size_t step = std::min(size - done, InflateStep);
        inflated.resize(done + step);
        const std::size_t got = source.Read(inflated.data() + done, step);
        done += got;
        if (got < step)
        {
          break;
        }
      }
    }
    if (done < size)
    {
      vtkErrorMacro(<< name << " is truncated: the header promises " << size << " bytes of "
                    << Quote(header.DataType) << " data at offset " << offset << ", but only "
                    << done << " could be inflated"
                    << (source.Error().empty() ? "" : " (gzip: " + source.Error() + ")")
                    << ".");
      return 0;
    }
    raw = inflated.data();
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
          const double stored =
            Convert(raw + static_cast<std::size_t>(element) * header.Type.Bytes, header.Type);
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
