// SPDX-License-Identifier: BSD-3-Clause
// Private helpers of the Sightline::IO readers (not wrapped, not installed): where a reader's
// bytes come from (a file or an in-memory copy of one) and how file content is quoted in
// messages.
#ifndef SightlineReaderInput_h
#define SightlineReaderInput_h

#include <cstddef>
#include <fstream>
#include <string>
#include <vector>

class vtkInformation;

namespace sightline_io
{
/// The bytes a reader parses: the whole file `fileName`, or `inputString` when `fromString`.
/// False, with `error` set (valid UTF-8), when no file name is set or the file cannot be read.
bool LoadInput(const char* fileName, bool fromString, const std::string& inputString,
  std::string& bytes, std::string& error);

/// Random access to a reader's bytes without holding them all: the file `fileName` read a block
/// at a time (so that a reader asked for one piece of a file holds about that piece), or
/// `inputString` when `fromString`. Open fails with the messages of LoadInput.
class InputFile
{
public:
  bool Open(const char* fileName, bool fromString, const std::string& inputString,
    std::string& error);
  /// The input's length in bytes.
  long long Size() const { return this->Length; }
  /// Up to `size` bytes from `offset` into `data`; fewer only at the end (or on a read error).
  std::size_t ReadAt(long long offset, char* data, std::size_t size);
  /// The byte at `offset`, or -1 past the end.
  int ByteAt(long long offset);

private:
  const std::string* String = nullptr;
  std::ifstream File;
  long long Length = 0;
  std::vector<char> Block; // a cache of the file from BlockStart
  long long BlockStart = 0;
  std::size_t BlockSize = 0;
};

/// `text` as valid, printable UTF-8 for an error message: well-formed UTF-8 sequences and
/// printable ASCII are kept, every other byte (control characters, stray or overlong UTF-8
/// bytes, surrogates) becomes \xHH; beyond `maxBytes` of input the rest is replaced by "...".
std::string Quote(const std::string& text, std::size_t maxBytes = 160);

/// How messages name the input: 'file name' (quoted as above), or "the input string".
std::string InputName(const char* fileName, bool fromString);

/// The piece a reader's output request asks for (UPDATE_PIECE_NUMBER of
/// UPDATE_NUMBER_OF_PIECES), or piece 0 of 1 when the request has none or an invalid one.
void RequestedPiece(vtkInformation* outInfo, int& piece, int& pieces);
} // namespace sightline_io

#endif
