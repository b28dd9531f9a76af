// SPDX-License-Identifier: BSD-3-Clause
#include "SightlineTRXArchive.h"

#include <filesystem>
#include <fstream>

namespace sightline_io
{
namespace
{
constexpr std::size_t kBlockBytes = 1 << 20;

class ZipMemberStream : public TRXMemberStream
{
public:
  ZipMemberStream(InputFile& archive, const ZipEntry& entry)
    : Reader(archive, entry)
  {
  }
  bool Read(std::uint64_t offset, char* data, std::size_t size, std::string& error) override
  {
    return this->Reader.Read(offset, data, size, error);
  }

private:
  ZipMemberReader Reader;
};

class FileMemberStream : public TRXMemberStream
{
public:
  InputFile File;
  std::string Name;
  bool Read(std::uint64_t offset, char* data, std::size_t size, std::string& error) override
  {
    if (offset > static_cast<std::uint64_t>(this->File.Size()) ||
      this->File.ReadAt(static_cast<long long>(offset), data, size) != size)
    {
      error = "cannot read " + Quote(this->Name) + " (changed while reading?)";
      return false;
    }
    return true;
  }
};

class ZipSink : public TRXArchiveWriter
{
public:
  ZipWriter Zip;
  bool Deflate = false;
  bool Begin(const std::string& path, std::uint64_t size, std::string& error) override
  {
    return this->Zip.BeginMember(path, this->Deflate, size, error);
  }
  bool Write(const char* data, std::size_t size, std::string& error) override
  {
    return this->Zip.Write(data, size, error);
  }
  bool End(std::string& error) override { return this->Zip.EndMember(error); }
  bool Close(std::string& error) override { return this->Zip.Close(error); }
};

class DirectorySink : public TRXArchiveWriter
{
public:
  std::filesystem::path Root;
  std::ofstream File;
  std::string Name;
  bool Begin(const std::string& path, std::uint64_t, std::string& error) override
  {
    const std::filesystem::path file = this->Root / path;
    std::error_code code;
    std::filesystem::create_directories(file.parent_path(), code);
    this->Name = file.string();
    this->File.open(file, std::ios::binary | std::ios::trunc);
    if (code || !this->File)
    {
      error = "cannot create " + Quote(this->Name);
      return false;
    }
    return true;
  }
  bool Write(const char* data, std::size_t size, std::string& error) override
  {
    this->File.write(data, static_cast<std::streamsize>(size));
    if (!this->File)
    {
      error = "cannot write " + Quote(this->Name) + " (disk full?)";
      return false;
    }
    return true;
  }
  bool End(std::string& error) override
  {
    this->File.close();
    if (!this->File)
    {
      error = "cannot write " + Quote(this->Name);
      return false;
    }
    return true;
  }
  bool Close(std::string&) override { return true; }
};

} // namespace

bool TRXArchiveReader::Open(const char* fileName, bool fromString,
  const std::string& inputString, std::string& error)
{
  std::error_code code;
  if (!fromString && fileName && std::filesystem::is_directory(fileName, code))
  {
    this->Root = fileName;
    for (auto it = std::filesystem::recursive_directory_iterator(this->Root, code);
         !code && it != std::filesystem::recursive_directory_iterator(); it.increment(code))
    {
      if (it->is_regular_file(code))
      {
        Member member;
        member.Path = it->path().lexically_relative(this->Root).generic_string();
        member.Size = it->file_size(code);
        this->Members.push_back(member);
      }
    }
    if (code)
    {
      error = "cannot list the TRX directory " + Quote(fileName) + ": " + code.message();
      return false;
    }
    this->Directory = true;
    return true;
  }
  if (!this->Archive.Open(fileName, fromString, inputString, error))
  {
    return false;
  }
  if (!ReadZipDirectory(this->Archive, this->Entries, error))
  {
    return false;
  }
  for (std::size_t e = 0; e < this->Entries.size(); ++e)
  {
    this->Members.push_back({ this->Entries[e].Name, this->Entries[e].Size, e });
  }
  return true;
}

std::unique_ptr<TRXMemberStream> TRXArchiveReader::OpenMember(
  const Member& member, std::string& error)
{
  if (!this->Directory)
  {
    return std::make_unique<ZipMemberStream>(this->Archive, this->Entries[member.Entry]);
  }
  auto file = std::make_unique<FileMemberStream>();
  file->Name = member.Path;
  const std::string path = (std::filesystem::path(this->Root) / member.Path).string();
  if (!file->File.Open(path.c_str(), false, std::string(), error))
  {
    return nullptr;
  }
  return file;
}

std::unique_ptr<TRXArchiveWriter> TRXArchiveWriter::Create(
  const std::string& path, bool directory, bool deflate, std::string& error)
{
  if (directory)
  {
    std::error_code code;
    if (std::filesystem::exists(path, code) &&
      !(std::filesystem::is_directory(path, code) && std::filesystem::is_empty(path, code)))
    {
      error = Quote(path) + " exists and is not an empty directory: a TRX directory is written "
                            "into a new or empty one";
      return nullptr;
    }
    auto sink = std::make_unique<DirectorySink>();
    sink->Root = path;
    return sink;
  }
  auto zip = std::make_unique<ZipSink>();
  zip->Deflate = deflate;
  if (!zip->Zip.Open(path, error))
  {
    return nullptr;
  }
  return zip;
}

TRXBlockWriter::TRXBlockWriter(TRXArchiveWriter& sink, std::string& error)
  : Sink(sink)
  , Error(error)
{
  this->Buffer.reserve(kBlockBytes);
}

bool TRXBlockWriter::Add(const void* data, std::size_t size)
{
  const char* bytes = static_cast<const char*>(data);
  this->Buffer.insert(this->Buffer.end(), bytes, bytes + size);
  return this->Buffer.size() < kBlockBytes || this->Flush();
}

bool TRXBlockWriter::Flush()
{
  const bool ok =
    this->Buffer.empty() || this->Sink.Write(this->Buffer.data(), this->Buffer.size(), this->Error);
  this->Buffer.clear();
  return ok;
}
} // namespace sightline_io
