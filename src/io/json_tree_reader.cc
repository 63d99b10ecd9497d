#include "io/json_tree_reader.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/SVD>

#include "io/json_writer.h"
#include "io/text_file.h"
#include "symba/io/format_double.h"

namespace symba {
namespace io_internal {
namespace {

using internal::Approx;

// A quaternion whose squared norm is this close to 1 is already unit to
// machine precision and is kept bit for bit.
constexpr double kExactlyUnit = 8.0 * std::numeric_limits<double>::epsilon();

}  // namespace

void JsonPath::Append(std::string* out) const {
  if (IsRoot()) return;
  parent->Append(out);
  switch (kind) {
    case Kind::kElement:
      out->append("[").append(std::to_string(index)).append("]");
      break;
    case Kind::kQuotedMember:
      out->push_back('[');
      AppendJsonString(key, out);
      out->push_back(']');
      break;
    default:
      if (!parent->IsRoot()) out->push_back('.');
      out->append(key);
  }
}

std::string QuoteForMessage(std::string_view text) {
  constexpr std::size_t kMax = 40;
  const bool cut = text.size() > kMax;
  std::string out;
  AppendJsonString(cut ? text.substr(0, kMax) : text, &out);
  if (cut) out.insert(out.size() - 1, "...");
  return out;
}

Status JsonTreeReader::Fail(const JsonPath& path, std::string_view what) const {
  std::string message = file_;
  if (line_ > 0) message.append(":").append(std::to_string(line_));
  message.append(": ");
  if (!path.IsRoot()) {
    path.Append(&message);
    message.append(": ");
  }
  message.append(what);
  return Status::Error(std::move(message));
}

std::string JsonTreeReader::Describe(Index i) const {
  const JsonTree::Node& node = tree_.node(i);
  switch (node.type) {
    case JsonType::kNull:
      return "null";
    case JsonType::kFalse:
      return "false";
    case JsonType::kTrue:
      return "true";
    case JsonType::kInteger:
      return std::to_string(node.integer);
    case JsonType::kUnsigned:
      return std::to_string(node.unsigned_integer);
    case JsonType::kFloat:
      return FormatDouble(node.number);
    case JsonType::kString:
      return "the string " + QuoteForMessage(tree_.String(i));
    case JsonType::kArray:
      return "an array";
    case JsonType::kObject:
      return "an object";
  }
  return "?";
}

Status JsonTreeReader::Object(Index i, const JsonPath& path) const {
  if (Type(i) == JsonType::kObject) return Status::Ok();
  return Fail(path, "expected an object, got " + Describe(i));
}

Status JsonTreeReader::Array(Index i, const JsonPath& path) const {
  if (Type(i) == JsonType::kArray) return Status::Ok();
  return Fail(path, "expected an array, got " + Describe(i));
}

Status JsonTreeReader::Number(Index i,
                              const JsonPath& path,
                              double* out) const {
  const JsonTree::Node& node = tree_.node(i);
  switch (node.type) {
    case JsonType::kInteger:
      *out = static_cast<double>(node.integer);
      break;
    case JsonType::kUnsigned:
      *out = static_cast<double>(node.unsigned_integer);
      break;
    case JsonType::kFloat:
      *out = node.number;
      break;
    default:
      return Fail(path, "expected a number, got " + Describe(i));
  }
  // JSON has no literal for them and the parser refuses overflow, so this
  // only guards the invariant.
  if (!std::isfinite(*out)) return Fail(path, "number is not finite");
  return Status::Ok();
}

Status JsonTreeReader::Positive(Index i,
                                const JsonPath& path,
                                double* out) const {
  Status status = Number(i, path, out);
  if (!status.ok()) return status;
  if (!(*out > 0.0)) return Fail(path, "must be positive, got " + Describe(i));
  return Status::Ok();
}

Status JsonTreeReader::Integer(Index i,
                               const JsonPath& path,
                               int64_t* out) const {
  const JsonTree::Node& node = tree_.node(i);
  switch (node.type) {
    case JsonType::kInteger:
      *out = node.integer;
      return Status::Ok();
    case JsonType::kUnsigned:
      if (node.unsigned_integer >
          static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
        return Fail(path, "integer " + Describe(i) + " is out of range");
      }
      *out = static_cast<int64_t>(node.unsigned_integer);
      return Status::Ok();
    case JsonType::kFloat: {
      const double value = node.number;
      if (std::floor(value) != value) {
        return Fail(path, "expected an integer, got " + Describe(i));
      }
      // [-2^63, 2^63): exactly the doubles that convert to int64.
      if (!(value >= -9223372036854775808.0 && value < 9223372036854775808.0)) {
        return Fail(path, "integer " + Describe(i) + " is out of range");
      }
      *out = static_cast<int64_t>(value);
      return Status::Ok();
    }
    default:
      return Fail(path, "expected an integer, got " + Describe(i));
  }
}

Status JsonTreeReader::Int(Index i, const JsonPath& path, int* out) const {
  int64_t value = 0;
  Status status = Integer(i, path, &value);
  if (!status.ok()) return status;
  if (value < std::numeric_limits<int>::min() ||
      value > std::numeric_limits<int>::max()) {
    return Fail(path, "integer " + Describe(i) + " is out of range");
  }
  *out = static_cast<int>(value);
  return Status::Ok();
}

Status JsonTreeReader::String(Index i,
                              const JsonPath& path,
                              std::string_view* out) const {
  if (Type(i) != JsonType::kString) {
    return Fail(path, "expected a string, got " + Describe(i));
  }
  *out = tree_.String(i);
  return Status::Ok();
}

Status JsonTreeReader::Symmetry(Index i,
                                const JsonPath& path,
                                SymmetryType* out) const {
  std::string_view name;
  Status status = String(i, path, &name);
  if (!status.ok()) return status;
  const std::optional<SymmetryType> parsed =
      ParseSymmetryType(std::string(name));
  if (!parsed) {
    return Fail(
        path,
        QuoteForMessage(name) + " is not asymmetric, discrete or continuous");
  }
  *out = *parsed;
  return Status::Ok();
}

Status JsonTreeReader::Require(Index object,
                               const JsonPath& path,
                               std::string_view key,
                               std::string_view hint,
                               Index* out) const {
  *out = Find(object, key);
  if (*out != 0) return Status::Ok();
  std::string what = "missing";
  if (!hint.empty()) what.append(" (").append(hint).append(")");
  return Fail(path.Member(key), what);
}

Status JsonTreeReader::Numbers(Index i,
                               const JsonPath& path,
                               int n,
                               double* out) const {
  const JsonTree::Node& node = tree_.node(i);
  if (node.type != JsonType::kArray || node.size != static_cast<uint32_t>(n)) {
    std::string what =
        "expected an array of " + std::to_string(n) + " numbers, got ";
    if (node.type == JsonType::kArray) {
      what += std::to_string(node.size) +
              (node.size == 1 ? " element" : " elements");
    } else {
      what += Describe(i);
    }
    return Fail(path, what);
  }
  int k = 0;
  for (Index e = node.first; e != 0; e = tree_.node(e).next, ++k) {
    Status status = Number(e, path.Element(k), &out[k]);
    if (!status.ok()) return status;
  }
  return Status::Ok();
}

Status JsonTreeReader::UnitVector(Index i,
                                  const JsonPath& path,
                                  Eigen::Vector3d* v) const {
  Status status = Numbers(i, path, 3, v->data());
  if (!status.ok()) return status;
  const double norm = v->norm();
  if (!(std::abs(norm - 1.0) <= kUnitTolerance)) {
    return Fail(path, "norm " + Approx(norm) + " is not within 1e-3 of 1");
  }
  // As for quaternions: one that is unit already is kept as it is.
  if (std::abs(v->squaredNorm() - 1.0) > kExactlyUnit) *v /= norm;
  return Status::Ok();
}

Status JsonTreeReader::Pose(Index i,
                            const JsonPath& path,
                            Rigid3d* pose) const {
  Status status = Object(i, path);
  if (!status.ok()) return status;
  Index t = 0;
  status = Require(i, path, "t", "the translation [x, y, z]", &t);
  if (!status.ok()) return status;
  status = Numbers(t, path.Member("t"), 3, pose->t.data());
  if (!status.ok()) return status;
  const Index q = Find(i, "q");
  const Index r = Find(i, "R");
  if (q != 0 && r != 0) {
    return Fail(path, "has both q and R; give one rotation");
  }
  if (q == 0 && r == 0) {
    return Fail(path,
                "has neither q [qx, qy, qz, qw] nor R (row-major 3 x 3); "
                "one of them is required");
  }
  if (q != 0) {
    const JsonPath q_path = path.Member("q");
    double v[4];
    status = Numbers(q, q_path, 4, v);
    if (!status.ok()) return status;
    pose->q = Eigen::Quaterniond(v[3], v[0], v[1], v[2]);  // w, x, y, z
    return Normalize(q_path, &pose->q);
  }
  const JsonPath r_path = path.Member("R");
  double v[9];
  status = Numbers(r, r_path, 9, v);
  if (!status.ok()) return status;
  const Eigen::Matrix3d R =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(v);
  const double deviation =
      (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(deviation <= kUnitTolerance)) {
    return Fail(r_path,
                "not a rotation: R^T R differs from the identity by " +
                    Approx(deviation) + " (more than 1e-3)");
  }
  const double det = R.determinant();
  if (!(det > 0.0)) {
    return Fail(r_path,
                "not a rotation: det(R) = " + Approx(det) + " is not positive");
  }
  // The nearest rotation in the Frobenius norm: U V^T.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(
      R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d R_projected = svd.matrixU() * svd.matrixV().transpose();
  pose->q = Eigen::Quaterniond(R_projected);
  return Normalize(r_path, &pose->q);
}

Status JsonTreeReader::Normalize(const JsonPath& path,
                                 Eigen::Quaterniond* q) const {
  const double squared_norm = q->squaredNorm();
  const double norm = std::sqrt(squared_norm);
  if (!(std::abs(norm - 1.0) <= kUnitTolerance)) {
    return Fail(path,
                "quaternion norm " + Approx(norm) + " is not within 1e-3 of 1");
  }
  if (std::abs(squared_norm - 1.0) > kExactlyUnit) q->coeffs() /= norm;
  return Status::Ok();
}

Status ObjectsArray(const JsonTreeReader& r, JsonTree::Index* objects) {
  const JsonPath root;
  Status status = r.Object(0, root);
  if (status.ok()) status = r.Require(0, root, "objects", "", objects);
  if (status.ok()) status = r.Array(*objects, root.Member("objects"));
  return status;
}

Status ObjectIdentity(const JsonTreeReader& r,
                      JsonTree::Index object,
                      const JsonPath& where,
                      int* id,
                      std::string* class_name,
                      SymmetryType* symmetry) {
  Status status = r.Object(object, where);
  JsonTree::Index member = 0;
  if (status.ok()) status = r.Require(object, where, "id", "", &member);
  if (status.ok()) status = r.Int(member, where.Member("id"), id);
  if (status.ok()) status = r.Require(object, where, "class", "", &member);
  std::string_view name;
  if (status.ok()) status = r.String(member, where.Member("class"), &name);
  if (!status.ok()) return status;
  *class_name = std::string(name);
  status = r.Require(object, where, "symmetry", "", &member);
  if (status.ok()) {
    status = r.Symmetry(member, where.Member("symmetry"), symmetry);
  }
  return status;
}

Status ReadJsonFile(const std::string& path, JsonTree* tree) {
  std::string text;
  Status status = internal::ReadText(path, &text);
  if (!status.ok()) return status;
  return ParseJsonText(text, path, tree);
}

Status ParseJsonText(const std::string& text,
                     const std::string& path,
                     JsonTree* tree) {
  JsonError error;
  if (ParseJson(text, tree, &error)) return Status::Ok();
  // error.offset bytes were read when parsing stopped (one past the end at
  // the end of the text); the line is the one holding the last byte read.
  const std::size_t before =
      std::min(error.offset > 0 ? error.offset - 1 : 0, text.size());
  const int line = 1 + static_cast<int>(std::count(
                           text.begin(),
                           text.begin() + static_cast<std::ptrdiff_t>(before),
                           '\n'));
  std::string what = "invalid JSON";
  if (error.column > 0) what += " at column " + std::to_string(error.column);
  return Status::Error(internal::At(path, line) + ": " + what + ": " +
                       error.message);
}

}  // namespace io_internal
}  // namespace symba
