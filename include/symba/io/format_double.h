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

}  // namespace symba

#endif  // SYMBA_IO_FORMAT_DOUBLE_H_
