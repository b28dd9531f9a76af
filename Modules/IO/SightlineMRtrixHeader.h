// SPDX-License-Identifier: BSD-3-Clause
// Private helper of vtkSightlineMIFReader and vtkSightlineTCKReader (not wrapped, not
// installed): the MRtrix3 text header both formats share ("mrtrix image" / "mrtrix tracks",
// "key: value" lines, "END"), its number lists, the `file: . OFFSET` entry and the datatype
// names with their byte order.
#ifndef SightlineMRtrixHeader_h
#define SightlineMRtrixHeader_h

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace sightline_io
{
struct MRtrixHeader
{
  /// "key: value" lines in file order, keys in lower case, comments ("# ...") removed.
  std::vector<std::pair<std::string, std::string>> Entries;
  /// Bytes from the start of the file to the end of the END line: data cannot start before.
  std::size_t Size = 0;

  /// Every value of `key`, in order (e.g. the three `transform` lines).
  std::vector<std::string> Values(const std::string& key) const;
  /// The last value of `key`, or "" when there is none.
  std::string Value(const std::string& key) const;
};

/// Reads the header through `next` (the next byte of the file, -1 at its end): the first line
/// must be `magic`; stops after END. At most 16 MiB are read. False with `error` (valid UTF-8,
/// without the file's name) for a wrong first line, a line without ':', or no END.
/// `what` names the format in that message ("MRtrix image").
bool ReadMRtrixHeader(const std::function<int()>& next, const char* magic, const char* what,
  MRtrixHeader& header, std::string& error);

std::string Trim(const std::string& text);
/// Comma-separated items, each trimmed.
std::vector<std::string> SplitList(const std::string& text);
/// The whole of `text` as a number; false for "", "1.5x", ...
bool ParseDouble(const std::string& text, double& value);
/// The whole of `text` as a decimal integer that fits a long long.
bool ParseInteger(const std::string& text, long long& value);

/// The `file` entry's offset when it is ". OFFSET" (data in this file), else false.
bool ParseDataFileEntry(const std::string& value, long long& offset);

/// The element types MRtrix3 names (Bit, complex and 64-bit integers excluded).
enum class MRtrixType
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

struct MRtrixDataType
{
  MRtrixType Type = MRtrixType::Float32;
  int Bytes = 4;
  /// The file's byte order; a name without LE/BE suffix means this machine's, as in MRtrix3.
  bool LittleEndian = true;
};

/// Parses "Float32LE", "UInt8", "Int16BE", ... (case-insensitive).
bool ParseDataType(const std::string& name, MRtrixDataType& type);

/// Brings `count` values of `type` in `data` from the file's byte order to the host's.
void ToHostByteOrder(void* data, std::size_t count, const MRtrixDataType& type);
} // namespace sightline_io

#endif
