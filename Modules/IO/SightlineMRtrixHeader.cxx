// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineMRtrixHeader.h"

#include "SightlineReaderInput.h"

#include "vtkByteSwap.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <sstream>

namespace sightline_io
{
namespace
{
// A header is a few hundred bytes; the cap stops a binary file without newlines from being
// read whole as "one line".
constexpr std::size_t MaxHeaderBytes = 16u << 20;

std::string Lower(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(),
    [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool HostIsLittleEndian()
{
#ifdef VTK_WORDS_BIGENDIAN
  return false;
#else
  return true;
#endif
}
} // namespace

std::vector<std::string> MRtrixHeader::Values(const std::string& key) const
{
  std::vector<std::string> values;
  for (const auto& entry : this->Entries)
  {
    if (entry.first == key)
    {
      values.push_back(entry.second);
    }
  }
  return values;
}

std::string MRtrixHeader::Value(const std::string& key) const
{
  const std::vector<std::string> values = this->Values(key);
  return values.empty() ? std::string() : values.back();
}

bool ReadMRtrixHeader(const std::function<int()>& next, const char* magic, const char* what,
  MRtrixHeader& header, std::string& error)
{
  header = MRtrixHeader();
  std::size_t consumed = 0;
  // One '\n'-terminated line (without it); false at the end of the input or the cap.
  auto readLine = [&](std::string& line) {
    line.clear();
    for (;;)
    {
      if (consumed == MaxHeaderBytes)
      {
        return false;
      }
      const int c = next();
      if (c < 0)
      {
        return !line.empty();
      }
      ++consumed;
      if (c == '\n')
      {
        return true;
      }
      line.push_back(static_cast<char>(c));
    }
  };
  std::string line;
  if (!readLine(line) || Trim(line) != magic)
  {
    error = std::string("this is not an ") + what + ": its first line is not \"" + magic + "\".";
    return false;
  }
  while (readLine(line))
  {
    if (Trim(line) == "END")
    {
      header.Size = consumed;
      return true;
    }
    const std::string content = Trim(line.substr(0, line.find('#')));
    if (content.empty())
    {
      continue;
    }
    const auto colon = content.find(':');
    if (colon == std::string::npos)
    {
      error = "malformed header line \"" + Quote(line) + "\" (no ':').";
      return false;
    }
    header.Entries.emplace_back(
      Lower(Trim(content.substr(0, colon))), Trim(content.substr(colon + 1)));
  }
  error = consumed == MaxHeaderBytes ? "no END line in the first 16 MiB of the header."
                                     : "the header has no END line (truncated file?).";
  return false;
}

std::string Trim(const std::string& text)
{
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos)
  {
    return std::string();
  }
  const auto last = text.find_last_not_of(" \t\r");
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
  errno = 0;
  value = std::strtoll(text.c_str(), &end, 10);
  return end && *end == '\0' && errno != ERANGE;
}

bool ParseDataFileEntry(const std::string& value, long long& offset)
{
  std::istringstream entry(value);
  std::string dataFile, offsetText, extra;
  return (entry >> dataFile >> offsetText) && dataFile == "." && !(entry >> extra) &&
    ParseInteger(offsetText, offset) && offset >= 0;
}

bool ParseDataType(const std::string& name, MRtrixDataType& type)
{
  static const std::array<std::pair<const char*, std::pair<MRtrixType, int>>, 8> types = { {
    { "int8", { MRtrixType::Int8, 1 } },
    { "uint8", { MRtrixType::UInt8, 1 } },
    { "int16", { MRtrixType::Int16, 2 } },
    { "uint16", { MRtrixType::UInt16, 2 } },
    { "int32", { MRtrixType::Int32, 4 } },
    { "uint32", { MRtrixType::UInt32, 4 } },
    { "float32", { MRtrixType::Float32, 4 } },
    { "float64", { MRtrixType::Float64, 8 } },
  } };
  const std::string lower = Lower(name);
  type.LittleEndian = HostIsLittleEndian();
  std::string base = lower;
  if (lower.size() > 2 && (lower.compare(lower.size() - 2, 2, "le") == 0 ||
                            lower.compare(lower.size() - 2, 2, "be") == 0))
  {
    type.LittleEndian = lower.compare(lower.size() - 2, 2, "le") == 0;
    base = lower.substr(0, lower.size() - 2);
  }
  for (const auto& entry : types)
  {
    if (base == entry.first)
    {
      type.Type = entry.second.first;
      type.Bytes = entry.second.second;
      // Byte order only matters for multi-byte types ("UInt8LE" is not a thing).
      return type.Bytes > 1 || base == lower;
    }
  }
  return false;
}

void ToHostByteOrder(void* data, std::size_t count, const MRtrixDataType& type)
{
  switch (type.Bytes)
  {
    case 2:
      type.LittleEndian ? vtkByteSwap::Swap2LERange(data, count)
                        : vtkByteSwap::Swap2BERange(data, count);
      break;
    case 4:
      type.LittleEndian ? vtkByteSwap::Swap4LERange(data, count)
                        : vtkByteSwap::Swap4BERange(data, count);
      break;
    case 8:
      type.LittleEndian ? vtkByteSwap::Swap8LERange(data, count)
                        : vtkByteSwap::Swap8BERange(data, count);
      break;
    default:
      break;
  }
}
} // namespace sightline_io
