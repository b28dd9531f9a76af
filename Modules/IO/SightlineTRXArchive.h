// SPDX-License-Identifier: BSD-3-Clause
// Private helpers of Sightline::IO (not wrapped, not installed): a TRX tractogram's members in
// either of its two forms, a zip archive (SightlineZip.h) or a directory of files, read at any
// offset (vtkSightlineTRXReader) or written in order (vtkSightlineTRXWriter).
#ifndef SightlineTRXArchive_h
#define SightlineTRXArchive_h

#include "SightlineReaderInput.h"
#include "SightlineZip.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace sightline_io
{
/// One member's bytes at any offset.
class TRXMemberStream
{
public:
  virtual ~TRXMemberStream() = default;
  virtual bool Read(std::uint64_t offset, char* data, std::size_t size, std::string& error) = 0;
};

/// The members of a TRX archive (a zip file, or the bytes of one in `inputString`) or of a TRX
/// directory.
class TRXArchiveReader
{
public:
  struct Member
  {
    std::string Path; ///< relative, '/'-separated
    std::uint64_t Size = 0;
    std::size_t Entry = 0; ///< zip entry index
  };
  std::vector<Member> Members;

  bool Open(const char* fileName, bool fromString, const std::string& inputString,
    std::string& error);
  /// A stream over one of Members; null with `error` set when its file cannot be opened.
  std::unique_ptr<TRXMemberStream> OpenMember(const Member& member, std::string& error);

private:
  bool Directory = false;
  std::string Root;
  InputFile Archive;
  std::vector<ZipEntry> Entries;
};

/// Where a writer's members go: Begin, Write any number of times, End; Close once.
class TRXArchiveWriter
{
public:
  virtual ~TRXArchiveWriter() = default;
  /// A zip archive at `path` (members deflated or stored), or with `directory` the files of the
  /// directory `path`, which must not exist or be empty. Null with `error` set otherwise.
  static std::unique_ptr<TRXArchiveWriter> Create(
    const std::string& path, bool directory, bool deflate, std::string& error);
  virtual bool Begin(const std::string& path, std::uint64_t size, std::string& error) = 0;
  virtual bool Write(const char* data, std::size_t size, std::string& error) = 0;
  virtual bool End(std::string& error) = 0;
  virtual bool Close(std::string& error) = 0;
};

/// Buffers a member's bytes and hands them to the writer a block (1 MiB) at a time.
class TRXBlockWriter
{
public:
  TRXBlockWriter(TRXArchiveWriter& sink, std::string& error);
  bool Add(const void* data, std::size_t size);
  bool Flush();

private:
  TRXArchiveWriter& Sink;
  std::string& Error;
  std::vector<char> Buffer;
};
} // namespace sightline_io

#endif
