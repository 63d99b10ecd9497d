#include "io/json_tree.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <system_error>

#include <nlohmann/json.hpp>

namespace symba {
namespace io_internal {
namespace {

constexpr uint32_t kMaxSize = std::numeric_limits<uint32_t>::max() - 1;

}  // namespace

// ---------------------------------------------------------------------------
// JsonTree

void JsonTree::Clear() {
  nodes_.clear();
  strings_.clear();
  open_.clear();
  pending_key_offset_ = 0;
  pending_key_size_ = 0;
}

JsonTree::Index JsonTree::Find(Index object, std::string_view key) const {
  Index found = 0;
  for (Index i = nodes_[object].first; i != 0; i = nodes_[i].next) {
    if (Key(i) == key) found = i;
  }
  return found;
}

JsonTree::Node* JsonTree::Add(JsonType type) {
  if (nodes_.size() >= kMaxSize) return nullptr;
  const Index index = static_cast<Index>(nodes_.size());
  nodes_.emplace_back();
  Node* node = &nodes_.back();
  node->type = type;
  if (!open_.empty()) {
    Open& parent = open_.back();
    Node& container = nodes_[parent.container];
    if (parent.last_child == 0) {
      container.first = index;
    } else {
      nodes_[parent.last_child].next = index;
    }
    parent.last_child = index;
    ++container.size;
    if (container.type == JsonType::kObject) {
      node->key_offset = pending_key_offset_;
      node->key_size = pending_key_size_;
    }
  }
  return node;
}

bool JsonTree::AppendString(std::string_view s, uint32_t* offset) {
  if (s.size() > kMaxSize || strings_.size() > kMaxSize - s.size()) {
    return false;
  }
  *offset = static_cast<uint32_t>(strings_.size());
  strings_.append(s);
  return true;
}

bool JsonTree::AddNull() { return Add(JsonType::kNull) != nullptr; }

bool JsonTree::AddBool(bool value) {
  return Add(value ? JsonType::kTrue : JsonType::kFalse) != nullptr;
}

bool JsonTree::AddInteger(int64_t value) {
  Node* node = Add(JsonType::kInteger);
  if (node == nullptr) return false;
  node->integer = value;
  return true;
}

bool JsonTree::AddUnsigned(uint64_t value) {
  Node* node = Add(JsonType::kUnsigned);
  if (node == nullptr) return false;
  node->unsigned_integer = value;
  return true;
}

bool JsonTree::AddFloat(double value) {
  Node* node = Add(JsonType::kFloat);
  if (node == nullptr) return false;
  node->number = value;
  return true;
}

bool JsonTree::AddString(std::string_view value) {
  uint32_t offset = 0;
  if (!AppendString(value, &offset)) return false;
  Node* node = Add(JsonType::kString);
  if (node == nullptr) return false;
  node->string_offset = offset;
  node->size = static_cast<uint32_t>(value.size());
  return true;
}

bool JsonTree::AddKey(std::string_view key) {
  uint32_t offset = 0;
  if (!AppendString(key, &offset)) return false;
  pending_key_offset_ = offset;
  pending_key_size_ = static_cast<uint32_t>(key.size());
  return true;
}

bool JsonTree::StartArray() {
  const Index index = static_cast<Index>(nodes_.size());
  if (Add(JsonType::kArray) == nullptr) return false;
  open_.push_back({index, 0});
  return true;
}

bool JsonTree::StartObject() {
  const Index index = static_cast<Index>(nodes_.size());
  if (Add(JsonType::kObject) == nullptr) return false;
  open_.push_back({index, 0});
  return true;
}

void JsonTree::EndContainer() { open_.pop_back(); }

// ---------------------------------------------------------------------------
// The fast scanner: RFC 8259 JSON restricted to what it can decide quickly.
// Whenever it returns false the caller parses again with nlohmann, so it
// must only ever accept valid JSON, and build exactly the tree nlohmann's
// SAX events would.

namespace {

class FastScanner {
 public:
  FastScanner(std::string_view text, JsonTree* tree)
      : p_(text.data()), end_(text.data() + text.size()), tree_(tree) {}

  bool Parse() {
    if (!Value(0)) return false;
    SkipSpace();
    return p_ == end_;
  }

 private:
  void SkipSpace() {
    while (p_ != end_ &&
           (*p_ == ' ' || *p_ == '\t' || *p_ == '\n' || *p_ == '\r')) {
      ++p_;
    }
  }

