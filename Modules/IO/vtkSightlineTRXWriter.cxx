// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSightlineTRXWriter.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include "SightlineReaderInput.h"
#include "SightlineTRXArchive.h"
#include "SightlineTRXFormat.h"
#include "sightline/math/Half.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSightlineTRXWriter);

namespace
{
using namespace sightline_io;
using namespace sightline_io::trx;

// A member name TRX can hold: no '.', no '/', not empty.
std::string MemberBase(const char* name)
{
  std::string base = name ? name : "";
  for (char& c : base)
  {
    if (c == '.' || c == '/' || c == '\\')
    {
      c = '_';
    }
  }
  return base.empty() ? std::string("unnamed") : base;
}

std::string MemberFile(const std::string& base, std::uint64_t columns, DType type)
{
  return base + (columns > 1 ? "." + std::to_string(columns) : std::string()) + "." + DTypeName(type);
}

std::string Number(double value)
{
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}
} // namespace

vtkSightlineTRXWriter::vtkSightlineTRXWriter() = default;

vtkSightlineTRXWriter::~vtkSightlineTRXWriter()
{
  this->SetFileName(nullptr);
}

vtkPolyData* vtkSightlineTRXWriter::GetInput()
{
  return vtkPolyData::SafeDownCast(this->Superclass::GetInput());
}

int vtkSightlineTRXWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  return 1;
}

