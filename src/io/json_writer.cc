#include "io/json_writer.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include "symba/common/check.h"
#include "symba/io/format_double.h"

namespace symba {
namespace io_internal {

void AppendJsonDouble(double value, std::string* out) {
  // Looked at for '.' and 'e' before it is appended.
  char buffer[kFormatDoubleSize + 2];
  char* end = FormatDoubleTo(value, buffer);
  if (std::find_if(buffer, end, [](char c) { return c == '.' || c == 'e'; }) ==
      end) {
    *end++ = '.';
    *end++ = '0';
  }
  out->append(buffer, end);
}

void AppendJsonString(std::string_view text, std::string* out) {
  static constexpr char kHex[] = "0123456789abcdef";
  out->push_back('"');
  std::size_t plain = 0;  // start of the bytes not yet copied
  for (std::size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c != '"' && c != '\\') continue;
    out->append(text.data() + plain, i - plain);
    plain = i + 1;
    if (c == '"' || c == '\\') {
      out->push_back('\\');
      out->push_back(static_cast<char>(c));
    } else if (c == '\n') {
      out->append("\\n");
    } else if (c == '\t') {
      out->append("\\t");
    } else {
      out->append("\\u00");
      out->push_back(kHex[c >> 4]);
      out->push_back(kHex[c & 15]);
    }
  }
  out->append(text.data() + plain, text.size() - plain);
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
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out_->append(buffer, result.ptr);
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
