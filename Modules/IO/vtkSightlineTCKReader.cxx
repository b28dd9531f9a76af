// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTCKReader.h"

#include "vtkCellArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include "SightlineMRtrixHeader.h"
#include "SightlineReaderInput.h"

#include <algorithm>
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

// The values of an MRtrix3 track scalar file (.tsf: a header like a .tck's, then one value per
// track point, each track ended by a NaN and the file by an Inf) for the tracks the reader kept:
// cell c is file track cellTrack[c] with cellSize[c] points. Only those tracks' values are
// stored; each must have exactly as many values as its track has points.
bool ReadTrackScalars(const char* fileName, const std::vector<long long>& cellTrack,
  const std::vector<vtkIdType>& cellSize, vtkFloatArray* out, std::string& error)
{
  InputFile input;
  if (!input.Open(fileName, false, std::string(), error))
  {
    return false;
  }
  const std::string name = "the track scalar file " + InputName(fileName, false);
  long long at = 0;
  MRtrixHeader header;
  if (!ReadMRtrixHeader([&] { return input.ByteAt(at++); }, "mrtrix track scalars",
        "MRtrix track scalar file", header, error))
  {
    error = name + ": " + error;
    return false;
  }
  MRtrixDataType type;
  if (!ParseDataType(header.Value("datatype"), type) ||
    (type.Type != MRtrixType::Float32 && type.Type != MRtrixType::Float64))
  {
    error = name + ": datatype '" + Quote(header.Value("datatype")) +
      "' is not one of Float32LE, Float32BE, Float64LE, Float64BE";
    return false;
  }
  long long offset = -1;
  const long long size = input.Size();
  if (!ParseDataFileEntry(header.Value("file"), offset) ||
    offset < static_cast<long long>(header.Size) || offset > size)
  {
    error = name + ": the 'file' entry does not give a data offset inside the file";
    return false;
  }
  vtkIdType total = 0;
  for (vtkIdType n : cellSize)
  {
    total += n;
  }
  out->SetNumberOfValues(total);
  const std::size_t valueSize = static_cast<std::size_t>(type.Bytes);
  const long long values = (size - offset) / static_cast<long long>(valueSize);
  constexpr long long chunkValues = 1 << 16;
  std::vector<char> chunk(static_cast<std::size_t>(chunkValues) * valueSize);
  std::size_t cell = 0;      // the next kept track
  long long track = 0;       // the file track being read
  vtkIdType inTrack = 0;     // its values so far
  vtkIdType written = 0;
  bool open = false;
  for (long long v0 = 0; v0 < values && cell < cellTrack.size(); v0 += chunkValues)
  {
    const long long count = std::min(chunkValues, values - v0);
    const std::size_t bytes = static_cast<std::size_t>(count) * valueSize;
    if (input.ReadAt(offset + v0 * static_cast<long long>(valueSize), chunk.data(), bytes) != bytes)
    {
      break;
    }
    ToHostByteOrder(chunk.data(), static_cast<std::size_t>(count), type);
    for (long long k = 0; k < count && cell < cellTrack.size(); ++k)
    {
      double value;
      if (valueSize == 4)
      {
        float f;
        std::memcpy(&f, chunk.data() + 4 * k, 4);
        value = f;
      }
      else
      {
        std::memcpy(&value, chunk.data() + 8 * k, 8);
      }
      if (std::isinf(value))
      {
        v0 = values; // the end marker
        break;
      }
      const bool kept = cellTrack[cell] == track;
      if (std::isnan(value))
      {
        if (open && kept)
        {
          if (inTrack != cellSize[cell])
          {
            error = name + ": track " + std::to_string(track) + " has " + std::to_string(inTrack) +
              " values but " + std::to_string(cellSize[cell]) + " points in the track file";
            return false;
          }
          ++cell;
        }
        track += open ? 1 : 0;
        open = false;
        inTrack = 0;
        continue;
      }
      open = true;
      if (kept && inTrack < cellSize[cell])
      {
        out->SetValue(written++, static_cast<float>(value));
      }
      ++inTrack;
    }
  }
  if (cell < cellTrack.size())
  {
    error = name + " ends after " + std::to_string(track) + " tracks, before track " +
      std::to_string(cellTrack[cell]) + " of the track file";
    return false;
  }
  return true;
}
} // namespace

