// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineReaderInput.h"

#include <cstdio>
#include <fstream>
#include <iterator>

namespace sightline_io
{
bool LoadInput(const char* fileName, bool fromString, const std::string& inputString,
  std::string& bytes, std::string& error)
{
  bytes.clear();
  if (fromString)
  {
    bytes = inputString;
    return true;
  }
  if (!fileName || !*fileName)
  {
    error = "No FileName was set.";
    return false;
  }
  std::ifstream file(fileName, std::ios::binary);
  if (!file)
  {
    error = "Cannot open " + InputName(fileName, false) + " (missing or unreadable).";
    return false;
  }
  bytes.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  if (file.bad())
  {
    error = "Cannot read " + InputName(fileName, false) + ".";
    return false;
  }
  return true;
}

namespace
{
// Length of the well-formed UTF-8 sequence of 2 to 4 bytes at text[i] (RFC 3629: no overlong
// forms, no surrogates, nothing beyond U+10FFFF), or 0.
std::size_t Utf8Sequence(const std::string& text, std::size_t i)
{
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF; // allowed range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF)
  {
    length = 2;
  }
  else if (lead >= 0xE0 && lead <= 0xEF)
  {
    length = 3;
    low = lead == 0xE0 ? 0xA0 : 0x80;
    high = lead == 0xED ? 0x9F : 0xBF;
  }
  else if (lead >= 0xF0 && lead <= 0xF4)
  {
    length = 4;
    low = lead == 0xF0 ? 0x90 : 0x80;
    high = lead == 0xF4 ? 0x8F : 0xBF;
  }
  if (length == 0 || i + length > text.size() || byte(i + 1) < low || byte(i + 1) > high)
  {
    return 0;
  }
  for (std::size_t k = 2; k < length; ++k)
  {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF)
    {
      return 0;
    }
  }
  return length;
}
} // namespace

std::string Quote(const std::string& text, std::size_t maxBytes)
{
  std::string quoted;
  std::size_t i = 0;
  while (i < text.size() && i < maxBytes)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7F)
    {
      quoted.push_back(static_cast<char>(c));
      ++i;
      continue;
    }
    const std::size_t length = c >= 0x80 ? Utf8Sequence(text, i) : 0;
    if (length > 0)
    {
      quoted.append(text, i, length);
      i += length;
      continue;
    }
    char escape[5];
    std::snprintf(escape, sizeof(escape), "\\x%02X", c);
    quoted += escape;
    ++i;
  }
  if (i < text.size())
  {
    quoted += "...";
  }
  return quoted;
}

std::string InputName(const char* fileName, bool fromString)
{
  if (fromString)
  {
    return "the input string";
  }
  return "'" + Quote(fileName ? fileName : "", 4096) + "'";
}
} // namespace sightline_io
