// SPDX-License-Identifier: BSD-3-Clause
// Private helpers of the Sightline::IO readers (not wrapped, not installed): where a reader's
// bytes come from (a file or an in-memory copy of one) and how file content is quoted in
// messages.
#ifndef SightlineReaderInput_h
#define SightlineReaderInput_h

#include <cstddef>
#include <string>

namespace sightline_io
{
/// The bytes a reader parses: the whole file `fileName`, or `inputString` when `fromString`.
/// False, with `error` set (valid UTF-8), when no file name is set or the file cannot be read.
bool LoadInput(const char* fileName, bool fromString, const std::string& inputString,
  std::string& bytes, std::string& error);

/// `text` as valid, printable UTF-8 for an error message: well-formed UTF-8 sequences and
/// printable ASCII are kept, every other byte (control characters, stray or overlong UTF-8
/// bytes, surrogates) becomes \xHH; beyond `maxBytes` of input the rest is replaced by "...".
std::string Quote(const std::string& text, std::size_t maxBytes = 160);

/// How messages name the input: 'file name' (quoted as above), or "the input string".
std::string InputName(const char* fileName, bool fromString);
} // namespace sightline_io

#endif