  bool Literal(std::string_view word) {
    if (static_cast<std::size_t>(end_ - p_) < word.size() ||
        std::string_view(p_, word.size()) != word) {
      return false;
    }
    p_ += word.size();
    return true;
  }

  // At the opening quote. Plain printable ASCII only; escapes, control and
  // non-ASCII bytes are left to nlohmann (which also validates UTF-8).
  bool String(std::string_view* out) {
    const char* begin = ++p_;
    while (p_ != end_) {
      const unsigned char c = static_cast<unsigned char>(*p_);
      if (c == '"') {
        *out = std::string_view(begin, static_cast<std::size_t>(p_ - begin));
        ++p_;
        return true;
      }
      if (c == '\\' || c < 0x20 || c >= 0x80) return false;
      ++p_;
    }
    return false;
  }

  bool Digit() const { return p_ != end_ && *p_ >= '0' && *p_ <= '9'; }

  bool Number() {
    const char* begin = p_;
    const bool negative = *p_ == '-';
    if (negative) ++p_;
    if (!Digit()) return false;
    if (*p_ == '0') {
      ++p_;
    } else {
      while (Digit()) ++p_;
    }
    bool is_float = false;
    if (p_ != end_ && *p_ == '.') {
      ++p_;
      if (!Digit()) return false;
      while (Digit()) ++p_;
      is_float = true;
    }
    if (p_ != end_ && (*p_ == 'e' || *p_ == 'E')) {
      ++p_;
      if (p_ != end_ && (*p_ == '+' || *p_ == '-')) ++p_;
      if (!Digit()) return false;
      while (Digit()) ++p_;
      is_float = true;
    }
    // nlohmann: an integer token is int64 (with a minus sign) or uint64
    // (without); one that does not fit becomes a double.
    if (!is_float) {
      if (negative) {
        int64_t value = 0;
        const auto result = std::from_chars(begin, p_, value);
        if (result.ec == std::errc() && result.ptr == p_) {
          return tree_->AddInteger(value);
        }
      } else {
        uint64_t value = 0;
        const auto result = std::from_chars(begin, p_, value);
        if (result.ec == std::errc() && result.ptr == p_) {
          return tree_->AddUnsigned(value);
        }
      }
    }
    // Correctly rounded, as glibc's strtod that nlohmann uses. Anything
    // from_chars calls out of range (overflow, underflow) goes to nlohmann.
    double value = 0.0;
    const auto result = std::from_chars(begin, p_, value);
    if (result.ec != std::errc() || result.ptr != p_ || !std::isfinite(value)) {
      return false;
    }
    return tree_->AddFloat(value);
  }

  bool Value(int depth) {
    SkipSpace();
    if (p_ == end_) return false;
    switch (*p_) {
      case '{': {
        if (depth >= kFastMaxDepth || !tree_->StartObject()) return false;
        ++p_;
        SkipSpace();
        if (p_ != end_ && *p_ == '}') {
          ++p_;
          tree_->EndContainer();
          return true;
        }
        while (true) {
          SkipSpace();
          std::string_view key;
          if (p_ == end_ || *p_ != '"' || !String(&key) ||
              !tree_->AddKey(key)) {
            return false;
          }
          SkipSpace();
          if (p_ == end_ || *p_ != ':') return false;
          ++p_;
          if (!Value(depth + 1)) return false;
          SkipSpace();
          if (p_ == end_) return false;
          if (*p_ == ',') {
            ++p_;
            continue;
          }
          if (*p_ != '}') return false;
          ++p_;
          tree_->EndContainer();
          return true;
        }
      }
      case '[': {
        if (depth >= kFastMaxDepth || !tree_->StartArray()) return false;
        ++p_;
        SkipSpace();
        if (p_ != end_ && *p_ == ']') {
          ++p_;
          tree_->EndContainer();
          return true;
        }
        while (true) {
          if (!Value(depth + 1)) return false;
          SkipSpace();
          if (p_ == end_) return false;
          if (*p_ == ',') {
            ++p_;
            continue;
          }
          if (*p_ != ']') return false;
          ++p_;
          tree_->EndContainer();
          return true;
        }
      }
      case '"': {
        std::string_view value;
        return String(&value) && tree_->AddString(value);
      }
      case 't':
        return Literal("true") && tree_->AddBool(true);
      case 'f':
        return Literal("false") && tree_->AddBool(false);
      case 'n':
        return Literal("null") && tree_->AddNull();
      default:
        if (*p_ == '-' || (*p_ >= '0' && *p_ <= '9')) return Number();
        return false;
    }
  }

