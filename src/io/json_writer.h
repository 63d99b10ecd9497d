// Internal: the one way symba writes JSON (log lines, objects.json,
// summary.json, gt_objects.json, evaluation reports, the benches' JSON).
//
// Why by hand and not nlohmann::json's dump (nlohmann reads every JSON file
// symba reads): numbers must be the text every other symba output uses,
// FormatDouble's shortest round-trip form, and a log line must be written
// into a reused buffer without building a document per keyframe. See
// docs/log-format.md, "Numbers".
//
// JsonWriter appends to a caller's string. Layouts:
//   - compact (wrap_depth 0): no whitespace, `{"a":1,"b":[1.0,2.0]}`;
//   - wrapped (wrap_depth d > 0): the elements of the containers opened at
//     depths below d each on their own line, indented by two spaces a level;
//     deeper containers on one line with ", " and ": ". With d =
//     kWrapEverything this is the layout of nlohmann's dump(2).
// Doubles are JSON float literals ("1.0", "1e+05", "-0.0"); NaN and
// infinities are written as null.
#ifndef SYMBA_SRC_IO_JSON_WRITER_H_
#define SYMBA_SRC_IO_JSON_WRITER_H_

#include <cstdint>
#include <string>
#include <string_view>

namespace symba {
namespace io_internal {

// FormatDouble(value), with ".0" added where it would read back as an
// integer, so the text always reads back as a double (signed zero included).
void AppendJsonDouble(double value, std::string* out);

// `text` as a JSON string literal, escaping '"', '\\' and control bytes.
// Other bytes are copied (the caller checks UTF-8).
void AppendJsonString(std::string_view text, std::string* out);

class JsonWriter {
 public:
  static constexpr int kWrapEverything = 1 << 30;
  static constexpr int kMaxDepth = 32;

  explicit JsonWriter(std::string* out, int wrap_depth = 0)
      : out_(out), wrap_depth_(wrap_depth) {}

  JsonWriter& BeginObject() { return Open('{'); }
  JsonWriter& EndObject() { return Close('}'); }
  JsonWriter& BeginArray() { return Open('['); }
  JsonWriter& EndArray() { return Close(']'); }

  // The next value is the member `key` of the open object.
  JsonWriter& Key(std::string_view key);

  JsonWriter& Double(double value);
  JsonWriter& Int(int64_t value);
  JsonWriter& Bool(bool value);
  JsonWriter& Null();
  JsonWriter& String(std::string_view value);

  // [values[0], ..., values[count - 1]] as doubles.
  JsonWriter& Doubles(const double* values, int count);

  // Key(key) followed by the value.
  JsonWriter& Member(std::string_view key, double value) {
    return Key(key).Double(value);
  }
  JsonWriter& Member(std::string_view key, int value) {
    return Key(key).Int(value);
  }
  JsonWriter& Member(std::string_view key, int64_t value) {
    return Key(key).Int(value);
  }
  JsonWriter& Member(std::string_view key, bool value) {
    return Key(key).Bool(value);
  }
  JsonWriter& Member(std::string_view key, std::string_view value) {
    return Key(key).String(value);
  }
  JsonWriter& Member(std::string_view key, const char* value) {
    return Key(key).String(value);
  }

  // Whether every container opened has been closed.
  bool Complete() const { return depth_ == 0 && wrote_value_; }

 private:
  JsonWriter& Open(char bracket);
  JsonWriter& Close(char bracket);
  // Separator and line break before a value or a key.
  void BeforeElement();
  void NewLine(int depth);
  bool Wrapped(int depth) const { return depth < wrap_depth_; }

  std::string* out_;
  int wrap_depth_;
  int depth_ = 0;
  bool after_key_ = false;
  bool wrote_value_ = false;
  // Per open container: its closing bracket and how many elements it has.
  char closer_[kMaxDepth] = {};
  int64_t elements_[kMaxDepth] = {};
};

}  // namespace io_internal
}  // namespace symba

#endif  // SYMBA_SRC_IO_JSON_WRITER_H_
