// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineZip.h"

#include "SightlineReaderInput.h"

#include "vtk_zlib.h"

#include <algorithm>
#include <cstring>

namespace sightline_io
{
namespace
{
constexpr std::uint32_t kLocalHeader = 0x04034b50;
constexpr std::uint32_t kCentralHeader = 0x02014b50;
constexpr std::uint32_t kEnd = 0x06054b50;
constexpr std::uint32_t kZip64End = 0x06064b50;
constexpr std::uint32_t kZip64Locator = 0x07064b50;
constexpr std::uint32_t k32 = 0xFFFFFFFFu;
// Deflate cannot expand data by more than about 1032:1 (a 258-byte match per 2 bits): a member
// that claims more is not what it says it is, and would only make a reader allocate for nothing.
constexpr std::uint64_t kMaxDeflateRatio = 1032;
constexpr std::size_t kChunk = 1 << 18;

std::uint16_t U16(const unsigned char* p)
{
  return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t U32(const unsigned char* p)
{
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
    (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}
std::uint64_t U64(const unsigned char* p)
{
  return static_cast<std::uint64_t>(U32(p)) | (static_cast<std::uint64_t>(U32(p + 4)) << 32);
}
void Put16(std::string& out, std::uint16_t v)
{
  out.push_back(static_cast<char>(v & 0xFF));
  out.push_back(static_cast<char>(v >> 8));
}
void Put32(std::string& out, std::uint32_t v)
{
  for (int k = 0; k < 4; ++k)
  {
    out.push_back(static_cast<char>((v >> (8 * k)) & 0xFF));
  }
}
void Put64(std::string& out, std::uint64_t v)
{
  Put32(out, static_cast<std::uint32_t>(v & k32));
  Put32(out, static_cast<std::uint32_t>(v >> 32));
}

bool ReadExactly(InputFile& input, std::uint64_t offset, unsigned char* data, std::size_t size)
{
  return offset <= static_cast<std::uint64_t>(input.Size()) &&
    input.ReadAt(static_cast<long long>(offset), reinterpret_cast<char*>(data), size) == size;
}

// Where the end-of-central-directory record is: the last one within the 64 KiB comment window.
bool FindEnd(InputFile& input, std::uint64_t& at)
{
  const std::uint64_t size = static_cast<std::uint64_t>(input.Size());
  if (size < 22)
  {
    return false;
  }
  const std::uint64_t window = std::min<std::uint64_t>(size, 22 + 0xFFFF);
  std::vector<unsigned char> tail(window);
  if (!ReadExactly(input, size - window, tail.data(), tail.size()))
  {
    return false;
  }
  for (std::uint64_t i = window - 22 + 1; i-- > 0;)
  {
    if (U32(&tail[i]) == kEnd && i + 22 + U16(&tail[i + 20]) == window)
    {
      at = size - window + i;
      return true;
    }
  }
  return false;
}
} // namespace

bool LooksLikeZip(InputFile& input)
{
  unsigned char head[4];
  return ReadExactly(input, 0, head, 4) && (U32(head) == kLocalHeader || U32(head) == kEnd);
}

bool ReadZipDirectory(InputFile& input, std::vector<ZipEntry>& entries, std::string& error)
{
  entries.clear();
  const std::uint64_t fileSize = static_cast<std::uint64_t>(input.Size());
  std::uint64_t endAt = 0;
  if (!FindEnd(input, endAt))
  {
    error = "no zip end-of-central-directory record: not a zip archive, or cut short";
    return false;
  }
  unsigned char end[22];
  ReadExactly(input, endAt, end, sizeof end);
  std::uint64_t count = U16(end + 10);
  std::uint64_t directorySize = U32(end + 12);
  std::uint64_t directoryAt = U32(end + 16);
  if (U16(end + 4) != 0 || U16(end + 6) != 0)
  {
    error = "multi-disk zip archives are not supported";
    return false;
  }
  if (count == 0xFFFF || directorySize == k32 || directoryAt == k32)
  {
    unsigned char locator[20];
    unsigned char end64[56];
    if (endAt < 20 || !ReadExactly(input, endAt - 20, locator, sizeof locator) ||
      U32(locator) != kZip64Locator || !ReadExactly(input, U64(locator + 8), end64, sizeof end64) ||
      U32(end64) != kZip64End)
    {
      error = "the zip archive's zip64 end record is missing or damaged";
      return false;
    }
    count = U64(end64 + 32);
    directorySize = U64(end64 + 40);
    directoryAt = U64(end64 + 48);
  }
  if (directoryAt > fileSize || directorySize > fileSize - directoryAt || count > directorySize / 46)
  {
    error = "the zip central directory lies outside the file or claims more entries than it holds";
    return false;
  }
  std::vector<unsigned char> directory(directorySize);
  if (!ReadExactly(input, directoryAt, directory.data(), directory.size()))
  {
    error = "cannot read the zip central directory";
    return false;
  }
  std::size_t at = 0;
  for (std::uint64_t e = 0; e < count; ++e)
  {
    if (at + 46 > directory.size() || U32(&directory[at]) != kCentralHeader)
    {
      error = "damaged zip central directory (entry " + std::to_string(e) + ")";
      return false;
    }
    const unsigned char* h = &directory[at];
    ZipEntry entry;
    const std::uint16_t flags = U16(h + 8);
    entry.Method = U16(h + 10);
    entry.Crc = U32(h + 16);
    entry.CompressedSize = U32(h + 20);
    entry.Size = U32(h + 24);
    const std::size_t nameLength = U16(h + 28);
    const std::size_t extraLength = U16(h + 30);
    const std::size_t commentLength = U16(h + 32);
    entry.LocalHeaderOffset = U32(h + 42);
    if (at + 46 + nameLength + extraLength + commentLength > directory.size())
    {
      error = "damaged zip central directory (entry " + std::to_string(e) + ")";
      return false;
    }
    entry.Name.assign(reinterpret_cast<const char*>(h + 46), nameLength);
    // zip64: the fields saturated in the header follow in this order in extra field 0x0001.
    for (std::size_t x = 0; x + 4 <= extraLength;)
    {
      const unsigned char* field = h + 46 + nameLength + x;
      const std::size_t fieldLength = U16(field + 2);
      if (x + 4 + fieldLength > extraLength)
      {
        break;
      }
      if (U16(field) == 0x0001)
      {
        std::size_t f = 4;
        for (std::uint64_t* value : { &entry.Size, &entry.CompressedSize, &entry.LocalHeaderOffset })
        {
          if (*value == k32)
          {
            if (f + 8 > 4 + fieldLength)
            {
              error = "zip entry " + Quote(entry.Name) + " has a short zip64 field";
              return false;
            }
            *value = U64(field + f);
            f += 8;
          }
        }
      }
      x += 4 + fieldLength;
    }
    at += 46 + nameLength + extraLength + commentLength;
    const std::string what = "zip entry " + Quote(entry.Name);
    if (flags & 0x41)
    {
      error = what + " is encrypted";
      return false;
    }
    if (entry.Method != 0 && entry.Method != 8)
    {
      error = what + " uses compression method " + std::to_string(entry.Method) +
        " (only stored and deflated members are read)";
      return false;
    }
    if (entry.Method == 0 && entry.CompressedSize != entry.Size)
    {
      error = what + " is stored but its two sizes differ";
      return false;
    }
    if (entry.Method == 8 && entry.Size / kMaxDeflateRatio > entry.CompressedSize + 1)
    {
      error = what + " claims " + std::to_string(entry.Size) + " bytes from " +
        std::to_string(entry.CompressedSize) + " deflated: more than deflate can hold";
      return false;
    }
    unsigned char local[30];
    if (!ReadExactly(input, entry.LocalHeaderOffset, local, sizeof local) ||
      U32(local) != kLocalHeader)
    {
      error = what + " has no local header where the central directory says";
      return false;
    }
    const std::size_t localName = U16(local + 26);
    std::string name(localName, '\0');
    if (!ReadExactly(input, entry.LocalHeaderOffset + 30,
          reinterpret_cast<unsigned char*>(&name[0]), localName) ||
      name != entry.Name || U16(local + 8) != entry.Method)
    {
      error = what + ": its local header names another member or method";
      return false;
    }
    entry.DataOffset = entry.LocalHeaderOffset + 30 + localName + U16(local + 28);
    if (entry.DataOffset > fileSize || entry.CompressedSize > fileSize - entry.DataOffset)
    {
      error = what + " runs past the end of the file";
      return false;
    }
    if (!entry.Name.empty() && entry.Name.back() != '/')
    {
      entries.push_back(std::move(entry));
    }
  }
  return true;
}

struct ZipMemberReader::Inflater
{
  z_stream Z{};
  bool Ready = false;
  std::uint64_t Produced = 0; // uncompressed bytes given out so far
  std::uint64_t Consumed = 0; // compressed bytes fed so far
  std::vector<char> In;
  ~Inflater()
  {
    if (this->Ready)
    {
      inflateEnd(&this->Z);
    }
  }
};

ZipMemberReader::ZipMemberReader(InputFile& input, const ZipEntry& entry)
  : Input(input)
  , Entry(entry)
{
}

ZipMemberReader::~ZipMemberReader() = default;

bool ZipMemberReader::Read(std::uint64_t offset, char* data, std::size_t size, std::string& error)
{
  const std::string what = "zip member " + Quote(this->Entry.Name);
  if (offset > this->Entry.Size || size > this->Entry.Size - offset)
  {
    error = what + " is shorter than needed";
    return false;
  }
  if (this->Entry.Method == 0)
  {
    if (this->Input.ReadAt(static_cast<long long>(this->Entry.DataOffset + offset), data, size) !=
      size)
    {
      error = "cannot read " + what;
      return false;
    }
    return true;
  }
  if (!this->Stream || offset < this->Stream->Produced)
  {
    this->Stream = std::make_unique<Inflater>();
    if (inflateInit2(&this->Stream->Z, -MAX_WBITS) != Z_OK)
    {
      error = "cannot start inflating " + what;
      return false;
    }
    this->Stream->Ready = true;
    this->Stream->In.resize(kChunk);
  }
  Inflater& s = *this->Stream;
  std::vector<char> skip;
  while (size > 0)
  {
    char* out = data;
    std::size_t want = size;
    const bool skipping = s.Produced < offset;
    if (skipping)
    {
      skip.resize(kChunk);
      out = skip.data();
      want = static_cast<std::size_t>(std::min<std::uint64_t>(kChunk, offset - s.Produced));
    }
    if (s.Z.avail_in == 0 && s.Consumed < this->Entry.CompressedSize)
    {
      const std::size_t n = static_cast<std::size_t>(
        std::min<std::uint64_t>(kChunk, this->Entry.CompressedSize - s.Consumed));
      if (this->Input.ReadAt(static_cast<long long>(this->Entry.DataOffset + s.Consumed),
            s.In.data(), n) != n)
      {
        error = "cannot read " + what;
        return false;
      }
      s.Consumed += n;
      s.Z.next_in = reinterpret_cast<Bytef*>(s.In.data());
      s.Z.avail_in = static_cast<uInt>(n);
    }
    s.Z.next_out = reinterpret_cast<Bytef*>(out);
    s.Z.avail_out = static_cast<uInt>(std::min<std::size_t>(want, 1u << 30));
    const uInt before = s.Z.avail_out;
    const int status = inflate(&s.Z, Z_NO_FLUSH);
    const std::size_t got = before - s.Z.avail_out;
    if (status != Z_OK && status != Z_STREAM_END && status != Z_BUF_ERROR)
    {
      error = what + " is not valid deflate data";
      return false;
    }
    s.Produced += got;
    if (!skipping)
    {
      data += got;
      size -= got;
    }
    if (size > 0 && got == 0 &&
      (status == Z_STREAM_END || (s.Z.avail_in == 0 && s.Consumed >= this->Entry.CompressedSize)))
    {
      error = what + " inflates to " + std::to_string(s.Produced) + " bytes, not the " +
        std::to_string(this->Entry.Size) + " the archive declares";
      return false;
    }
  }
  return true;
}

struct ZipWriter::Deflater
{
  z_stream Z{};
  bool Ready = false;
  ~Deflater()
  {
    if (this->Ready)
    {
      deflateEnd(&this->Z);
    }
  }
};

ZipWriter::ZipWriter() = default;
ZipWriter::~ZipWriter() = default;

bool ZipWriter::Open(const std::string& path, std::string& error)
{
  this->Path = path;
  this->File.open(path, std::ios::binary | std::ios::trunc);
  if (!this->File)
  {
    error = "cannot create " + Quote(path);
    return false;
  }
  this->Written.clear();
  this->Position = 0;
  return true;
}

bool ZipWriter::WriteRaw(const char* data, std::size_t size, std::string& error)
{
  this->File.write(data, static_cast<std::streamsize>(size));
  if (!this->File)
  {
    error = "cannot write " + Quote(this->Path) + " (disk full?)";
    return false;
  }
  this->Position += size;
  return true;
}

bool ZipWriter::BeginMember(
  const std::string& name, bool deflate, std::uint64_t expectedSize, std::string& error)
{
  this->Current = ZipEntry();
  this->Current.Name = name;
  this->Current.Method = deflate ? 8 : 0;
  this->Current.LocalHeaderOffset = this->Position;
  this->CurrentZip64 = expectedSize >= 0xF0000000u;
  std::string header;
  Put32(header, kLocalHeader);
  Put16(header, this->CurrentZip64 ? 45 : 20);
  Put16(header, 0x0800); // names are UTF-8
  Put16(header, this->Current.Method);
  Put32(header, 0); // time and date: none
  Put32(header, 0); // CRC and sizes are filled in by EndMember
  Put32(header, this->CurrentZip64 ? k32 : 0);
  Put32(header, this->CurrentZip64 ? k32 : 0);
  Put16(header, static_cast<std::uint16_t>(name.size()));
  Put16(header, this->CurrentZip64 ? 20 : 0);
  header += name;
  if (this->CurrentZip64)
  {
    Put16(header, 0x0001);
    Put16(header, 16);
    Put64(header, 0);
    Put64(header, 0);
  }
  if (!this->WriteRaw(header.data(), header.size(), error))
  {
    return false;
  }
  this->Current.DataOffset = this->Position;
  this->Stream.reset();
  if (deflate)
  {
    this->Stream = std::make_unique<Deflater>();
    if (deflateInit2(&this->Stream->Z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, -MAX_WBITS, 8,
          Z_DEFAULT_STRATEGY) != Z_OK)
    {
      error = "cannot start deflating " + Quote(name);
      return false;
    }
    this->Stream->Ready = true;
  }
  return true;
}

bool ZipWriter::Write(const char* data, std::size_t size, std::string& error)
{
  this->Current.Crc = static_cast<std::uint32_t>(
    crc32_z(this->Current.Crc, reinterpret_cast<const Bytef*>(data), size));
  this->Current.Size += size;
  if (!this->Stream)
  {
    return this->WriteRaw(data, size, error);
  }
  z_stream& z = this->Stream->Z;
  std::vector<char> out(kChunk);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
  z.avail_in = static_cast<uInt>(size);
  // (callers write in chunks far below 4 GiB)
  do
  {
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = static_cast<uInt>(out.size());
    deflate(&z, Z_NO_FLUSH);
    if (!this->WriteRaw(out.data(), out.size() - z.avail_out, error))
    {
      return false;
    }
  } while (z.avail_out == 0);
  return true;
}

bool ZipWriter::EndMember(std::string& error)
{
  if (this->Stream)
  {
    z_stream& z = this->Stream->Z;
    std::vector<char> out(kChunk);
    int status = Z_OK;
    do
    {
      z.next_out = reinterpret_cast<Bytef*>(out.data());
      z.avail_out = static_cast<uInt>(out.size());
      status = deflate(&z, Z_FINISH);
      if (!this->WriteRaw(out.data(), out.size() - z.avail_out, error))
      {
        return false;
      }
    } while (status == Z_OK);
    this->Stream.reset();
  }
  this->Current.CompressedSize = this->Position - this->Current.DataOffset;
  if (!this->CurrentZip64 && (this->Current.Size >= k32 || this->Current.CompressedSize >= k32))
  {
    error = "zip member " + Quote(this->Current.Name) + " grew past 4 GiB unannounced";
    return false;
  }
  std::string fields;
  Put32(fields, this->Current.Crc);
  Put32(fields, this->CurrentZip64 ? k32 : static_cast<std::uint32_t>(this->Current.CompressedSize));
  Put32(fields, this->CurrentZip64 ? k32 : static_cast<std::uint32_t>(this->Current.Size));
  this->File.seekp(static_cast<std::streamoff>(this->Current.LocalHeaderOffset + 14));
  this->File.write(fields.data(), static_cast<std::streamsize>(fields.size()));
  if (this->CurrentZip64)
  {
    std::string sizes;
    Put64(sizes, this->Current.Size);
    Put64(sizes, this->Current.CompressedSize);
    this->File.seekp(static_cast<std::streamoff>(
      this->Current.LocalHeaderOffset + 30 + this->Current.Name.size() + 4));
    this->File.write(sizes.data(), static_cast<std::streamsize>(sizes.size()));
  }
  this->File.seekp(static_cast<std::streamoff>(this->Position));
  if (!this->File)
  {
    error = "cannot write " + Quote(this->Path);
    return false;
  }
  this->Written.push_back(this->Current);
  return true;
}

bool ZipWriter::Close(std::string& error)
{
  const std::uint64_t directoryAt = this->Position;
  std::string directory;
  for (const ZipEntry& e : this->Written)
  {
    std::string extra;
    if (e.Size >= k32 || e.CompressedSize >= k32 || e.LocalHeaderOffset >= k32)
    {
      std::string values;
      if (e.Size >= k32)
      {
        Put64(values, e.Size);
      }
      if (e.CompressedSize >= k32)
      {
        Put64(values, e.CompressedSize);
      }
      if (e.LocalHeaderOffset >= k32)
      {
        Put64(values, e.LocalHeaderOffset);
      }
      Put16(extra, 0x0001);
      Put16(extra, static_cast<std::uint16_t>(values.size()));
      extra += values;
    }
    Put32(directory, kCentralHeader);
    Put16(directory, 45);
    Put16(directory, extra.empty() ? 20 : 45);
    Put16(directory, 0x0800);
    Put16(directory, e.Method);
    Put32(directory, 0);
    Put32(directory, e.Crc);
    Put32(directory, static_cast<std::uint32_t>(std::min<std::uint64_t>(e.CompressedSize, k32)));
    Put32(directory, static_cast<std::uint32_t>(std::min<std::uint64_t>(e.Size, k32)));
    Put16(directory, static_cast<std::uint16_t>(e.Name.size()));
    Put16(directory, static_cast<std::uint16_t>(extra.size()));
    Put16(directory, 0); // comment
    Put16(directory, 0); // disk
    Put16(directory, 0); // internal attributes
    Put32(directory, 0); // external attributes
    Put32(directory, static_cast<std::uint32_t>(std::min<std::uint64_t>(e.LocalHeaderOffset, k32)));
    directory += e.Name;
    directory += extra;
  }
  const std::uint64_t count = this->Written.size();
  const bool zip64 = count >= 0xFFFF || directoryAt >= k32 || directory.size() >= k32;
  std::string end;
  if (zip64)
  {
    const std::uint64_t end64At = directoryAt + directory.size();
    Put32(end, kZip64End);
    Put64(end, 44);
    Put16(end, 45);
    Put16(end, 45);
    Put32(end, 0);
    Put32(end, 0);
    Put64(end, count);
    Put64(end, count);
    Put64(end, directory.size());
    Put64(end, directoryAt);
    Put32(end, kZip64Locator);
    Put32(end, 0);
    Put64(end, end64At);
    Put32(end, 1);
  }
  Put32(end, kEnd);
  Put16(end, 0);
  Put16(end, 0);
  Put16(end, static_cast<std::uint16_t>(std::min<std::uint64_t>(count, 0xFFFF)));
  Put16(end, static_cast<std::uint16_t>(std::min<std::uint64_t>(count, 0xFFFF)));
  Put32(end, static_cast<std::uint32_t>(std::min<std::uint64_t>(directory.size(), k32)));
  Put32(end, static_cast<std::uint32_t>(std::min<std::uint64_t>(directoryAt, k32)));
  Put16(end, 0);
  if (!this->WriteRaw(directory.data(), directory.size(), error) ||
    !this->WriteRaw(end.data(), end.size(), error))
  {
    return false;
  }
  this->File.close();
  if (!this->File)
  {
    error = "cannot finish " + Quote(this->Path);
    return false;
  }
  return true;
}
} // namespace sightline_io
