// SPDX-License-Identifier: BSD-3-Clause
// Private helpers of Sightline::IO (not wrapped, not installed): what the TRX tractogram format
// (tee-ar-ex/trx-spec, as trx-python reads and writes it) names and stores, shared by
// vtkSightlineTRXReader and vtkSightlineTRXWriter. A member is `FOLDER/NAME[.COLUMNS].DTYPE`,
// little endian, one row per vertex (dpv, positions), per streamline (dps, offsets), per group
// member (groups) or one row (dpg/GROUP).
#ifndef SightlineTRXFormat_h
#define SightlineTRXFormat_h

#include <cstddef>
#include <cstdint>
#include <string>

class vtkDataArray;

namespace sightline_io
{
namespace trx
{
enum class DType
{
  Int8,
  Int16,
  Int32,
  Int64,
  UInt8,
  UInt16,
  UInt32,
  UInt64,
  Float16,
  Float32,
  Float64,
  Bit, ///< NumPy's bool, one byte per value (trx-python names it "bit")
};

/// NumPy's name ("float16", "uint32", ... "bit"; "bool" is read as "bit").
bool ParseDType(const std::string& text, DType& type);
const char* DTypeName(DType type);
std::size_t DTypeSize(DType type);
bool IsInteger(DType type);
/// The VTK array type values of `type` become: float16 widens to VTK_FLOAT, bit is unsigned char.
int VTKType(DType type);
/// The TRX dtype a VTK array type is written as; false for types TRX cannot hold (strings).
bool DTypeOfVTK(int vtkType, DType& type);

/// A member's path split into folder ("", "dpv", "dps", "groups" or "dpg/GROUP"), base name,
/// columns and dtype. False with `error` set when the name has no known dtype or a bad column count.
struct MemberName
{
  std::string Folder;
  std::string Base;
  std::uint64_t Columns = 1;
  DType Type = DType::Float32;
};
bool ParseMemberName(const std::string& path, MemberName& name, std::string& error);

/// Appends `count` rows of `bytes` (little-endian values of `type`) to `array` (of VTKType(type)
/// and as many components as the rows have), from tuple `firstTuple` on.
void ConvertRows(const char* bytes, DType type, std::size_t values, vtkDataArray* array,
  std::size_t firstValue);
} // namespace trx
} // namespace sightline_io

#endif
