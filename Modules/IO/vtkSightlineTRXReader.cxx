// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTRXReader.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkTypeInt32Array.h"
#include "vtkTypeInt64Array.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtk_jsoncpp.h"

#include "SightlineReaderInput.h"
#include "SightlineTRXArchive.h"
#include "SightlineTRXFormat.h"
#include "SightlineZip.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <vector>

vtkStandardNewMacro(vtkSightlineTRXReader);

namespace
{
using namespace sightline_io;
using namespace sightline_io::trx;

constexpr std::size_t kBlockBytes = 1 << 20;
constexpr std::uint64_t kMaxHeaderBytes = 1 << 20;
// Far beyond any tractogram, and small enough that rows * columns * 8 cannot overflow.
constexpr std::uint64_t kMaxCount = std::uint64_t(1) << 48;

// A TRX member, its parsed name and where to read it from.
struct Array
{
  const TRXArchiveReader::Member* Member = nullptr;
  MemberName Name;
  std::uint64_t Rows = 0;
};

// Rows [first, first + rows) of `array` into `out`'s values from tuple `firstTuple` on, a block
// at a time; `progress` is told the fraction done.
template <typename Progress>
bool ReadRows(TRXMemberStream& stream, const Array& array, std::uint64_t first, std::uint64_t rows,
  vtkDataArray* out, std::string& error, Progress&& progress)
{
  if (out->GetNumberOfValues() < static_cast<vtkIdType>(rows * array.Name.Columns))
  {
    error = "not enough memory for " + Quote(array.Member->Path);
    return false;
  }
  const std::size_t valueSize = DTypeSize(array.Name.Type);
  const std::uint64_t rowBytes = array.Name.Columns * valueSize;
  const std::uint64_t rowsPerBlock = std::max<std::uint64_t>(1, kBlockBytes / rowBytes);
  std::vector<char> block;
  for (std::uint64_t done = 0; done < rows;)
  {
    const std::uint64_t n = std::min(rowsPerBlock, rows - done);
    block.resize(static_cast<std::size_t>(n * rowBytes));
    if (!stream.Read((first + done) * rowBytes, block.data(), block.size(), error))
    {
      return false;
    }
    ConvertRows(block.data(), array.Name.Type, static_cast<std::size_t>(n * array.Name.Columns),
      out, static_cast<std::size_t>(done * array.Name.Columns));
    done += n;
    progress(static_cast<double>(done) / static_cast<double>(rows));
  }
  return true;
}

// Integer rows (offsets, group members) [first, first + rows) as unsigned 64-bit values.
bool ReadIndices(TRXMemberStream& stream, const Array& array, std::uint64_t first, std::uint64_t rows,
  std::vector<std::uint64_t>& out, std::string& error)
{
  vtkSmartPointer<vtkDataArray> values;
  values.TakeReference(vtkDataArray::CreateDataArray(VTKType(array.Name.Type)));
  out.clear();
  constexpr std::uint64_t kRows = kBlockBytes / 8;
  for (std::uint64_t done = 0; done < rows;)
  {
    const std::uint64_t n = std::min(kRows, rows - done);
    values->SetNumberOfValues(static_cast<vtkIdType>(n));
    if (!ReadRows(stream, array, first + done, n, values, error, [](double) {}))
    {
      return false;
    }
    for (std::uint64_t i = 0; i < n; ++i)
    {
      const double asDouble = values->GetComponent(static_cast<vtkIdType>(i), 0);
      if (asDouble < 0)
      {
        error = Quote(array.Member->Path) + " holds the negative value " +
          std::to_string(static_cast<long long>(asDouble)) + " at row " +
          std::to_string(first + done + i);
        return false;
      }
      std::uint64_t value = 0;
      switch (array.Name.Type)
      {
        case DType::UInt64:
          value = static_cast<const std::uint64_t*>(values->GetVoidPointer(0))[i];
          break;
        case DType::Int64:
          value = static_cast<std::uint64_t>(static_cast<const std::int64_t*>(values->GetVoidPointer(0))[i]);
          break;
        default:
          value = static_cast<std::uint64_t>(asDouble);
      }
      out.push_back(value);
    }
    done += n;
  }
  return true;
}

bool CountField(const Json::Value& header, const char* key, std::uint64_t& value, std::string& error)
{
  const Json::Value& field = header[key];
  if (!field.isUInt64() || field.asUInt64() > kMaxCount)
  {
    error = std::string("header.json has no valid ") + key +
      " (a non-negative integer below 2^48)";
    return false;
  }
  value = field.asUInt64();
  return true;
}
} // namespace

