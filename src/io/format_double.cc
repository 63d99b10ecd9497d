#include "symba/io/format_double.h"

#include <charconv>

namespace symba {

char* FormatDoubleTo(double value, char* buffer) {
  return std::to_chars(buffer, buffer + kFormatDoubleSize, value).ptr;
}

void AppendDouble(double value, std::string* out) {
  char buffer[kFormatDoubleSize];
  out->append(buffer, FormatDoubleTo(value, buffer));
}

std::string FormatDouble(double value) {
  std::string text;
  AppendDouble(value, &text);
  return text;
}

}  // namespace symba