  const char* p_;
  const char* end_;
  JsonTree* tree_;
};

// nlohmann's SAX events into the tree; records the first error.
class TreeSax final : public nlohmann::json_sax<nlohmann::json> {
 public:
  TreeSax(JsonTree* tree, JsonError* error) : tree_(tree), error_(error) {}

  bool null() override { return Check(tree_->AddNull()); }
  bool boolean(bool value) override { return Check(tree_->AddBool(value)); }
  bool number_integer(number_integer_t value) override {
    return Check(tree_->AddInteger(value));
  }
  bool number_unsigned(number_unsigned_t value) override {
    return Check(tree_->AddUnsigned(value));
  }
  bool number_float(number_float_t value, const string_t&) override {
    return Check(tree_->AddFloat(value));
  }
  bool string(string_t& value) override {
    return Check(tree_->AddString(value));
  }
  bool binary(binary_t&) override { return Check(false); }
  bool start_object(std::size_t) override {
    return Check(tree_->StartObject());
  }
  bool key(string_t& value) override { return Check(tree_->AddKey(value)); }
  bool end_object() override {
    tree_->EndContainer();
    return true;
  }
  bool start_array(std::size_t) override { return Check(tree_->StartArray()); }
  bool end_array() override {
    tree_->EndContainer();
    return true;
  }

  bool parse_error(std::size_t position,
                   const std::string& last_token,
                   const nlohmann::detail::exception& ex) override {
    failed_ = true;
    const std::string what = Printable(ex.what());
    error_->column = position;
    error_->offset = position;
    if (ex.id == 406) {
      // out_of_range.406: a number that overflows a double.
      error_->message =
          "number " + Printable(last_token) + " overflows a double";
      if (position >= last_token.size()) {
        error_->column = position - last_token.size() + 1;
      }
      return false;
    }
    // "[json.exception.parse_error.101] parse error at line 1, column 12:
    // syntax error while parsing ..." -> column 12, "syntax error ...".
    const std::size_t at = what.find(", column ");
    if (at != std::string::npos) {
      const char* digits = what.c_str() + at + 9;
      char* end = nullptr;
      const unsigned long column = std::strtoul(digits, &end, 10);
      if (end != digits && end[0] == ':' && end[1] == ' ') {
        error_->column = column;
        error_->message = end + 2;
        return false;
      }
    }
    const std::size_t bracket = what.find("] ");
    error_->message =
        bracket == std::string::npos ? what : what.substr(bracket + 2);
    return false;
  }

  bool failed() const { return failed_; }

  // nlohmann quotes the bytes it read, which may not be UTF-8: spell bytes
  // above 0x7F as \xNN so the message stays printable.
  static std::string Printable(const std::string& text) {
    static constexpr char kHex[] = "0123456789ABCDEF";
    std::string out;
    for (const char ch : text) {
      const unsigned char c = static_cast<unsigned char>(ch);
      if (c < 0x80) {
        out.push_back(ch);
      } else {
        out.append("\\x");
        out.push_back(kHex[c >> 4]);
        out.push_back(kHex[c & 15]);
      }
    }
    return out;
  }

 private:
  bool Check(bool ok) {
    if (!ok && !failed_) {
      failed_ = true;
      error_->column = 0;
      error_->message = "the line is too large to parse";
    }
    return ok;
  }

  JsonTree* tree_;
  JsonError* error_;
  bool failed_ = false;
};

}  // namespace

bool ParseJsonFast(std::string_view text, JsonTree* tree) {
  tree->Clear();
  return FastScanner(text, tree).Parse();
}

bool ParseJsonNlohmann(std::string_view text,
                       JsonTree* tree,
                       JsonError* error) {
  tree->Clear();
  TreeSax sax(tree, error);
  const bool ok = nlohmann::json::sax_parse(text, &sax);
  if (ok && !sax.failed()) return true;
  if (!sax.failed()) {
    error->column = 0;
    error->message = "invalid JSON";
  }
  return false;
}

bool ParseJson(std::string_view text, JsonTree* tree, JsonError* error) {
  if (ParseJsonFast(text, tree)) return true;
  return ParseJsonNlohmann(text, tree, error);
}

}  // namespace io_internal
}  // namespace symba
