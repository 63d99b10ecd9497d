// Doubles as text in every file symba writes (TUM trajectories, logs, ground
// truth) and in messages: the shortest decimal text that reads back as
// exactly the same double (std::to_chars), e.g. "0.1", "-2", "1e+300", "-0".
#ifndef SYMBA_IO_FORMAT_DOUBLE_H_
#define SYMBA_IO_FORMAT_DOUBLE_H_

#include <string>

namespace symba {

// The shortest decimal text that reads back as the same double.
std::string FormatDouble(double value);

// Appends FormatDouble(value) to `out` without a temporary string.
void AppendDouble(double value, std::string* out);

// Room for any FormatDouble text ("-2.2250738585072014e-308" is 24).
inline constexpr int kFormatDoubleSize = 32;

// Writes FormatDouble(value) into `buffer` (kFormatDoubleSize chars, no
// terminating zero) and returns the end of the text.
char* FormatDoubleTo(double value, char* buffer);

}  // namespace symba

#endif  // SYMBA_IO_FORMAT_DOUBLE_H_
