// Internal: reading a parsed JSON text (a JsonTree, io/json_tree.h) with
// errors that name where the value sits. The one path-aware JSON reader:
// the log reader (one tree a line) and the readers of objects.json and
// gt_objects.json (one tree a file) use it.
//
// Every message is LOCATION PATH: WHAT, e.g.
//   run.jsonl:3: detections[0].hypotheses[2].q: quaternion norm 2 is not ...
//   out/objects.json: objects[1].axis: missing
// LOCATION is "FILE:LINE: " for a log line and "FILE: " for a whole file.
// Paths live on the stack and are spelled out only for a message, so a valid
// text costs no string building.
#ifndef SYMBA_SRC_IO_JSON_TREE_READER_H_
#define SYMBA_SRC_IO_JSON_TREE_READER_H_

#include <cstdint>
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "io/json_tree.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"

namespace symba {
namespace io_internal {

// Quaternions (and unit vectors) whose norm is within this of 1 are
// normalised; others are errors.
inline constexpr double kUnitTolerance = 1e-3;

// Where a value sits in the JSON, e.g. detections[0].hypotheses[2].q or
// detections["17/0"]. A path points to its parent, so children are made
// only from named paths: `const JsonPath a = root.Member("a");
// a.Element(0)`, never `root.Member("a").Element(0)` (deleted below).
struct JsonPath {
  enum class Kind { kRoot, kMember, kElement, kQuotedMember };
  const JsonPath* parent = nullptr;
  Kind kind = Kind::kRoot;
  std::string_view key;  // kMember, kQuotedMember
  int64_t index = -1;    // kElement

  JsonPath Member(std::string_view name) const& {
    return JsonPath{this, Kind::kMember, name, -1};
  }
  // A member whose name is data (e.g. a detection id): written ["name"].
  JsonPath QuotedMember(std::string_view name) const& {
    return JsonPath{this, Kind::kQuotedMember, name, -1};
  }
  JsonPath Element(int64_t i) const& {
    return JsonPath{this, Kind::kElement, {}, i};
  }
  // A child of a temporary would point to it after it is gone.
  JsonPath Member(std::string_view) const&& = delete;
  JsonPath QuotedMember(std::string_view) const&& = delete;
  JsonPath Element(int64_t) const&& = delete;
  bool IsRoot() const { return kind == Kind::kRoot; }

  void Append(std::string* out) const;
};

// A string value for a message: quoted, control bytes escaped, long ones cut.
std::string QuoteForMessage(std::string_view text);

class JsonTreeReader {
 public:
  using Index = JsonTree::Index;

  // `line` > 0: a line of `file`; 0: the whole file.
  JsonTreeReader(const std::string& file, int line, const JsonTree& tree)
      : file_(file), line_(line), tree_(tree) {}

  Status Fail(const JsonPath& path, std::string_view what) const;

  JsonType Type(Index i) const { return tree_.node(i).type; }
  // The member `key` of object `object` (the last one if it repeats), or 0.
  Index Find(Index object, std::string_view key) const {
    return tree_.Find(object, key);
  }
  const JsonTree& tree() const { return tree_; }

  // "a string", "an array", "1.5", ... for "expected X, got Y".
  std::string Describe(Index i) const;

  Status Object(Index i, const JsonPath& path) const;
  Status Array(Index i, const JsonPath& path) const;
  // A finite number.
  Status Number(Index i, const JsonPath& path, double* out) const;
  Status Positive(Index i, const JsonPath& path, double* out) const;
  // A JSON integer, or a number with zero fractional part, in int64 range.
  Status Integer(Index i, const JsonPath& path, int64_t* out) const;
  // The same in int range.
  Status Int(Index i, const JsonPath& path, int* out) const;
  Status String(Index i, const JsonPath& path, std::string_view* out) const;
  // "asymmetric", "discrete" or "continuous".
  Status Symmetry(Index i, const JsonPath& path, SymmetryType* out) const;
  // The member `key` of `object`, which must exist; `hint` (may be empty)
  // says what it should be.
  Status Require(Index object,
                 const JsonPath& path,
                 std::string_view key,
                 std::string_view hint,
                 Index* out) const;
  // An array of exactly n numbers.
  Status Numbers(Index i, const JsonPath& path, int n, double* out) const;
  // A 3-vector whose norm is within kUnitTolerance of 1, normalised.
  Status UnitVector(Index i, const JsonPath& path, Eigen::Vector3d* v) const;
  // {"t": [x, y, z], "q": [qx, qy, qz, qw]} or {"t": [...], "R": [9]}.
  Status Pose(Index i, const JsonPath& path, Rigid3d* pose) const;
  // Normalises `q` if its norm is within kUnitTolerance of 1 (a quaternion
  // unit to machine precision is kept bit for bit).
  Status Normalize(const JsonPath& path, Eigen::Quaterniond* q) const;

 private:
  const std::string& file_;
  int line_;
  const JsonTree& tree_;
};

// symba's files of objects (objects.json, gt_objects.json): the root is an
// object with an array "objects" ...
Status ObjectsArray(const JsonTreeReader& r, JsonTree::Index* objects);
// ... whose every entry is an object with an integer "id", a string "class"
// and a "symmetry".
Status ObjectIdentity(const JsonTreeReader& r,
                      JsonTree::Index object,
                      const JsonPath& where,
                      int* id,
                      std::string* class_name,
                      SymmetryType* symmetry);

// Reads the file `path` and parses it as one JSON text into `tree`; a syntax
// error reads "PATH:LINE: invalid JSON at column C: REASON".
Status ReadJsonFile(const std::string& path, JsonTree* tree);
// The same for a text already read; `path` names it in messages.
Status ParseJsonText(const std::string& text,
                     const std::string& path,
                     JsonTree* tree);

}  // namespace io_internal
}  // namespace symba

#endif  // SYMBA_SRC_IO_JSON_TREE_READER_H_
