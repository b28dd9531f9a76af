// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineNetCDFClassicHeader.h"

#include "SightlineReaderInput.h"

#include <cstdint>

namespace sightline_io
{
namespace
{
// The header's grammar (netCDF's "classic format specification"): big-endian 32-bit tags and
// types; counts and lengths 32-bit, 64-bit in CDF-5; variable offsets 64-bit from CDF-2 on.
class HeaderWalk
{
public:
  HeaderWalk(InputFile& file, int version)
    : File(file)
    , Version(version)
  {
  }

  bool Walk(std::string& error)
  {
    this->Position = 4;
    std::uint64_t records = 0;
    if (!this->Count(records, "record count"))
    {
      error = this->Error;
      return false;
    }
    std::uint64_t dimensions = 0;
    std::uint64_t variables = 0;
    if (!this->List(0x0A, "dimensions", dimensions, [this](std::uint64_t) {
          std::uint64_t length = 0;
          return this->Name() && this->Count(length, "dimension length");
        }) ||
      !this->Attributes() ||
      !this->List(0x0B, "variables", variables, [this, dimensions](std::uint64_t) {
        std::uint64_t rank = 0;
        if (!this->Name() || !this->Count(rank, "variable rank") ||
          !this->Fits(rank, this->CountBytes(), "variable dimensions"))
        {
          return false;
        }
        for (std::uint64_t d = 0; d < rank; ++d)
        {
          std::uint64_t id = 0;
          if (!this->Count(id, "dimension id"))
          {
            return false;
          }
          if (id >= dimensions)
          {
            this->Error = "a variable names dimension " + std::to_string(id) + " of " +
              std::to_string(dimensions);
            return false;
          }
        }
        std::uint64_t type = 0;
        std::uint64_t size = 0;
        std::uint64_t begin = 0;
        return this->Attributes() && this->Word(type, 4, "variable type") &&
          this->TypeSize(type) > 0 && this->Word(size, this->Version == 5 ? 8 : 4, "size") &&
          this->Word(begin, this->Version == 1 ? 4 : 8, "offset");
      }))
    {
      error = this->Error;
      return false;
    }
    return true;
  }

private:
  InputFile& File;
  int Version;
  long long Position = 0;
  std::string Error;

  int CountBytes() const { return this->Version == 5 ? 8 : 4; }

  bool Word(std::uint64_t& value, int bytes, const char* what)
  {
    unsigned char data[8];
    if (this->File.ReadAt(this->Position, reinterpret_cast<char*>(data), bytes) !=
      static_cast<std::size_t>(bytes))
    {
      this->Error = std::string("the header ends inside a ") + what;
      return false;
    }
    value = 0;
    for (int i = 0; i < bytes; ++i)
    {
      value = (value << 8) | data[i];
    }
    this->Position += bytes;
    return true;
  }

  bool Count(std::uint64_t& value, const char* what)
  {
    return this->Word(value, this->CountBytes(), what);
  }

  // Whether `count` items of at least `bytes` each can still follow in the file.
  bool Fits(std::uint64_t count, std::uint64_t bytes, const char* what)
  {
    const std::uint64_t left = static_cast<std::uint64_t>(this->File.Size() - this->Position);
    if (bytes > 0 && count > left / bytes)
    {
      this->Error = std::string("the header claims ") + std::to_string(count) + " " + what +
        ", more than the file holds";
      return false;
    }
    return true;
  }

  bool Skip(std::uint64_t bytes, const char* what)
  {
    if (!this->Fits(bytes, 1, what))
    {
      return false;
    }
    this->Position += static_cast<long long>((bytes + 3) / 4 * 4); // padded to 4 bytes
    return true;
  }

  bool Name()
  {
    std::uint64_t length = 0;
    return this->Count(length, "name length") && this->Skip(length, "bytes of a name");
  }

  std::uint64_t TypeSize(std::uint64_t type)
  {
    // NC_BYTE, CHAR, SHORT, INT, FLOAT, DOUBLE; CDF-5 adds UBYTE, USHORT, UINT, INT64, UINT64.
    static const int sizes[] = { 0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8 };
    const std::uint64_t last = this->Version == 5 ? 11 : 6;
    if (type < 1 || type > last)
    {
      this->Error = "the header has an unknown type " + std::to_string(type);
      return 0;
    }
    return static_cast<std::uint64_t>(sizes[type]);
  }

  template <typename Item>
  bool List(std::uint64_t tag, const char* what, std::uint64_t& count, Item item)
  {
    std::uint64_t found = 0;
    if (!this->Word(found, 4, what) || !this->Count(count, what))
    {
      return false;
    }
    if (found == 0 && count == 0)
    {
      return true; // ABSENT
    }
    if (found != tag)
    {
      this->Error = std::string("the header's list of ") + what + " has the wrong tag";
      return false;
    }
    // Each item takes at least a name length and one more count.
    if (!this->Fits(count, 2 * this->CountBytes(), what))
    {
      return false;
    }
    for (std::uint64_t i = 0; i < count; ++i)
    {
      if (!item(i))
      {
        return false;
      }
    }
    return true;
  }

  bool Attributes()
  {
    std::uint64_t attributes = 0; // a list of its own: variables hold one inside theirs
    return this->List(0x0C, "attributes", attributes, [this](std::uint64_t) {
      std::uint64_t type = 0;
      std::uint64_t values = 0;
      if (!this->Name() || !this->Word(type, 4, "attribute type") || !this->Count(values, "values"))
      {
        return false;
      }
      const std::uint64_t size = this->TypeSize(type);
      return size > 0 && this->Fits(values, size, "attribute values") &&
        this->Skip(values * size, "attribute values");
    });
  }
};
} // namespace

bool CheckNetCDFClassicHeader(InputFile& file, std::string& error)
{
  char magic[4] = {};
  if (file.ReadAt(0, magic, 4) != 4 || magic[0] != 'C' || magic[1] != 'D' || magic[2] != 'F')
  {
    return true; // not a classic file
  }
  const int version = magic[3];
  if (version != 1 && version != 2 && version != 5)
  {
    error = "a classic netCDF header of unknown version " + std::to_string(version);
    return false;
  }
  HeaderWalk walk(file, version);
  if (!walk.Walk(error))
  {
    error = "damaged netCDF header: " + error;
    return false;
  }
  return true;
}
} // namespace sightline_io