vtkSightlineTCKReader::vtkSightlineTCKReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSightlineTCKReader::~vtkSightlineTCKReader()
{
  this->SetFileName(nullptr);
  this->SetScalarFileName(nullptr);
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

int vtkSightlineTCKReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  outputVector->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkSightlineTCKReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkPolyData* output = vtkPolyData::GetData(outInfo);
  int piece = 0, pieces = 1;
  sightline_io::RequestedPiece(outInfo, piece, pieces);
  InputFile input;
  std::string error;
  if (!input.Open(this->FileName, this->ReadFromInputString, this->InputString, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const std::string name = InputName(this->FileName, this->ReadFromInputString);
  long long at = 0;
  MRtrixHeader header;
  if (!ReadMRtrixHeader([&] { return input.ByteAt(at++); }, kMagic, "MRtrix track file", header,
        error))
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
  const long long size = input.Size();
  if (!ParseDataFileEntry(location, offset) || offset < static_cast<long long>(header.Size) ||
    offset > size)
  {
    vtkErrorMacro(<< name << ": the 'file' entry '" << Quote(location)
                  << "' does not give a data offset inside the file (" << size
                  << " bytes) and after the header (" << header.Size << " bytes).");
    return 0;
  }

  // The data: triplets until the Inf triplet, read a chunk at a time and converted to the
  // host's byte order. A streamline is a run of points ended by a NaN (or the Inf) triplet;
  // `visit` sees each triplet and returns false to stop.
  const std::size_t valueSize = static_cast<std::size_t>(type.Bytes);
  const std::size_t tripletBytes = 3 * valueSize;
  const long long triplets = (size - offset) / static_cast<long long>(tripletBytes);
  auto scan = [&](auto&& visit) {
    constexpr long long chunkTriplets = 1 << 14;
    std::vector<char> chunk(static_cast<std::size_t>(chunkTriplets) * tripletBytes);
    for (long long t0 = 0; t0 < triplets; t0 += chunkTriplets)
    {
      const long long count = std::min(chunkTriplets, triplets - t0);
      const std::size_t bytes = static_cast<std::size_t>(count) * tripletBytes;
      if (input.ReadAt(offset + t0 * static_cast<long long>(tripletBytes), chunk.data(),
            bytes) != bytes)
      {
        return; // a read error: as if the file ended here
      }
      ToHostByteOrder(chunk.data(), static_cast<std::size_t>(3 * count), type);
      for (long long t = 0; t < count; ++t)
      {
        double p[3];
        for (int a = 0; a < 3; ++a)
        {
          const char* v = chunk.data() + (3 * t + a) * valueSize;
          if (valueSize == 4)
          {
            float f;
            std::memcpy(&f, v, 4);
            p[a] = f;
          }
          else
          {
            std::memcpy(&p[a], v, 8);
          }
        }
        if (!visit(p))
        {
          return;
        }
      }
    }
  };
  auto isEnd = [](const double p[3]) {
    return std::isinf(p[0]) || std::isinf(p[1]) || std::isinf(p[2]);
  };
  auto isBreak = [](const double p[3]) {
    return std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2]);
  };

  // This piece's streamlines: [piece * N / pieces, (piece + 1) * N / pieces) of the N in the
  // file, the last piece also taking any beyond N (so a wrong `count` loses nothing). N is the
  // header's count, or found by a scan that stores nothing.
  const std::string count = header.Value("count");
  long long expected = -1;
  if (count.empty() || !ParseInteger(count, expected) || expected < 0)
  {
    expected = -1;
  }
  long long total = expected;
  if (pieces > 1 && total < 0)
  {
    total = 0;
    bool open = false;
    scan([&](const double p[3]) {
      if (isEnd(p) || isBreak(p))
      {
        total += open ? 1 : 0;
        open = false;
        return !isEnd(p);
      }
      open = true;
      return true;
    });
  }
  const long long first = pieces > 1 ? total * piece / pieces : 0;
  const long long last =
    piece + 1 < pieces ? total * (piece + 1) / pieces : std::numeric_limits<long long>::max();

  // Points are stored in single precision: a finite Float64 value beyond its range would
  // become an infinity.
  constexpr double largest = std::numeric_limits<float>::max();
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  std::vector<double> current; // the streamline being read, added once it is complete
  bool open = false;           // a streamline has started (whether or not it is this piece's)
  bool finished = false, outOfRange = false, toEnd = false;
  long long streamline = 0; // index of the streamline being read in the file
  vtkIdType skipped = 0;
  long long firstSkipped = -1;
  double badValue = 0.0;
  std::vector<long long> cellTrack; // the file streamline of each cell (for a .tsf)
  std::vector<vtkIdType> cellSize;
  auto endStreamline = [&] {
    if (open && streamline >= first)
    {
      if (outOfRange)
      {
        firstSkipped = skipped == 0 ? streamline : firstSkipped;
        ++skipped;
      }
      else
      {
        const vtkIdType firstPoint = points->GetNumberOfPoints();
        const vtkIdType n = static_cast<vtkIdType>(current.size() / 3);
        cellTrack.push_back(streamline);
        cellSize.push_back(n);
        lines->InsertNextCell(n);
        for (vtkIdType k = 0; k < n; ++k)
        {
          points->InsertNextPoint(&current[3 * k]);
          lines->InsertCellPoint(firstPoint + k);
        }
      }
    }
    streamline += open ? 1 : 0;
    open = false;
    current.clear();
    outOfRange = false;
  };
  if (first < last)
  {
    toEnd = true;
    scan([&](const double p[3]) {
      if (isEnd(p))
      {
        finished = true;
        endStreamline();
        return false;
      }
      if (isBreak(p))
      {
        endStreamline();
        if (streamline >= last)
        {
          toEnd = false; // this piece's streamlines are read; the rest are other pieces'
          return false;
        }
        return true;
      }
      open = true;
      if (streamline < first)
      {
        return true;
      }
      for (int a = 0; a < 3; ++a)
      {
        if (std::fabs(p[a]) > largest && !outOfRange)
        {
          outOfRange = true;
          badValue = skipped == 0 ? p[a] : badValue;
        }
      }
      current.insert(current.end(), p, p + 3);
      return true;
    });
  }
  if (toEnd && !finished)
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
  if (toEnd && !count.empty() && (expected < 0 || expected != streamline))
  {
    vtkWarningMacro(<< name << ": the header's count is " << Quote(count) << " but "
                    << streamline << " streamlines were read.");
  }
  // Insertion grows the arrays by doubling: give back the unused capacity (up to half of a
  // piece's points and connectivity, kept for as long as the output lives).
  points->Squeeze();
  lines->Squeeze();
  if (this->ScalarFileName && *this->ScalarFileName)
  {
    vtkNew<vtkFloatArray> values;
    std::string stem = this->ScalarFileName;
    stem = stem.substr(stem.find_last_of('/') + 1);
    if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".tsf") == 0)
    {
      stem.resize(stem.size() - 4);
    }
    values->SetName(Quote(stem).c_str());
    if (!ReadTrackScalars(this->ScalarFileName, cellTrack, cellSize, values, error))
    {
      vtkErrorMacro(<< name << ": " << error);
      return 0;
    }
    output->GetPointData()->AddArray(values);
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
  os << indent << "ScalarFileName: " << (this->ScalarFileName ? this->ScalarFileName : "(none)")
     << "\n";
}