vtkSightlineTRXReader::vtkSightlineTRXReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSightlineTRXReader::~vtkSightlineTRXReader()
{
  this->SetFileName(nullptr);
}

void vtkSightlineTRXReader::SetInputString(const std::string& bytes)
{
  if (bytes != this->InputString)
  {
    this->InputString = bytes;
    this->Modified();
  }
}

int vtkSightlineTRXReader::CanReadFile(const char* fileName)
{
  if (!fileName)
  {
    return 0;
  }
  std::error_code code;
  if (std::filesystem::is_directory(fileName, code))
  {
    return std::filesystem::is_regular_file(std::filesystem::path(fileName) / "header.json", code);
  }
  InputFile input;
  std::string error;
  std::vector<ZipEntry> entries;
  if (!input.Open(fileName, false, std::string(), error) || !LooksLikeZip(input) ||
    !ReadZipDirectory(input, entries, error))
  {
    return 0;
  }
  return std::any_of(
    entries.begin(), entries.end(), [](const ZipEntry& e) { return e.Name == "header.json"; });
}

int vtkSightlineTRXReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  outputVector->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkSightlineTRXReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkPolyData* output = vtkPolyData::GetData(outInfo);
  int piece = 0, pieces = 1;
  RequestedPiece(outInfo, piece, pieces);
  const std::string name = InputName(this->FileName, this->ReadFromInputString);
  std::string error;
  TRXArchiveReader source;
  if (!source.Open(this->FileName, this->ReadFromInputString, this->InputString, error))
  {
    vtkErrorMacro(<< name << ": " << error);
    return 0;
  }
  auto fail = [&](const std::string& message) {
    vtkErrorMacro(<< name << ": " << message);
    output->Initialize();
    return 0;
  };

  // The header.
  const TRXArchiveReader::Member* headerMember = nullptr;
  for (const TRXArchiveReader::Member& member : source.Members)
  {
    if (member.Path == "header.json")
    {
      headerMember = &member;
    }
  }
  if (!headerMember)
  {
    return fail("no header.json: not a TRX file");
  }
  if (headerMember->Size > kMaxHeaderBytes)
  {
    return fail("header.json is " + std::to_string(headerMember->Size) + " bytes, not a TRX header");
  }
  std::string headerText(static_cast<std::size_t>(headerMember->Size), '\0');
  {
    std::unique_ptr<TRXMemberStream> stream = source.OpenMember(*headerMember, error);
    if (!stream || !stream->Read(0, &headerText[0], headerText.size(), error))
    {
      return fail(error);
    }
  }
  Json::Value header;
  {
    Json::CharReaderBuilder builder;
    builder["collectComments"] = false;
    builder["stackLimit"] = 64;
    std::unique_ptr<Json::CharReader> parser(builder.newCharReader());
    std::string errors;
    bool parsed = false;
    try
    {
      parsed = parser->parse(headerText.data(), headerText.data() + headerText.size(), &header, &errors);
    }
    catch (const std::exception& e)
    {
      errors = e.what();
    }
    if (!parsed || !header.isObject())
    {
      return fail("header.json is not a JSON object: " + Quote(errors));
    }
  }
  std::uint64_t vertexCount = 0, streamlineCount = 0;
  if (!CountField(header, "NB_VERTICES", vertexCount, error) ||
    !CountField(header, "NB_STREAMLINES", streamlineCount, error))
  {
    return fail(error);
  }
  vtkNew<vtkDoubleArray> affine;
  affine->SetName("VOXEL_TO_RASMM");
  if (header.isMember("VOXEL_TO_RASMM"))
  {
    const Json::Value& m = header["VOXEL_TO_RASMM"];
    bool valid = m.isArray() && m.size() == 4;
    for (Json::ArrayIndex r = 0; valid && r < 4; ++r)
    {
      valid = m[r].isArray() && m[r].size() == 4;
      for (Json::ArrayIndex c = 0; valid && c < 4; ++c)
      {
        valid = m[r][c].isNumeric() && std::isfinite(m[r][c].asDouble());
        if (valid)
        {
          affine->InsertNextValue(m[r][c].asDouble());
        }
      }
    }
    if (!valid)
    {
      return fail("header.json's VOXEL_TO_RASMM is not a 4x4 matrix of numbers");
    }
  }
  vtkNew<vtkIntArray> dimensions;
  dimensions->SetName("DIMENSIONS");
  if (header.isMember("DIMENSIONS"))
  {
    const Json::Value& d = header["DIMENSIONS"];
    bool valid = d.isArray() && d.size() == 3;
    for (Json::ArrayIndex k = 0; valid && k < 3; ++k)
    {
      valid = d[k].isInt() && d[k].asInt() >= 0;
      if (valid)
      {
        dimensions->InsertNextValue(d[k].asInt());
      }
    }
    if (!valid)
    {
      return fail("header.json's DIMENSIONS are not 3 non-negative integers");
    }
  }

  // The members: each checked against the header before anything is read.
  Array positions, offsets;
  bool havePositions = false, haveOffsets = false;
  std::vector<Array> dpv, dps, groups, dpg;
  for (const TRXArchiveReader::Member& member : source.Members)
  {
    if (&member == headerMember)
    {
      continue;
    }
    Array array;
    array.Member = &member;
    if (!ParseMemberName(member.Path, array.Name, error))
    {
      return fail(error);
    }
    const MemberName& n = array.Name;
    const std::uint64_t rowBytes = n.Columns * DTypeSize(n.Type);
    if (member.Size % rowBytes != 0)
    {
      return fail(Quote(member.Path) + " holds " + std::to_string(member.Size) +
        " bytes, not whole rows of " + std::to_string(rowBytes));
    }
    array.Rows = member.Size / rowBytes;
    auto expectRows = [&](std::uint64_t rows, const char* what) {
      if (array.Rows != rows)
      {
        error = Quote(member.Path) + " holds " + std::to_string(array.Rows) + " rows, not " +
          std::to_string(rows) + " (" + what + ")";
        return false;
      }
      return true;
    };
    if (n.Folder.empty() && n.Base == "positions")
    {
      if (n.Columns != 3 || (n.Type != DType::Float16 && n.Type != DType::Float32 &&
                              n.Type != DType::Float64))
      {
        return fail(Quote(member.Path) + ": positions must be 3 columns of float16, float32 or float64");
      }
      if (havePositions || !expectRows(vertexCount, "NB_VERTICES"))
      {
        return fail(havePositions ? "two positions members" : error);
      }
      positions = array;
      havePositions = true;
    }
    else if (n.Folder.empty() && n.Base == "offsets")
    {
      if (n.Columns != 1 || !IsInteger(n.Type) || n.Type == DType::Bit)
      {
        return fail(Quote(member.Path) + ": offsets must be one column of integers");
      }
      if (haveOffsets || (array.Rows != streamlineCount && array.Rows != streamlineCount + 1))
      {
        return fail(haveOffsets ? "two offsets members"
                                : Quote(member.Path) + " holds " + std::to_string(array.Rows) +
              " offsets for NB_STREAMLINES " + std::to_string(streamlineCount) +
              " (expected that many, or one more)");
      }
      offsets = array;
      haveOffsets = true;
    }
    else if (n.Folder == "dpv")
    {
      if (!expectRows(vertexCount, "NB_VERTICES"))
      {
        return fail(error);
      }
      dpv.push_back(array);
    }
    else if (n.Folder == "dps")
    {
      if (!expectRows(streamlineCount, "NB_STREAMLINES"))
      {
        return fail(error);
      }
      dps.push_back(array);
    }
    else if (n.Folder == "groups")
    {
      if (n.Columns != 1 || !IsInteger(n.Type) || n.Type == DType::Bit)
      {
        return fail(Quote(member.Path) + ": a group must be one column of integer streamline indices");
      }
      groups.push_back(array);
    }
    else if (n.Folder.compare(0, 4, "dpg/") == 0 && n.Folder.find('/', 4) == std::string::npos &&
      n.Folder.size() > 4)
    {
      if (!expectRows(1, "data per group is one row"))
      {
        return fail(error);
      }
      dpg.push_back(array);
    }
    else
    {
      vtkWarningMacro(<< name << ": skipped " << Quote(member.Path) << ", which TRX does not define");
    }
  }
  for (const std::vector<Array>* list : { &dpv, &dps, &groups })
  {
    for (std::size_t i = 0; i < list->size(); ++i)
    {
      for (std::size_t j = 0; j < i; ++j)
      {
        if ((*list)[i].Name.Base == (*list)[j].Name.Base)
        {
          return fail("two members named " + Quote((*list)[i].Member->Path) + " and " +
            Quote((*list)[j].Member->Path));
        }
      }
    }
  }
  for (const Array& data : dpg)
  {
    const std::string group = data.Name.Folder.substr(4);
    if (std::none_of(groups.begin(), groups.end(), [&](const Array& g) { return g.Name.Base == group; }))
    {
      return fail(Quote(data.Member->Path) + " is data for the undeclared group " + Quote(group));
    }
  }
  if (streamlineCount == 0 || vertexCount == 0)
  {
    output->Initialize(); // an empty tractogram, as trx-python reads it
    return 1;
  }
  if (!havePositions || !haveOffsets)
  {
    return fail(havePositions ? "no offsets member" : "no positions member");
  }

  // This piece's streamlines and their vertex range.
  const std::uint64_t first = static_cast<std::uint64_t>(
    static_cast<unsigned __int128>(streamlineCount) * static_cast<unsigned>(piece) / static_cast<unsigned>(pieces));
  const std::uint64_t last = static_cast<std::uint64_t>(
    static_cast<unsigned __int128>(streamlineCount) * static_cast<unsigned>(piece + 1) / static_cast<unsigned>(pieces));
  std::vector<std::uint64_t> starts;
  const std::uint64_t readable = std::min(last + 1, offsets.Rows);
  std::unique_ptr<TRXMemberStream> offsetStream = source.OpenMember(*offsets.Member, error);
  if (!offsetStream || !ReadIndices(*offsetStream, offsets, first, readable - first, starts, error))
  {
    return fail(error);
  }
  if (starts.size() == last - first)
  {
    starts.push_back(vertexCount); // older files: the last streamline runs to the end
  }
  if (first == 0 && starts.front() != 0)
  {
    return fail(Quote(offsets.Member->Path) + " does not start at 0");
  }
  for (std::size_t i = 0; i < starts.size(); ++i)
  {
    if (starts[i] > vertexCount || (i > 0 && starts[i] < starts[i - 1]))
    {
      return fail(Quote(offsets.Member->Path) + ": offset " + std::to_string(first + i) + " (" +
        std::to_string(starts[i]) + ") " +
        (starts[i] > vertexCount ? "is past NB_VERTICES " + std::to_string(vertexCount)
                                 : std::string("is smaller than the one before")));
    }
  }
  if (last == streamlineCount && starts.back() != vertexCount)
  {
    return fail(Quote(offsets.Member->Path) + " ends at " + std::to_string(starts.back()) +
      ", not at NB_VERTICES " + std::to_string(vertexCount));
  }
  const std::uint64_t firstVertex = starts.front();
  const std::uint64_t vertices = starts.back() - firstVertex;
  const std::uint64_t streamlines = last - first;
  // A vtkPolyData line needs two points (VTK refuses to build cells otherwise): shorter
  // streamlines are left out (with their dps rows and group memberships; a lone vertex stays
  // among the points, unused), and the cells are the others in file order.
  std::vector<vtkIdType> cellOf(streamlines, -1);
  vtkIdType lines = 0;
  for (std::uint64_t i = 0; i < streamlines; ++i)
  {
    cellOf[i] = starts[i + 1] - starts[i] >= 2 ? lines++ : -1;
  }
  if (static_cast<std::uint64_t>(lines) < streamlines)
  {
    vtkWarningMacro(<< name << ": " << streamlines - static_cast<std::uint64_t>(lines)
                    << " streamlines with fewer than two vertices are left out (the first is number "
                    << first + static_cast<std::uint64_t>(
                         std::find(cellOf.begin(), cellOf.end(), -1) - cellOf.begin())
                    << ")");
  }

  try
  {
    vtkNew<vtkPoints> points;
    points->SetDataType(positions.Name.Type == DType::Float64 ? VTK_DOUBLE : VTK_FLOAT);
    points->SetNumberOfPoints(static_cast<vtkIdType>(vertices));
    const double share = 0.8; // of the progress: reading positions is most of the work
    std::unique_ptr<TRXMemberStream> positionStream = source.OpenMember(*positions.Member, error);
    if (!positionStream ||
      !ReadRows(*positionStream, positions, firstVertex, vertices, points->GetData(), error,
          [&](double done) { this->UpdateProgress(share * done); }))
    {
      return fail(error);
    }
    // Points are float or double (above): checked in place, not a virtual call a coordinate.
    auto firstNonFinite = [](const auto* xyz, std::uint64_t count)
    {
      std::uint64_t v = 0;
      while (v < count && std::isfinite(xyz[3 * v]) && std::isfinite(xyz[3 * v + 1]) &&
        std::isfinite(xyz[3 * v + 2]))
      {
        ++v;
      }
      return v;
    };
    auto* floats = vtkFloatArray::FastDownCast(points->GetData());
    const std::uint64_t finite = floats
      ? firstNonFinite(floats->GetPointer(0), vertices)
      : firstNonFinite(vtkDoubleArray::FastDownCast(points->GetData())->GetPointer(0), vertices);
    if (finite < vertices)
    {
      return fail(Quote(positions.Member->Path) + ": vertex " + std::to_string(firstVertex + finite) +
        " is not finite");
    }
    // Cell c runs over connectivity [offset c, offset c + 1): the vertex ids of the kept
    // streamlines, one after the other (0, 1, 2, ... when none is left out). 32-bit ids while
    // they fit (below 2^31 vertices): 4 bytes a vertex less than VTK's default 64-bit storage.
    vtkNew<vtkCellArray> cells;
    auto fill = [&](auto* cellOffsets, auto* connectivity) {
      using Id = typename std::remove_pointer_t<decltype(connectivity)>::ValueType;
      cellOffsets->SetNumberOfValues(lines + 1);
      connectivity->SetNumberOfValues(static_cast<vtkIdType>(vertices));
      Id used = 0;
      cellOffsets->SetValue(0, 0);
      for (std::uint64_t i = 0; i < streamlines; ++i)
      {
        if (cellOf[i] >= 0)
        {
          for (std::uint64_t v = starts[i]; v < starts[i + 1]; ++v)
          {
            connectivity->SetValue(used++, static_cast<Id>(v - firstVertex));
          }
          cellOffsets->SetValue(cellOf[i] + 1, used);
        }
      }
      connectivity->SetNumberOfValues(used);
      cells->SetData(cellOffsets, connectivity);
    };
    if (vertices < (std::uint64_t(1) << 31))
    {
      vtkNew<vtkTypeInt32Array> cellOffsets, connectivity;
      fill(cellOffsets.Get(), connectivity.Get());
    }
    else
    {
      vtkNew<vtkTypeInt64Array> cellOffsets, connectivity;
      fill(cellOffsets.Get(), connectivity.Get());
    }

    vtkNew<vtkPolyData> result;
    result->SetPoints(points);
    result->SetLines(cells);
    auto readData = [&](const Array& data, std::uint64_t from, std::uint64_t rows,
                      vtkFieldData* into, const std::string& arrayName) {
      vtkSmartPointer<vtkDataArray> values;
      values.TakeReference(vtkDataArray::CreateDataArray(VTKType(data.Name.Type)));
      values->SetName(arrayName.c_str());
      values->SetNumberOfComponents(static_cast<int>(data.Name.Columns));
      values->SetNumberOfTuples(static_cast<vtkIdType>(rows));
      std::unique_ptr<TRXMemberStream> stream = source.OpenMember(*data.Member, error);
      if (!stream || !ReadRows(*stream, data, from, rows, values, error, [](double) {}))
      {
        return false;
      }
      into->AddArray(values);
      return true;
    };
    for (const Array& data : dpv)
    {
      if (!readData(data, firstVertex, vertices, result->GetPointData(), data.Name.Base))
      {
        return fail(error);
      }
    }
    for (const Array& data : dps)
    {
      if (!readData(data, first, streamlines, result->GetCellData(), data.Name.Base))
      {
        return fail(error);
      }
      if (lines < static_cast<vtkIdType>(streamlines))
      {
        vtkDataArray* values = result->GetCellData()->GetArray(data.Name.Base.c_str());
        for (std::uint64_t i = 0; i < streamlines; ++i)
        {
          if (cellOf[i] >= 0)
          {
            values->SetTuple(cellOf[i], static_cast<vtkIdType>(i), values);
          }
        }
        values->SetNumberOfTuples(lines);
      }
    }
    std::vector<std::uint64_t> members;
    for (const Array& group : groups)
    {
      vtkNew<vtkUnsignedCharArray> in;
      in->SetName(("group:" + group.Name.Base).c_str());
      in->SetNumberOfValues(lines);
      in->FillValue(0);
      constexpr std::uint64_t kRows = kBlockBytes / 8;
      std::unique_ptr<TRXMemberStream> stream = source.OpenMember(*group.Member, error);
      if (!stream)
      {
        return fail(error);
      }
      for (std::uint64_t done = 0; done < group.Rows; done += kRows)
      {
        if (!ReadIndices(*stream, group, done, std::min(kRows, group.Rows - done), members, error))
        {
          return fail(error);
        }
        for (std::uint64_t s : members)
        {
          if (s >= streamlineCount)
          {
            return fail(Quote(group.Member->Path) + " names streamline " + std::to_string(s) +
              " of NB_STREAMLINES " + std::to_string(streamlineCount));
          }
          if (s >= first && s < last && cellOf[s - first] >= 0)
          {
            in->SetValue(cellOf[s - first], 1);
          }
        }
      }
      result->GetCellData()->AddArray(in);
    }
    for (const Array& data : dpg)
    {
      if (!readData(data, 0, 1, result->GetFieldData(),
            "dpg:" + data.Name.Folder.substr(4) + ":" + data.Name.Base))
      {
        return fail(error);
      }
    }
    if (affine->GetNumberOfTuples() == 16)
    {
      result->GetFieldData()->AddArray(affine);
    }
    if (dimensions->GetNumberOfTuples() == 3)
    {
      result->GetFieldData()->AddArray(dimensions);
    }
    output->ShallowCopy(result);
  }
  catch (const std::bad_alloc&)
  {
    return fail("not enough memory for " + std::to_string(vertices) + " vertices and " +
      std::to_string(lines) + " streamlines");
  }
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSightlineTRXReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ReadFromInputString: " << this->ReadFromInputString << "\n";
}
