// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTrackVisReader.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include "SightlineReaderInput.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

vtkStandardNewMacro(vtkSightlineTrackVisReader);

namespace
{
constexpr int kHeaderSize = 1000;

/// Reads little- or big-endian values from the header and the body.
class Decoder
{
public:
  explicit Decoder(bool swap) : Swap(swap) {}

  template <class T>
  T Get(const char* bytes) const
  {
    char copy[sizeof(T)];
    std::memcpy(copy, bytes, sizeof(T));
    if (this->Swap)
    {
      std::reverse(copy, copy + sizeof(T));
    }
    T value;
    std::memcpy(&value, copy, sizeof(T));
    return value;
  }

private:
  bool Swap;
};

/// A run of per-point scalars or per-streamline properties stored as one array.
struct ValueArray
{
  std::string Name;
  int First = 0; ///< its first value among the point's (streamline's) values
  int Count = 1; ///< its components
};

/// The arrays of `values` values named by the ten 20-byte fields at `fields`. A field
/// "NAME\0COUNT" names COUNT consecutive values (nibabel's convention for vectors such as
/// colours); values no field names become one-component arrays "<fallback><index>".
std::vector<ValueArray> ValueArrays(const char* fields, int values, const std::string& fallback)
{
  std::vector<ValueArray> arrays;
  int next = 0;
  for (int f = 0; f < 10 && next < values; ++f)
  {
    const char* field = fields + 20 * f;
    const std::size_t length = strnlen(field, 20);
    if (length == 0)
    {
      break;
    }
    int count = 1;
    if (length + 1 < 20)
    {
      const std::string rest(field + length + 1, strnlen(field + length + 1, 19 - length));
      if (!rest.empty() && rest.size() <= 3 &&
        rest.find_first_not_of("0123456789") == std::string::npos)
      {
        count = std::max(1, std::stoi(rest));
      }
    }
    count = std::min(count, values - next);
    arrays.push_back({ std::string(field, length), next, count });
    next += count;
  }
  for (; next < values; ++next)
  {
    arrays.push_back({ fallback + std::to_string(next), next, 1 });
  }
  return arrays;
}

/// Orientation of voxel axis j of a matrix: the world axis (0 x/R, 1 y/A, 2 z/S) it runs along
/// most and the direction (+1 towards R/A/S).
void AxisCodes(const double m[4][4], int axis[3], int sign[3])
{
  for (int j = 0; j < 3; ++j)
  {
    int best = 0;
    for (int i = 1; i < 3; ++i)
    {
      if (std::abs(m[i][j]) > std::abs(m[best][j]))
      {
        best = i;
      }
    }
    axis[j] = best;
    sign[j] = m[best][j] >= 0.0 ? 1 : -1;
  }
}
} // namespace

vtkSightlineTrackVisReader::vtkSightlineTrackVisReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSightlineTrackVisReader::~vtkSightlineTrackVisReader()
{
  this->SetFileName(nullptr);
}

void vtkSightlineTrackVisReader::SetInputString(const std::string& bytes)
{
  if (bytes != this->InputString)
  {
    this->InputString = bytes;
    this->Modified();
  }
}

int vtkSightlineTrackVisReader::CanReadFile(const char* fileName)
{
  std::ifstream file(fileName ? fileName : "", std::ios::binary);
  char id[6] = {};
  return file.read(id, 6) && std::memcmp(id, "TRACK", 5) == 0;
}

int vtkSightlineTrackVisReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  outputVector->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkSightlineTrackVisReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkPolyData* output = vtkPolyData::GetData(outInfo);
  int piece = 0, pieces = 1;
  sightline_io::RequestedPiece(outInfo, piece, pieces);
  this->VoxmmToRAS->Identity();
  sightline_io::InputFile input;
  std::string error;
  if (!input.Open(this->FileName, this->ReadFromInputString, this->InputString, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const std::string name = sightline_io::InputName(this->FileName, this->ReadFromInputString);
  char headerBytes[kHeaderSize];
  if (input.Size() < kHeaderSize ||
    input.ReadAt(0, headerBytes, kHeaderSize) != static_cast<std::size_t>(kHeaderSize) ||
    std::memcmp(headerBytes, "TRACK", 5) != 0)
  {
    vtkErrorMacro(<< name << " is not a TrackVis file: it does not start with a " << kHeaderSize
                  << "-byte header whose id is TRACK.");
    return 0;
  }
  const char* header = headerBytes;
  // The header size (1000) tells the byte order: read as the host's, or swapped.
  const Decoder native(false), swapped(true);
  Decoder decode = native;
  if (native.Get<std::int32_t>(header + 996) != kHeaderSize)
  {
    if (swapped.Get<std::int32_t>(header + 996) != kHeaderSize)
    {
      vtkErrorMacro(<< name << ": the header size field is neither 1000 little- nor "
                    << "big-endian; not a TrackVis file or a damaged one.");
      return 0;
    }
    decode = swapped;
  }

  int dims[3];
  double voxelSize[3];
  for (int a = 0; a < 3; ++a)
  {
    dims[a] = decode.Get<std::int16_t>(header + 6 + 2 * a);
    voxelSize[a] = decode.Get<float>(header + 12 + 4 * a);
  }
  const int scalars = std::max(0, static_cast<int>(decode.Get<std::int16_t>(header + 36)));
  const int properties = std::max(0, static_cast<int>(decode.Get<std::int16_t>(header + 238)));
  if (scalars > 10 || properties > 10)
  {
    vtkErrorMacro(<< name << ": " << scalars << " scalars and " << properties
                  << " properties per point/streamline; TrackVis allows 10 of each.");
    return 0;
  }
  double voxToRAS[4][4];
  for (int r = 0; r < 4; ++r)
  {
    for (int c = 0; c < 4; ++c)
    {
      voxToRAS[r][c] = decode.Get<float>(header + 440 + 4 * (4 * r + c));
    }
  }
  if (voxToRAS[3][3] == 0.0)
  {
    // Version 1 files have none: TrackVis assumes the identity (as nibabel does).
    for (int r = 0; r < 4; ++r)
    {
      for (int c = 0; c < 4; ++c)
      {
        voxToRAS[r][c] = r == c ? 1.0 : 0.0;
      }
    }
  }
  std::string order(header + 948, strnlen(header + 948, 4));
  for (char& ch : order)
  {
    ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  }
  if (order.size() != 3)
  {
    order = "LPS"; // TrackVis' default when the file says nothing
  }
  std::copy(order.begin(), order.end(), this->VoxelOrder);
  this->VoxelOrder[3] = 0;

  // voxmm -> voxel centres -> the matrix's voxel order (nibabel's ornt_transform and
  // inv_ornt_aff) -> RAS mm.
  if (!this->CoordinatesVoxmm)
  {
    for (int a = 0; a < 3; ++a)
    {
      if (!(voxelSize[a] > 0.0) || !std::isfinite(voxelSize[a]))
      {
        vtkErrorMacro(<< name << ": voxel size " << voxelSize[a] << " along axis " << a
                      << " cannot map voxmm to RAS mm (CoordinatesVoxmm keeps the raw values).");
        return 0;
      }
    }
    double rotation[3][3];
    bool finite = true;
    for (int r = 0; r < 4; ++r)
    {
      for (int c = 0; c < 4; ++c)
      {
        finite = finite && std::isfinite(voxToRAS[r][c]);
        if (r < 3 && c < 3)
        {
          rotation[r][c] = voxToRAS[r][c];
        }
      }
    }
    int matrixAxis[3], matrixSign[3];
    AxisCodes(voxToRAS, matrixAxis, matrixSign);
    if (!finite || vtkMath::Determinant3x3(rotation) == 0.0 ||
      matrixAxis[0] == matrixAxis[1] || matrixAxis[1] == matrixAxis[2] ||
      matrixAxis[0] == matrixAxis[2])
    {
      vtkErrorMacro(<< name << ": the voxel-to-RAS matrix is not finite, or its voxel axes do "
                    << "not run along three different world axes (CoordinatesVoxmm keeps the "
                    << "raw values).");
      return 0;
    }
    int toAxis[3], flip[3];
    bool named[3] = { false, false, false };
    for (int i = 0; i < 3; ++i)
    {
      const char letter = order[i];
      const char* positive = "RAS";
      const char* negative = "LPI";
      const char* p = std::strchr(positive, letter);
      const char* q = std::strchr(negative, letter);
      if (!letter || (!p && !q))
      {
        vtkErrorMacro(<< name << ": voxel order '" << sightline_io::Quote(order)
                      << "' is not made of R/L, A/P, S/I.");
        return 0;
      }
      const int worldAxis = p ? static_cast<int>(p - positive) : static_cast<int>(q - negative);
      const int sign = p ? 1 : -1;
      if (named[worldAxis])
      {
        vtkErrorMacro(<< name << ": voxel order '" << sightline_io::Quote(order)
                      << "' names the axis " << positive[worldAxis] << "/" << negative[worldAxis]
                      << " twice; it must name R/L, A/P and S/I once each.");
        return 0;
      }
      named[worldAxis] = true;
      toAxis[i] = -1;
      for (int j = 0; j < 3; ++j)
      {
        if (matrixAxis[j] == worldAxis)
        {
          toAxis[i] = j;
          flip[i] = sign * matrixSign[j];
        }
      }
      if (toAxis[i] < 0)
      {
        vtkErrorMacro(<< name << ": voxel order '" << sightline_io::Quote(order)
                      << "' does not match the axes of the voxel-to-RAS matrix.");
        return 0;
      }
    }
    vtkNew<vtkMatrix4x4> toCentres; // voxmm / size - 0.5
    vtkNew<vtkMatrix4x4> reorder;   // y_i = flip(x)_{toAxis[i]} about the grid's centre
    reorder->Zero();
    reorder->SetElement(3, 3, 1.0);
    for (int a = 0; a < 3; ++a)
    {
      toCentres->SetElement(a, a, 1.0 / voxelSize[a]);
      toCentres->SetElement(a, 3, -0.5);
    }
    for (int i = 0; i < 3; ++i)
    {
      const int k = toAxis[i];
      const double centre = 0.5 * (dims[k] - 1);
      reorder->SetElement(i, k, flip[k]);
      reorder->SetElement(i, 3, centre - flip[k] * centre);
    }
    vtkNew<vtkMatrix4x4> toRAS;
    toRAS->DeepCopy(&voxToRAS[0][0]);
    vtkMatrix4x4::Multiply4x4(reorder, toCentres, this->VoxmmToRAS);
    vtkMatrix4x4::Multiply4x4(toRAS, this->VoxmmToRAS, this->VoxmmToRAS);
  }

  // The streamlines, read one at a time from the file. This piece's are
  // [piece * N / pieces, (piece + 1) * N / pieces) of the N in the file, the last piece also
  // taking any beyond N (so a wrong n_count loses nothing); the others' are skipped by their
  // point counts, never read. N is the header's n_count, or counted by such a skipping scan.
  const long long bodySize = input.Size() - kHeaderSize;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  const std::vector<ValueArray> scalarRuns = ValueArrays(header + 38, scalars, "scalar_");
  const std::vector<ValueArray> propertyRuns = ValueArrays(header + 240, properties, "property_");
  std::vector<vtkSmartPointer<vtkFloatArray>> scalarArrays, propertyArrays;
  for (const auto& [runs, arrays] :
    { std::make_pair(&scalarRuns, &scalarArrays), std::make_pair(&propertyRuns, &propertyArrays) })
  {
    for (const ValueArray& run : *runs)
    {
      arrays->push_back(vtkSmartPointer<vtkFloatArray>::New());
      arrays->back()->SetNumberOfComponents(run.Count);
      arrays->back()->SetName(sightline_io::Quote(run.Name).c_str());
    }
  }
  const std::size_t pointBytes = 4u * (3u + scalars);
  const std::int32_t expected = decode.Get<std::int32_t>(header + 988);
  // The point count of the streamline at `at` (relative to the body) and its size in bytes;
  // false at the end of the body, with `negative` set for a negative count.
  auto next = [&](long long at, std::int32_t& count, long long& bytes, bool& negative) {
    char raw[4];
    negative = false;
    if (at + 4 > bodySize || input.ReadAt(kHeaderSize + at, raw, 4) != 4)
    {
      return false;
    }
    count = decode.Get<std::int32_t>(raw);
    negative = count < 0;
    bytes = 4 + static_cast<long long>(count) * static_cast<long long>(pointBytes) +
      4LL * properties;
    return !negative;
  };
  long long total = expected > 0 ? expected : 0;
  if (pieces > 1 && expected <= 0)
  {
    std::int32_t count;
    long long bytes;
    bool negative;
    for (long long at = 0; next(at, count, bytes, negative) && at + bytes <= bodySize; at += bytes)
    {
      ++total;
    }
  }
  const long long firstWanted = pieces > 1 ? total * piece / pieces : 0;
  const long long lastWanted =
    piece + 1 < pieces ? total * (piece + 1) / pieces : std::numeric_limits<long long>::max();

  long long at = 0;
  std::vector<double> mapped;
  std::vector<char> buffer;
  bool cut = false, toEnd = firstWanted < lastWanted;
  vtkIdType streamline = 0, skipped = 0, firstSkipped = -1;
  while (toEnd && at + 4 <= bodySize)
  {
    if (streamline >= lastWanted)
    {
      toEnd = false; // the rest are other pieces'
      break;
    }
    std::int32_t count = 0;
    long long bytes = 0;
    bool negative = false;
    if (!next(at, count, bytes, negative))
    {
      if (negative)
      {
        vtkErrorMacro(<< name << ": streamline " << streamline << " has the negative point count " << count << ".");
        output->Initialize();
        return 0;
      }
      cut = true;
      break;
    }
    if (at + bytes > bodySize)
    {
      cut = true;
      break;
    }
    if (streamline < firstWanted)
    {
      at += bytes;
      ++streamline;
      continue;
    }
    buffer.resize(static_cast<std::size_t>(bytes));
    if (input.ReadAt(kHeaderSize + at, buffer.data(), buffer.size()) != buffer.size())
    {
      cut = true;
      break;
    }
    // The points first, mapped: a streamline with a NaN or infinite coordinate, or one that
    // maps beyond float range, is left out whole (its scalars and properties with it).
    mapped.resize(3 * static_cast<std::size_t>(count));
    const char* data = buffer.data() + 4;
    bool finite = true;
    for (std::int32_t k = 0; k < count; ++k)
    {
      const char* point = data + k * pointBytes;
      double p[4] = { decode.Get<float>(point), decode.Get<float>(point + 4),
        decode.Get<float>(point + 8), 1.0 };
      if (!this->CoordinatesVoxmm)
      {
        this->VoxmmToRAS->MultiplyPoint(p, p);
      }
      // The output points are floats: a finite double beyond float range would become inf.
      constexpr double largest = std::numeric_limits<float>::max();
      finite = finite && std::abs(p[0]) <= largest && std::abs(p[1]) <= largest &&
        std::abs(p[2]) <= largest;
      std::copy(p, p + 3, mapped.begin() + 3 * k);
    }
    at += bytes;
    ++streamline;
    if (!finite)
    {
      firstSkipped = skipped++ == 0 ? streamline - 1 : firstSkipped;
      continue;
    }
    const vtkIdType first = points->GetNumberOfPoints();
    lines->InsertNextCell(count);
    for (std::int32_t k = 0; k < count; ++k)
    {
      points->InsertNextPoint(&mapped[3 * k]);
      lines->InsertCellPoint(first + k);
      for (std::size_t a = 0; a < scalarRuns.size(); ++a)
      {
        for (int c = 0; c < scalarRuns[a].Count; ++c)
        {
          scalarArrays[a]->InsertNextValue(
            decode.Get<float>(data + k * pointBytes + 12 + 4 * (scalarRuns[a].First + c)));
        }
      }
    }
    for (std::size_t a = 0; a < propertyRuns.size(); ++a)
    {
      for (int c = 0; c < propertyRuns[a].Count; ++c)
      {
        propertyArrays[a]->InsertNextValue(
          decode.Get<float>(data + count * pointBytes + 4 * (propertyRuns[a].First + c)));
      }
    }
  }
  if (skipped > 0)
  {
    vtkWarningMacro(<< name << ": " << skipped << " streamlines have NaN or infinite "
                    << "coordinates, or coordinates beyond single precision in RAS, and were "
                    << "left out (the first is streamline " << firstSkipped << ").");
  }
  if (toEnd && (cut || at != bodySize))
  {
    vtkWarningMacro(<< name << " ends inside streamline " << streamline
                    << " (cut short?); the " << lines->GetNumberOfCells()
                    << " complete streamlines are kept.");
  }
  if (toEnd && expected > 0 && expected != streamline)
  {
    vtkWarningMacro(<< name << ": the header's n_count is " << expected << " but "
                    << streamline << " streamlines were read.");
  }
  // Insertion grows the arrays by doubling: give back the unused capacity (up to half of a
  // piece's points and connectivity, kept for as long as the output lives).
  points->Squeeze();
  lines->Squeeze();
  output->SetPoints(points);
  output->SetLines(lines);
  for (auto& array : scalarArrays)
  {
    output->GetPointData()->AddArray(array);
  }
  for (auto& array : propertyArrays)
  {
    output->GetCellData()->AddArray(array);
  }
  return 1;
}

void vtkSightlineTrackVisReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ReadFromInputString: " << this->ReadFromInputString << "\n";
  os << indent << "CoordinatesVoxmm: " << this->CoordinatesVoxmm << "\n";
  os << indent << "VoxelOrder: " << this->VoxelOrder << "\n";
  os << indent << "VoxmmToRAS:\n";
  this->VoxmmToRAS->PrintSelf(os, indent.GetNextIndent());
}
