// Internal to the log reader: one JSON text (a line of a log) parsed into a
// flat tree that is reused from line to line, so reading a log allocates
// nothing once the buffers have grown to the longest line.
//
// ParseJson tries a fast scanner first. It handles the JSON a log normally
// holds (ASCII strings without escapes, numbers that fit a double exactly as
// strtod reads them, nesting up to kFastMaxDepth) and gives up on anything
// else, including every syntax error; nlohmann::json's SAX parser then parses
// the text again and has the last word on what is valid JSON and on the
// error message. Both feed the same JsonTree builder, so the tree never
// depends on which parser built it (fuzz/log_reader_fuzzer.cc checks that).
#ifndef SYMBA_SRC_IO_JSON_TREE_H_
#define SYMBA_SRC_IO_JSON_TREE_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace symba {
namespace io_internal {

enum class JsonType : uint8_t {
  kNull,
  kFalse,
  kTrue,
  kInteger,   // an integer written with a minus sign that fits int64_t
  kUnsigned,  // an integer written without one that fits uint64_t
  kFloat,     // any other number (as strtod reads it)
  kString,
  kArray,
  kObject,
};

class JsonTree {
 public:
  // Node indices; 0 is the root, so 0 also means "none" for links.
  using Index = uint32_t;

  struct Node {
    JsonType type = JsonType::kNull;
    uint32_t size = 0;        // children (array, object) or bytes (string)
    Index first = 0;          // first child
    Index next = 0;           // next sibling
    uint32_t key_offset = 0;  // object members: the key, in strings_
    uint32_t key_size = 0;
    union {
      int64_t integer;
      uint64_t unsigned_integer;
      double number;
      uint32_t string_offset;
    };
    Node() : integer(0) {}
  };

  // Empties the tree, keeping its capacity.
  void Clear();
  bool empty() const { return nodes_.empty(); }
  std::size_t size() const { return nodes_.size(); }
  const Node& node(Index i) const { return nodes_[i]; }
  std::string_view String(Index i) const {
    return std::string_view(strings_).substr(nodes_[i].string_offset,
                                             nodes_[i].size);
  }
  std::string_view Key(Index i) const {
    return std::string_view(strings_).substr(nodes_[i].key_offset,
                                             nodes_[i].key_size);
  }
  // The member of object `object` named `key` (the last one if the key
  // repeats), or 0.
  Index Find(Index object, std::string_view key) const;

  // The builder, in document order (SAX style). Each returns false when the
  // tree cannot grow any more (more than 2^32 - 2 nodes or string bytes).
  bool AddNull();
  bool AddBool(bool value);
  bool AddInteger(int64_t value);
  bool AddUnsigned(uint64_t value);
  bool AddFloat(double value);
  bool AddString(std::string_view value);
  bool AddKey(std::string_view key);
  bool StartArray();
  bool StartObject();
  void EndContainer();

 private:
  struct Open {
    Index container;
    Index last_child;
  };
  Node* Add(JsonType type);
  bool AppendString(std::string_view s, uint32_t* offset);

  std::vector<Node> nodes_;
  std::string strings_;
  std::vector<Open> open_;
  uint32_t pending_key_offset_ = 0;
  uint32_t pending_key_size_ = 0;
};

// How a JSON text failed to parse.
struct JsonError {
  std::size_t column = 0;  // 1-based byte column of the problem in its line
  std::size_t offset = 0;  // bytes of the text read when parsing stopped
  std::string message;     // e.g. "syntax error while parsing value - ..."
};

// Parses `text` (one JSON value, surrounded by optional whitespace) into
// `tree`. Returns false and fills `error` when it is not valid JSON or holds
// a number that overflows a double.
bool ParseJson(std::string_view text, JsonTree* tree, JsonError* error);

// The two parsers on their own, for the fuzzer's differential check.
// ParseJsonFast returns false when it gives up (the tree is then partial).
bool ParseJsonFast(std::string_view text, JsonTree* tree);
bool ParseJsonNlohmann(std::string_view text, JsonTree* tree, JsonError* error);

// Largest nesting the fast scanner handles (a log needs 5 levels).
inline constexpr int kFastMaxDepth = 32;

}  // namespace io_internal
}  // namespace symba

#endif  // SYMBA_SRC_IO_JSON_TREE_H_
