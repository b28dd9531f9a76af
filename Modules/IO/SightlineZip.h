// SPDX-License-Identifier: BSD-3-Clause
// Private helpers of Sightline::IO (not wrapped, not installed): the part of the zip format
// (PKWARE APPNOTE 6.3) that TRX archives use. Reading: the central directory, zip64 included,
// and a member's bytes from any offset, stored members read in place and deflated ones inflated
// as a stream, never the whole archive in memory. Writing: stored or deflated members, streamed,
// with zip64 records where sizes or offsets need them.
#ifndef SightlineZip_h
#define SightlineZip_h

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace sightline_io
{
class InputFile;

struct ZipEntry
{
  std::string Name;
  std::uint16_t Method = 0; ///< 0 stored, 8 deflated (nothing else is accepted)
  std::uint32_t Crc = 0;
  std::uint64_t CompressedSize = 0;
  std::uint64_t Size = 0; ///< uncompressed
  std::uint64_t LocalHeaderOffset = 0;
  std::uint64_t DataOffset = 0; ///< where the member's (compressed) bytes start
};

/// Whether `input` starts like a zip archive (a local file header or an empty archive's end).
bool LooksLikeZip(InputFile& input);

/// The members of the zip archive `input`, directories left out. False with `error` set for
/// anything that is not a well-formed archive of stored or deflated, unencrypted members whose
/// local headers agree with the central directory and whose bytes lie inside the input.
bool ReadZipDirectory(InputFile& input, std::vector<ZipEntry>& entries, std::string& error);

/// A member's uncompressed bytes at any offset. Stored members are read in place; deflated
/// ones are inflated from the start (reads at increasing offsets continue the stream). A
/// deflated stream that ends early, runs past its declared size or is corrupt is an error.
class ZipMemberReader
{
public:
  ZipMemberReader(InputFile& input, const ZipEntry& entry);
  ~ZipMemberReader();
  ZipMemberReader(const ZipMemberReader&) = delete;
  ZipMemberReader& operator=(const ZipMemberReader&) = delete;

  bool Read(std::uint64_t offset, char* data, std::size_t size, std::string& error);

private:
  struct Inflater;
  InputFile& Input;
  ZipEntry Entry;
  std::unique_ptr<Inflater> Stream;
};

/// Writes a zip archive member by member: BeginMember, Write any number of times, EndMember,
/// and Close once. Each member's local header is completed once its bytes are known (the
/// output is seekable), so readers need no data descriptors.
class ZipWriter
{
public:
  ZipWriter();
  ~ZipWriter();
  bool Open(const std::string& path, std::string& error);
  /// `deflate` compresses the member; `expectedSize` (its uncompressed size) decides whether
  /// the local header carries zip64 sizes.
  bool BeginMember(const std::string& name, bool deflate, std::uint64_t expectedSize,
    std::string& error);
  bool Write(const char* data, std::size_t size, std::string& error);
  bool EndMember(std::string& error);
  bool Close(std::string& error);

private:
  struct Deflater;
  bool WriteRaw(const char* data, std::size_t size, std::string& error);
  std::ofstream File;
  std::string Path;
  std::vector<ZipEntry> Written;
  ZipEntry Current;
  bool CurrentZip64 = false;
  std::unique_ptr<Deflater> Stream;
  std::uint64_t Position = 0;
};
} // namespace sightline_io

#endif