void vtkSightlineTRXWriter::WriteData()
{
  vtkPolyData* input = this->GetInput();
  if (!this->FileName || !*this->FileName)
  {
    vtkErrorMacro(<< "no FileName set");
    return;
  }
  const std::string target = Quote(this->FileName);
  if (!input)
  {
    vtkErrorMacro(<< target << ": the input is not poly data");
    return;
  }
  if (input->GetNumberOfPolys() + input->GetNumberOfStrips() + input->GetNumberOfVerts() > 0)
  {
    vtkWarningMacro(<< target << ": only line cells are tractogram streamlines; "
                    << input->GetNumberOfVerts() << " vertex, " << input->GetNumberOfPolys()
                    << " polygon and " << input->GetNumberOfStrips()
                    << " strip cells are left out");
  }
  vtkCellArray* lines = input->GetLines();
  const vtkIdType streamlines = lines ? lines->GetNumberOfCells() : 0;
  const vtkIdType cellBase = input->GetNumberOfVerts(); // cell ids: verts, then lines
  std::uint64_t vertices = lines ? static_cast<std::uint64_t>(lines->GetNumberOfConnectivityIds()) : 0;
  vtkPoints* points = input->GetPoints();
  if (vertices > 0 && !points)
  {
    vtkErrorMacro(<< target << ": the input has lines but no points");
    return;
  }
  DType positionType = DType::Float32;
  switch (this->PositionsType)
  {
    case POSITIONS_FLOAT16:
      positionType = DType::Float16;
      break;
    case POSITIONS_FLOAT64:
      positionType = DType::Float64;
      break;
    case POSITIONS_AS_INPUT:
      positionType = points && points->GetDataType() == VTK_DOUBLE ? DType::Float64 : DType::Float32;
      break;
    default:
      break;
  }

  std::string error;
  std::unique_ptr<TRXArchiveWriter> sink =
    TRXArchiveWriter::Create(this->FileName, this->WriteToDirectory, this->Compress, error);
  if (!sink)
  {
    vtkErrorMacro(<< target << ": " << error);
    return;
  }
  auto failed = [&]() { vtkErrorMacro(<< target << ": " << error); };

  // Which arrays go where.
  struct Output
  {
    vtkDataArray* Array;
    std::string Path;
    DType Type;
  };
  std::vector<Output> perVertex, perStreamline, perGroup;
  std::vector<std::pair<std::string, vtkDataArray*>> groups;
  auto choose = [&](vtkFieldData* data, const char* folder, std::vector<Output>& into) {
    for (int a = 0; data && a < data->GetNumberOfArrays(); ++a)
    {
      vtkDataArray* array = data->GetArray(a);
      const char* arrayName = data->GetArrayName(a);
      DType type;
      if (!array || !DTypeOfVTK(array->GetDataType(), type))
      {
        vtkWarningMacro(<< target << ": skipped the array " << Quote(arrayName ? arrayName : "")
                        << " (TRX holds numbers only)");
        continue;
      }
      const std::string name = arrayName ? arrayName : "";
      if (folder == std::string("dps") && name.compare(0, 6, "group:") == 0)
      {
        groups.emplace_back(MemberBase(name.c_str() + 6), array);
        continue;
      }
      const std::string base = MemberBase(arrayName);
      if (base != name)
      {
        vtkWarningMacro(<< target << ": the array " << Quote(name) << " is written as "
                        << Quote(base) << " (TRX names hold no '.' or '/')");
      }
      into.push_back({ array,
        std::string(folder) + "/" +
          MemberFile(base, static_cast<std::uint64_t>(array->GetNumberOfComponents()), type),
        type });
    }
  };
  choose(input->GetPointData(), "dpv", perVertex);
  choose(input->GetCellData(), "dps", perStreamline);
  vtkFieldData* field = input->GetFieldData();
  vtkDataArray* affine = field ? field->GetArray("VOXEL_TO_RASMM") : nullptr;
  vtkDataArray* dimensions = field ? field->GetArray("DIMENSIONS") : nullptr;
  for (int a = 0; field && a < field->GetNumberOfArrays(); ++a)
  {
    const char* arrayName = field->GetArrayName(a);
    const std::string name = arrayName ? arrayName : "";
    const std::size_t split = name.find(':', 4);
    DType type;
    if (name.compare(0, 4, "dpg:") != 0 || split == std::string::npos || !field->GetArray(a) ||
      !DTypeOfVTK(field->GetArray(a)->GetDataType(), type))
    {
      continue;
    }
    const std::string group = MemberBase(name.substr(4, split - 4).c_str());
    bool known = false;
    for (const auto& g : groups)
    {
      known = known || g.first == group;
    }
    if (!known)
    {
      vtkWarningMacro(<< target << ": skipped " << Quote(name) << ", data for a group the input has no array group:" << Quote(group) << " for");
      continue;
    }
    vtkDataArray* array = field->GetArray(a);
    const std::uint64_t columns =
      static_cast<std::uint64_t>(array->GetNumberOfTuples()) * static_cast<std::uint64_t>(array->GetNumberOfComponents());
    perGroup.push_back({ array, "dpg/" + group + "/" + MemberFile(MemberBase(name.c_str() + split + 1), columns, type), type });
  }

  // header.json
  {
    std::string header = "{\"DIMENSIONS\": [";
    for (int k = 0; k < 3; ++k)
    {
      header += (k ? ", " : "") +
        std::to_string(dimensions && dimensions->GetNumberOfValues() == 3
            ? static_cast<long long>(dimensions->GetComponent(k, 0))
            : 1LL);
    }
    header += "], \"NB_STREAMLINES\": " + std::to_string(streamlines) +
      ", \"NB_VERTICES\": " + std::to_string(vertices) + ", \"VOXEL_TO_RASMM\": [";
    for (int r = 0; r < 4; ++r)
    {
      header += r ? ", [" : "[";
      for (int c = 0; c < 4; ++c)
      {
        const double value = affine && affine->GetNumberOfValues() == 16
          ? affine->GetComponent((4 * r + c) / affine->GetNumberOfComponents(),
              (4 * r + c) % affine->GetNumberOfComponents())
          : (r == c ? 1.0 : 0.0);
        header += (c ? ", " : "") + Number(value);
      }
      header += "]";
    }
    header += "]}";
    if (!sink->Begin("header.json", header.size(), error) ||
      !sink->Write(header.data(), header.size(), error) || !sink->End(error))
    {
      return failed();
    }
  }
  if (streamlines == 0 || vertices == 0)
  {
    // trx-python's empty tractogram: a header and nothing else.
    if (!sink->Close(error))
    {
      failed();
    }
    return;
  }

  // Walks every streamline's point ids in order, calling `visit(pointId)`.
  auto eachVertex = [&](auto&& visit) {
    const vtkIdType* ids = nullptr;
    vtkIdType count = 0;
    for (lines->InitTraversal(); lines->GetNextCell(count, ids);)
    {
      for (vtkIdType k = 0; k < count; ++k)
      {
        if (!visit(ids[k]))
        {
          return false;
        }
      }
    }
    return true;
  };
  // positions
  {
    const std::string path = std::string("positions.3.") + DTypeName(positionType);
    if (!sink->Begin(path, vertices * 3 * DTypeSize(positionType), error))
    {
      return failed();
    }
    TRXBlockWriter out(*sink, error);
    std::uint64_t done = 0;
    bool finite = true;
    const bool ok = eachVertex([&](vtkIdType id) {
      double p[3];
      points->GetPoint(id, p);
      if (++done % (1 << 20) == 0)
      {
        this->UpdateProgress(0.8 * static_cast<double>(done) / static_cast<double>(vertices));
      }
      if (positionType == DType::Float64)
      {
        return out.Add(p, sizeof p);
      }
      const float f[3] = { static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]) };
      if (positionType == DType::Float32)
      {
        return out.Add(f, sizeof f);
      }
      const std::uint16_t h[3] = { sightline::floatToHalf(f[0]), sightline::floatToHalf(f[1]), sightline::floatToHalf(f[2]) };
      for (int c = 0; c < 3; ++c)
      {
        if (std::isfinite(p[c]) && !std::isfinite(sightline::halfToFloat(h[c])))
        {
          finite = false;
          error = "point " + std::to_string(id) + " is beyond float16's range (65504): write float32 positions";
          return false;
        }
      }
      return out.Add(h, sizeof h);
    });
    if (!ok || !finite || !out.Flush() || !sink->End(error))
    {
      return failed();
    }
  }
  // offsets: one per streamline and NB_VERTICES
  {
    if (!sink->Begin("offsets.uint64", 8 * (static_cast<std::uint64_t>(streamlines) + 1), error))
    {
      return failed();
    }
    TRXBlockWriter out(*sink, error);
    std::uint64_t at = 0;
    const vtkIdType* ids = nullptr;
    vtkIdType count = 0;
    bool ok = true;
    for (lines->InitTraversal(); ok && lines->GetNextCell(count, ids);)
    {
      ok = out.Add(&at, 8);
      at += static_cast<std::uint64_t>(count);
    }
    if (!ok || !out.Add(&at, 8) || !out.Flush() || !sink->End(error))
    {
      return failed();
    }
  }
  // Raw tuples of an array, converted to nothing: TRX keeps the array's own type.
  auto writeTuples = [&](const Output& o, std::uint64_t rows, auto&& tupleOf) {
    const std::size_t tupleBytes =
      static_cast<std::size_t>(o.Array->GetNumberOfComponents() * o.Array->GetDataTypeSize());
    if (!sink->Begin(o.Path, rows * tupleBytes, error))
    {
      return false;
    }
    const char* base = static_cast<const char*>(o.Array->GetVoidPointer(0));
    TRXBlockWriter out(*sink, error);
    for (std::uint64_t r = 0; r < rows; ++r)
    {
      if (!out.Add(base + static_cast<std::size_t>(tupleOf(r)) * tupleBytes, tupleBytes))
      {
        return false;
      }
    }
    return out.Flush() && sink->End(error);
  };
  for (const Output& o : perVertex)
  {
    if (o.Array->GetNumberOfTuples() < input->GetNumberOfPoints())
    {
      vtkWarningMacro(<< target << ": skipped " << Quote(o.Path) << ", shorter than the points");
      continue;
    }
    std::vector<vtkIdType> order; // the point of each vertex, in file order
    order.reserve(static_cast<std::size_t>(vertices));
    eachVertex([&](vtkIdType id) {
      order.push_back(id);
      return true;
    });
    if (!writeTuples(o, vertices, [&](std::uint64_t r) { return order[static_cast<std::size_t>(r)]; }))
    {
      return failed();
    }
  }
  for (const Output& o : perStreamline)
  {
    if (o.Array->GetNumberOfTuples() < cellBase + streamlines)
    {
      vtkWarningMacro(<< target << ": skipped " << Quote(o.Path) << ", shorter than the cells");
      continue;
    }
    if (!writeTuples(o, static_cast<std::uint64_t>(streamlines),
          [&](std::uint64_t r) { return cellBase + static_cast<vtkIdType>(r); }))
    {
      return failed();
    }
  }
  for (const auto& group : groups)
  {
    vtkDataArray* in = group.second;
    const bool wide = static_cast<std::uint64_t>(streamlines) > 0xFFFFFFFFu;
    std::vector<std::uint64_t> members;
    for (vtkIdType s = 0; s < streamlines && cellBase + s < in->GetNumberOfTuples(); ++s)
    {
      if (in->GetComponent(cellBase + s, 0) != 0)
      {
        members.push_back(static_cast<std::uint64_t>(s));
      }
    }
    const std::string path = "groups/" + group.first + (wide ? ".uint64" : ".uint32");
    if (!sink->Begin(path, members.size() * (wide ? 8 : 4), error))
    {
      return failed();
    }
    TRXBlockWriter out(*sink, error);
    for (std::uint64_t m : members)
    {
      const std::uint32_t narrow = static_cast<std::uint32_t>(m);
      if (!(wide ? out.Add(&m, 8) : out.Add(&narrow, 4)))
      {
        return failed();
      }
    }
    if (!out.Flush() || !sink->End(error))
    {
      return failed();
    }
  }
  for (const Output& o : perGroup)
  {
    const std::size_t bytes = static_cast<std::size_t>(o.Array->GetNumberOfValues() * o.Array->GetDataTypeSize());
    if (!sink->Begin(o.Path, bytes, error) ||
      !sink->Write(static_cast<const char*>(o.Array->GetVoidPointer(0)), bytes, error) ||
      !sink->End(error))
    {
      return failed();
    }
  }
  if (!sink->Close(error))
  {
    return failed();
  }
  this->UpdateProgress(1.0);
}

void vtkSightlineTRXWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "PositionsType: " << this->PositionsType << "\n";
  os << indent << "Compress: " << this->Compress << "\n";
  os << indent << "WriteToDirectory: " << this->WriteToDirectory << "\n";
}
