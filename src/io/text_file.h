// Small helpers for the line-oriented text formats symba reads (TUM
// trajectories, the evaluation's CSV): reading a whole file, splitting it
// into lines, strict number parsing and "FILE:LINE" message prefixes. Not
// installed.
#ifndef SYMBA_SRC_IO_TEXT_FILE_H_
#define SYMBA_SRC_IO_TEXT_FILE_H_

#include <charconv>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "symba/common/status.h"

namespace symba::internal {

// Opens `path` for binary reading: "PATH: is a directory" /
// "PATH: cannot open".
Status OpenForReading(const std::string& path, std::ifstream* in);

// The size of the file `in` reads, or 0 when it has none (a pipe); the
// stream is left at its start and in a good state.
std::size_t StreamSize(std::ifstream* in);

// The whole file as bytes, a pipe included; OpenForReading's errors and
// "PATH: cannot read".
Status ReadText(const std::string& path, std::string* text);

// `text` without a leading UTF-8 byte order mark (EF BB BF), which some
// editors and spreadsheet programs write at the start of a text file.
std::string_view WithoutByteOrderMark(std::string_view text);

// The lines of `text` (a leading byte order mark dropped), without their
// '\n' (and a trailing '\r').
std::vector<std::string_view> SplitLines(const std::string& text);

// The whitespace-separated (space, tab) fields of one line.
std::vector<std::string_view> SplitFields(std::string_view line);

// True if the line holds only spaces and tabs.
bool IsBlank(std::string_view line);

// The whole token is one finite double (std::from_chars, no locale).
bool ParseDouble(std::string_view token, double* value);

// The whole token is one integer of type Int.
template <typename Int>
bool ParseInteger(std::string_view token, Int* value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, *value);
  return result.ec == std::errc() && result.ptr == end;
}

// "PATH:LINE", the prefix of every message about one line of a file.
std::string At(const std::string& path, int line);
// "\"TEXT\"".
std::string Quoted(const std::string& text);
// "%g" of a value, for messages.
std::string Approx(double value);

}  // namespace symba::internal

#endif  // SYMBA_SRC_IO_TEXT_FILE_H_
