// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineTRXFormat.h"

#include "SightlineReaderInput.h"
#include "sightline/math/Half.h"

#include "vtkDataArray.h"
#include "vtkType.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace sightline_io
{
namespace trx
{
namespace
{
struct DTypeInfo
{
  DType Type;
  const char* Name;
  std::size_t Size;
  int VTK;
};
const DTypeInfo kTypes[] = {
  { DType::Int8, "int8", 1, VTK_SIGNED_CHAR },
  { DType::Int16, "int16", 2, VTK_SHORT },
  { DType::Int32, "int32", 4, VTK_INT },
  { DType::Int64, "int64", 8, VTK_LONG_LONG },
  { DType::UInt8, "uint8", 1, VTK_UNSIGNED_CHAR },
  { DType::UInt16, "uint16", 2, VTK_UNSIGNED_SHORT },
  { DType::UInt32, "uint32", 4, VTK_UNSIGNED_INT },
  { DType::UInt64, "uint64", 8, VTK_UNSIGNED_LONG_LONG },
  { DType::Float16, "float16", 2, VTK_FLOAT },
  { DType::Float32, "float32", 4, VTK_FLOAT },
  { DType::Float64, "float64", 8, VTK_DOUBLE },
  { DType::Bit, "bit", 1, VTK_UNSIGNED_CHAR },
};
const DTypeInfo& Info(DType type)
{
  return kTypes[static_cast<int>(type)];
}

template <typename T>
void CopyValues(const char* bytes, std::size_t values, vtkDataArray* array, std::size_t first)
{
  // TRX is little endian, as are the platforms Sightline builds on (x86_64, arm64).
  static_assert(sizeof(T) > 0, "");
  std::memcpy(static_cast<T*>(array->GetVoidPointer(0)) + first, bytes, values * sizeof(T));
}
} // namespace

bool ParseDType(const std::string& text, DType& type)
{
  for (const DTypeInfo& info : kTypes)
  {
    if (text == info.Name)
    {
      type = info.Type;
      return true;
    }
  }
  if (text == "bool")
  {
    type = DType::Bit;
    return true;
  }
  return false;
}

const char* DTypeName(DType type)
{
  return Info(type).Name;
}

std::size_t DTypeSize(DType type)
{
  return Info(type).Size;
}

bool IsInteger(DType type)
{
  return type != DType::Float16 && type != DType::Float32 && type != DType::Float64;
}

int VTKType(DType type)
{
  return Info(type).VTK;
}

bool DTypeOfVTK(int vtkType, DType& type)
{
  switch (vtkType)
  {
    case VTK_CHAR:
    case VTK_SIGNED_CHAR:
      type = DType::Int8;
      return true;
    case VTK_SHORT:
      type = DType::Int16;
      return true;
    case VTK_INT:
      type = DType::Int32;
      return true;
    case VTK_LONG:
      type = sizeof(long) == 8 ? DType::Int64 : DType::Int32;
      return true;
    case VTK_LONG_LONG:
    case VTK_ID_TYPE:
      type = DType::Int64;
      return true;
    case VTK_UNSIGNED_CHAR:
      type = DType::UInt8;
      return true;
    case VTK_UNSIGNED_SHORT:
      type = DType::UInt16;
      return true;
    case VTK_UNSIGNED_INT:
      type = DType::UInt32;
      return true;
    case VTK_UNSIGNED_LONG:
      type = sizeof(unsigned long) == 8 ? DType::UInt64 : DType::UInt32;
      return true;
    case VTK_UNSIGNED_LONG_LONG:
      type = DType::UInt64;
      return true;
    case VTK_FLOAT:
      type = DType::Float32;
      return true;
    case VTK_DOUBLE:
      type = DType::Float64;
      return true;
    default:
      return false;
  }
}

bool ParseMemberName(const std::string& path, MemberName& name, std::string& error)
{
  const std::size_t slash = path.rfind('/');
  name.Folder = slash == std::string::npos ? std::string() : path.substr(0, slash);
  const std::string file = slash == std::string::npos ? path : path.substr(slash + 1);
  std::vector<std::string> parts;
  for (std::size_t from = 0;;)
  {
    const std::size_t dot = file.find('.', from);
    parts.push_back(file.substr(from, dot == std::string::npos ? dot : dot - from));
    if (dot == std::string::npos)
    {
      break;
    }
    from = dot + 1;
  }
  if (parts.size() < 2 || parts.size() > 3 || parts[0].empty())
  {
    error = "TRX member " + Quote(path) + " is not named NAME[.COLUMNS].DTYPE";
    return false;
  }
  name.Base = parts[0];
  if (!ParseDType(parts.back(), name.Type))
  {
    error = "TRX member " + Quote(path) + " has the unknown dtype " + Quote(parts.back());
    return false;
  }
  name.Columns = 1;
  if (parts.size() == 3)
  {
    const std::string& columns = parts[1];
    if (columns.empty() || columns.size() > 6 ||
      columns.find_first_not_of("0123456789") != std::string::npos || std::stoul(columns) == 0)
    {
      error = "TRX member " + Quote(path) + " has a bad column count " + Quote(columns);
      return false;
    }
    name.Columns = std::stoul(columns);
  }
  return true;
}

void ConvertRows(
  const char* bytes, DType type, std::size_t values, vtkDataArray* array, std::size_t firstValue)
{
  switch (type)
  {
    case DType::Int8:
      CopyValues<std::int8_t>(bytes, values, array, firstValue);
      break;
    case DType::Int16:
      CopyValues<std::int16_t>(bytes, values, array, firstValue);
      break;
    case DType::Int32:
      CopyValues<std::int32_t>(bytes, values, array, firstValue);
      break;
    case DType::Int64:
      CopyValues<std::int64_t>(bytes, values, array, firstValue);
      break;
    case DType::UInt8:
    case DType::Bit:
      CopyValues<std::uint8_t>(bytes, values, array, firstValue);
      break;
    case DType::UInt16:
      CopyValues<std::uint16_t>(bytes, values, array, firstValue);
      break;
    case DType::UInt32:
      CopyValues<std::uint32_t>(bytes, values, array, firstValue);
      break;
    case DType::UInt64:
      CopyValues<std::uint64_t>(bytes, values, array, firstValue);
      break;
    case DType::Float32:
      CopyValues<float>(bytes, values, array, firstValue);
      break;
    case DType::Float64:
      CopyValues<double>(bytes, values, array, firstValue);
      break;
    case DType::Float16:
      sightline::halvesToFloats(bytes, values, static_cast<float*>(array->GetVoidPointer(0)) + firstValue);
      break;
  }
}
} // namespace trx
} // namespace sightline_io
