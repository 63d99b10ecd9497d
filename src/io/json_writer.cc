#include "io/json_writer.h"

#include <cmath>
#include <string>

#include "symba/common/check.h"
#include "symba/io/format_double.h"

namespace symba {
namespace io_internal {

void AppendJsonDouble(double value, std::string* out) {
  const std::size_t start = out->size();
  AppendDouble(value, out);
  if (out->find_first_of(".e", start) == std::string::npos) out->append(".0");
}

void AppendJsonString(std::string_view text, std::string* out) {
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

void JsonWriter::NewLine(int depth) {
  out_->push_back('\n');
  out_->append(2 * static_cast<std::size_t>(depth), ' ');
}

void JsonWriter::BeforeElement() {
  if (after_key_) {  // the value of a member: the key wrote the separator
    after_key_ = false;
    return;
  }
  SYMBA_CHECK(depth_ > 0 || !wrote_value_) << "a second top-level JSON value";
  if (depth_ == 0) return;
  const int parent = depth_ - 1;
  if (elements_[parent] > 0) {
    out_->push_back(',');
    if (!Wrapped(parent) && wrap_depth_ > 0) out_->push_back(' ');
  }
  if (Wrapped(parent)) NewLine(depth_);
  ++elements_[parent];
}

JsonWriter& JsonWriter::Key(std::string_view key) {
  SYMBA_CHECK(depth_ > 0 && closer_[depth_ - 1] == '}' && !after_key_)
      << "a JSON key outside an object";
  BeforeElement();
  AppendJsonString(key, out_);
  out_->append(wrap_depth_ > 0 ? ": " : ":");
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::Open(char bracket) {
  SYMBA_CHECK(depth_ < kMaxDepth) << "JSON nested deeper than " << kMaxDepth;
  BeforeElement();
  out_->push_back(bracket);
  closer_[depth_] = bracket == '{' ? '}' : ']';
  elements_[depth_] = 0;
  ++depth_;
  return *this;
}

JsonWriter& JsonWriter::Close(char bracket) {
  SYMBA_CHECK(depth_ > 0 && closer_[depth_ - 1] == bracket && !after_key_)
      << "unbalanced JSON " << bracket;
  --depth_;
  if (elements_[depth_] > 0 && Wrapped(depth_)) NewLine(depth_);
  out_->push_back(bracket);
  wrote_value_ = true;
  return *this;
}

JsonWriter& JsonWriter::Double(double value) {
  if (!std::isfinite(value)) return Null();
  BeforeElement();
  AppendJsonDouble(value, out_);
  wrote_value_ = true;
  return *this;
}

JsonWriter& JsonWriter::Int(int64_t value) {
  BeforeElement();
  out_->append(std::to_string(value));
  wrote_value_ = true;
  return *this;
}

JsonWriter& JsonWriter::Bool(bool value) {
  BeforeElement();
  out_->append(value ? "true" : "false");
  wrote_value_ = true;
  return *this;
}

JsonWriter& JsonWriter::Null() {
  BeforeElement();
  out_->append("null");
  wrote_value_ = true;
  return *this;
}

JsonWriter& JsonWriter::String(std::string_view value) {
  BeforeElement();
  AppendJsonString(value, out_);
  wrote_value_ = true;
  return *this;
}

JsonWriter& JsonWriter::Doubles(const double* values, int count) {
  BeginArray();
  for (int i = 0; i < count; ++i) Double(values[i]);
  return EndArray();
}

}  // namespace io_internal
}  // namespace symba
