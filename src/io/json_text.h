// Internal to the hand-written JSON writers (the log writer, the
// simulator's gt_objects.json) and the log reader: numbers and strings as
// JSON text.
#ifndef SYMBA_SRC_IO_JSON_TEXT_H_
#define SYMBA_SRC_IO_JSON_TEXT_H_

#include <string>
#include <string_view>

#include "symba/io/format_double.h"

namespace symba {
namespace io_internal {

// As AppendDouble (symba/io/format_double.h), but always a JSON float
// literal (with '.' or an exponent: "1.0", "-0.0"), so it reads back as a
// double, signed zero included.
inline void AppendJsonDouble(double value, std::string* out) {
  const std::size_t start = out->size();
  AppendDouble(value, out);
  if (out->find_first_of(".e", start) == std::string::npos) out->append(".0");
}

// `text` as a JSON string literal, escaping '"', '\\' and control bytes.
// Other bytes are copied (the caller checks UTF-8).
inline void AppendJsonString(std::string_view text, std::string* out) {
  static constexpr char kHex[] = "0123456789abcdef";
  out->push_back('"');
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out->push_back('\\');
      out->push_back(ch);
    } else if (c == '\n') {
      out->append("\\n");
    } else if (c == '\t') {
      out->append("\\t");
    } else if (c < 0x20) {
      out->append("\\u00");
      out->push_back(kHex[c >> 4]);
      out->push_back(kHex[c & 15]);
    } else {
      out->push_back(ch);
    }
  }
  out->push_back('"');
}

}  // namespace io_internal
}  // namespace symba

#endif  // SYMBA_SRC_IO_JSON_TEXT_H_
