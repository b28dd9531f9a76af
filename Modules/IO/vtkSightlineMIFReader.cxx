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
#include <tuple>
#include <utility>
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
// The data are read (inflated, for gzip) this many bytes at a time into one reused buffer and
// scattered into the output, so that memory holds the requested extent plus this step, and a
// file that promises more than it holds is found out before much memory is taken.
constexpr std::size_t ReadStep = 1u << 20;

/// The file's bytes as a stream: as they are, or inflated on the fly when they are gzip
/// (one member or several, as gzip and MRtrix write them). The file is read a block at a
/// time, never held whole; uncompressed data can be skipped by seeking.
class Source
{
public:
  explicit Source(InputFile& file)
    : File(file)
    , Compressed(file.ByteAt(0) == 0x1f && file.ByteAt(1) == 0x8b)
  {
    if (this->Compressed)
    {
      std::memset(&this->Stream, 0, sizeof(this->Stream));
      this->Initialized = inflateInit2(&this->Stream, 15 + 16) == Z_OK;
      this->Ready = this->Initialized;
      this->In.resize(1u << 16);
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
    const long long stored = this->File.Size();
    return this->Compressed ? stored * MaxDeflateRatio + 1024 : stored;
  }
  /// A message from zlib when the stream is damaged, else "".
  const std::string& Error() const { return this->ZError; }

  /// The next byte, or -1 at the end.
  int Next()
  {
    if (!this->Compressed)
    {
      const int c = this->File.ByteAt(static_cast<long long>(this->At));
      this->At += c >= 0 ? 1 : 0;
      return c;
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
    if (!this->Compressed)
    {
      const std::size_t n = this->File.ReadAt(
        static_cast<long long>(this->At), reinterpret_cast<char*>(data), size);
      this->At += n;
      return n;
    }
    std::size_t done = 0;
    while (done < size)
    {
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
  /// Uncompressed data are skipped by seeking; compressed ones are inflated and dropped.
  bool SkipTo(std::size_t offset)
  {
    if (!this->Compressed)
    {
      if (static_cast<long long>(offset) > this->File.Size())
      {
        return false;
      }
      this->At = std::max(this->At, offset);
      return true;
    }
    std::vector<unsigned char> scratch(1u << 16);
    while (this->At < offset)
    {
      if (this->Read(scratch.data(), std::min(scratch.size(), offset - this->At)) == 0)
      {
        return false;
      }
    }
    return true;
  }

private:
  // At least `count` unread compressed bytes in In when the file has them.
  void Refill(std::size_t count)
  {
    if (this->Stream.avail_in >= count || this->InAt >= this->File.Size())
    {
      return;
    }
    if (this->Stream.avail_in > 0)
    {
      std::memmove(this->In.data(), this->Stream.next_in, this->Stream.avail_in);
    }
    const std::size_t kept = this->Stream.avail_in;
    const std::size_t n = this->File.ReadAt(
      this->InAt, reinterpret_cast<char*>(this->In.data()) + kept, this->In.size() - kept);
    this->InAt += static_cast<long long>(n);
    this->Stream.next_in = this->In.data();
    this->Stream.avail_in = static_cast<uInt>(kept + n);
  }

  bool Fill()
  {
    this->WindowAt = this->WindowEnd = 0;
    while (this->Ready && this->WindowEnd == 0)
    {
      this->Refill(1);
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
        this->Refill(2);
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

  InputFile& File;
  const bool Compressed;
  bool Initialized = false; // inflateEnd is owed
  bool Ready = false;       // more can be inflated
  z_stream Stream;
  std::vector<unsigned char> In; // compressed bytes read from the file, from InAt on
  long long InAt = 0;
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
  InputFile Bytes;
  std::unique_ptr<Source> Stream;
  Header Parsed;
};

// Loads the file (or the input string) and parses its header; false with the whole message.
bool OpenInput(const char* fileName, bool fromString, const std::string& inputString,
  Input& input, std::string& error)
{
  if (!input.Bytes.Open(fileName, fromString, inputString, error))
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
  InputFile file;
  std::string error;
  if (!fileName || !file.Open(fileName, false, std::string(), error))
  {
    return 0;
  }
  Source source(file);
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
  // Any sub-extent can be read: the pipeline splits piece requests into extents.
  outInfo->Set(CAN_PRODUCE_SUB_EXTENT(), 1);
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
  const vtkIdType nc = header.Dim[3];
  const std::size_t valueBytes = static_cast<std::size_t>(header.Type.Bytes);
  const std::size_t offset = static_cast<std::size_t>(header.DataOffset);

  // The requested extent (the whole one unless a piece or sub-extent is asked for), within
  // the image; all components always.
  int extent[6] = { 0, static_cast<int>(header.Dim[0] - 1), 0,
    static_cast<int>(header.Dim[1] - 1), 0, static_cast<int>(header.Dim[2] - 1) };
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    int update[6];
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), update);
    for (int a = 0; a < 3; ++a)
    {
      extent[2 * a] = std::max(extent[2 * a], update[2 * a]);
      extent[2 * a + 1] = std::min(extent[2 * a + 1], update[2 * a + 1]);
    }
  }
  if (extent[0] > extent[1] || extent[2] > extent[3] || extent[4] > extent[5])
  {
    return 1; // an empty piece
  }
  const vtkIdType ex = extent[1] - extent[0] + 1, ey = extent[3] - extent[2] + 1,
                  ez = extent[5] - extent[4] + 1;

  // Only the data between the first and the last requested position along the slowest axis on
  // disk are read (a contiguous run of the file): uncompressed data are skipped by seeking,
  // compressed ones inflated and dropped, and the run is read a step at a time and scattered
  // into the output, so that memory holds the piece, not the image.
  int outer = 0;
  for (int a = 1; a < MaxAxes; ++a)
  {
    if (header.Dim[a] > 1 && (header.Dim[outer] == 1 || header.Stride[a] > header.Stride[outer]))
    {
      outer = a;
    }
  }
  vtkIdType low = 0, high = header.Dim[outer] - 1; // disk indices along `outer`
  if (outer < 3)
  {
    vtkIdType lo = extent[2 * outer], hi = extent[2 * outer + 1]; // MRtrix indices
    if (outer == 2 && this->SlicesReversed)
    {
      std::tie(lo, hi) = std::make_pair(header.Dim[2] - 1 - hi, header.Dim[2] - 1 - lo);
    }
    if (header.Reversed[outer])
    {
      std::tie(lo, hi) = std::make_pair(header.Dim[outer] - 1 - hi, header.Dim[outer] - 1 - lo);
    }
    low = lo;
    high = hi;
  }
  const vtkIdType outerStride = header.Dim[outer] > 1 ? header.Stride[outer] : header.Count;
  const std::size_t firstElement = static_cast<std::size_t>(low * outerStride);
  const std::size_t elements = static_cast<std::size_t>((high - low + 1) * outerStride);
  const std::size_t start = offset + firstElement * valueBytes;
  const std::size_t size = elements * valueBytes;

  output->SetExtent(extent);
  output->SetSpacing(header.Spacing.data());
  output->SetOrigin(0.0, 0.0, 0.0);
  vtkNew<vtkFloatArray> values;
  values->SetName("SHCoefficients");
  values->SetNumberOfComponents(static_cast<int>(nc));
  values->SetNumberOfTuples(ex * ey * ez);
  float* out = values->GetPointer(0);

  // The disk index of each axis for the element being read (an odometer in disk order, the
  // fastest axis first), starting at the run's first element.
  std::array<int, MaxAxes> order{ { 0, 1, 2, 3 } };
  std::stable_sort(order.begin(), order.end(),
    [&](int a, int b) { return header.Stride[a] < header.Stride[b]; });
  std::array<vtkIdType, MaxAxes> disk{ { 0, 0, 0, 0 } };
  disk[outer] = low;
  std::vector<unsigned char> buffer;
  std::size_t done = 0;
  bool complete = source.SkipTo(start);
  while (complete && done < size)
  {
    const std::size_t step = std::min(size - done, ReadStep);
    buffer.resize(step);
    const std::size_t got = source.Read(buffer.data(), step);
    done += got;
    if (got < step)
    {
      complete = false;
    }
    for (std::size_t e = 0; e + valueBytes <= got; e += valueBytes)
    {
      // Disk index -> MRtrix index -> VTK index (slices reversed for a left-handed grid).
      vtkIdType index[MaxAxes];
      for (int a = 0; a < MaxAxes; ++a)
      {
        index[a] = header.Reversed[a] ? header.Dim[a] - 1 - disk[a] : disk[a];
      }
      if (this->SlicesReversed)
      {
        index[2] = header.Dim[2] - 1 - index[2];
      }
      if (index[0] >= extent[0] && index[0] <= extent[1] && index[1] >= extent[2] &&
        index[1] <= extent[3] && index[2] >= extent[4] && index[2] <= extent[5])
      {
        const double stored = Convert(buffer.data() + e, header.Type);
        out[(((index[2] - extent[4]) * ey + (index[1] - extent[2])) * ex +
              (index[0] - extent[0])) * nc + index[3]] =
          static_cast<float>(header.ScaleOffset + header.ScaleMultiplier * stored);
      }
      for (const int a : order)
      {
        if (header.Dim[a] == 1)
        {
          continue;
        }
        if (++disk[a] < header.Dim[a])
        {
          break;
        }
        disk[a] = 0;
      }
    }
  }
  if (done < size)
  {
    const std::size_t inflated = source.Position() > offset ? source.Position() - offset : 0;
    vtkErrorMacro(<< name << " is truncated: the header promises " << header.Bytes
                  << " bytes of " << Quote(header.DataType) << " data at offset " << offset
                  << ", but only " << inflated << " could be "
                  << (source.IsCompressed() ? "inflated" : "read")
                  << (source.Error().empty() ? "" : " (gzip: " + source.Error() + ")") << ".");
    output->Initialize();
    return 0;
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
