// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineReaderInput.h"

#include "vtkInformation.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
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

bool InputFile::Open(const char* fileName, bool fromString, const std::string& inputString,
  std::string& error)
{
  this->String = nullptr;
  this->BlockSize = 0;
  if (fromString)
  {
    this->String = &inputString;
    this->Length = static_cast<long long>(inputString.size());
    return true;
  }
  if (!fileName || !*fileName)
  {
    error = "No FileName was set.";
    return false;
  }
  this->File.close();
  this->File.clear();
  this->File.open(fileName, std::ios::binary);
  if (!this->File)
  {
    error = "Cannot open " + InputName(fileName, false) + " (missing or unreadable).";
    return false;
  }
  this->File.seekg(0, std::ios::end);
  const std::streamoff end = this->File.tellg();
  if (!this->File || end < 0)
  {
    error = "Cannot read " + InputName(fileName, false) + ".";
    return false;
  }
  this->Length = static_cast<long long>(end);
  // Something that opens but cannot be read (a directory) is named as such here, not later as
  // a file without a valid header.
  char first;
  this->File.seekg(0);
  if (this->Length > 0 && !this->File.read(&first, 1))
  {
    error = "Cannot read " + InputName(fileName, false) + ".";
    return false;
  }
  return true;
}

std::size_t InputFile::ReadAt(long long offset, char* data, std::size_t size)
{
  if (offset < 0 || offset >= this->Length || size == 0)
  {
    return 0;
  }
  size = static_cast<std::size_t>(
    std::min<long long>(static_cast<long long>(size), this->Length - offset));
  if (this->String)
  {
    std::memcpy(data, this->String->data() + offset, size);
    return size;
  }
  constexpr std::size_t blockBytes = 1u << 16;
  std::size_t done = 0;
  while (done < size)
  {
    const long long at = offset + static_cast<long long>(done);
    if (at >= this->BlockStart && at < this->BlockStart + static_cast<long long>(this->BlockSize))
    {
      const std::size_t from = static_cast<std::size_t>(at - this->BlockStart);
      const std::size_t n = std::min(size - done, this->BlockSize - from);
      std::memcpy(data + done, this->Block.data() + from, n);
      done += n;
      continue;
    }
    this->File.clear();
    this->File.seekg(at);
    if (size - done >= blockBytes)
    {
      // Large reads go straight to the caller's buffer.
      this->File.read(data + done, static_cast<std::streamsize>(size - done));
      const std::size_t n = static_cast<std::size_t>(this->File.gcount());
      done += n;
      break;
    }
    this->Block.resize(blockBytes);
    this->File.read(this->Block.data(), static_cast<std::streamsize>(blockBytes));
    this->BlockStart = at;
    this->BlockSize = static_cast<std::size_t>(this->File.gcount());
    if (this->BlockSize == 0)
    {
      break;
    }
  }
  return done;
}

int InputFile::ByteAt(long long offset)
{
  char c;
  return this->ReadAt(offset, &c, 1) == 1 ? static_cast<unsigned char>(c) : -1;
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
void RequestedPiece(vtkInformation* outInfo, int& piece, int& pieces)
{
  piece = 0;
  pieces = 1;
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) &&
    outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()))
  {
    piece = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER());
    pieces = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES());
  }
  if (pieces < 1 || piece < 0 || piece >= pieces)
  {
    piece = 0;
    pieces = 1;
  }
}
} // namespace sightline_io
