#include "symba/io/pose_graph.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string_view>
#include <system_error>

#include "io/text_file.h"
#include "pose_graph/pose_graph_checks.h"
#include "symba/factors/pose_graph_edge.h"

namespace symba {
namespace {

constexpr std::string_view kVertexTag = "VERTEX_SE3:QUAT";
constexpr std::string_view kEdgeTag = "EDGE_SE3:QUAT";
constexpr std::string_view kFixTag = "FIX";
constexpr int kVertexFields = 8;     // id x y z qx qy qz qw
constexpr int kEdgeFields = 9 + 21;  // from to x y z qx qy qz qw, upper Omega

std::vector<std::string_view> SplitFields(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i])))
      ++i;
    const size_t begin = i;
    while (i < line.size() &&
           !std::isspace(static_cast<unsigned char>(line[i])))
      ++i;
    if (i > begin) fields.push_back(line.substr(begin, i - begin));
  }
  return fields;
}

// Name of field `index` (0-based, after the tag) of an edge line.
std::string EdgeFieldName(int index) {
  static const char* const kNames[] = {
      "from", "to", "x", "y", "z", "qx", "qy", "qz", "qw"};
  if (index < 9) return kNames[index];
  int k = index - 9;
  for (int row = 0; row < 6; ++row) {
    const int in_row = 6 - row;
    if (k < in_row) {
      return "information(" + std::to_string(row + 1) + "," +
             std::to_string(row + 1 + k) + ")";
    }
    k -= in_row;
  }
  return "?";
}

std::string VertexFieldName(int index) {
  static const char* const kNames[] = {
      "id", "x", "y", "z", "qx", "qy", "qz", "qw"};
  return kNames[index];
}

// Parses one line's fields; every error names the file, line and field.
class LineParser {
 public:
  LineParser(const std::string& path, int line) : path_(path), line_(line) {}

  Status Error(const std::string& what) const {
    return Status::Error(path_ + ":" + std::to_string(line_) + ": " + what);
  }

  Status Integer(std::string_view field,
                 const std::string& name,
                 int64_t* value) const {
    const char* end = field.data() + field.size();
    const auto [ptr, ec] = std::from_chars(field.data(), end, *value);
    if (ec != std::errc() || ptr != end) {
      return Error(name + " is not an integer: '" + std::string(field) + "'");
    }
    return Status::Ok();
  }

  Status Real(std::string_view field,
              const std::string& name,
              double* value) const {
    std::string_view digits = field;
    // from_chars rejects an explicit '+' on the mantissa; g2o writers don't
    // emit one, but it is a valid number.
    if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-') {
      digits.remove_prefix(1);
    }
    const char* end = digits.data() + digits.size();
    const auto [ptr, ec] = std::from_chars(digits.data(), end, *value);
    if (ec == std::errc::result_out_of_range) {
      return Error(name + " is out of range: '" + std::string(field) + "'");
    }
    if (ec != std::errc() || ptr != end) {
      return Error(name + " is not a number: '" + std::string(field) + "'");
    }
    if (!std::isfinite(*value)) {
      return Error(name + " is not finite: '" + std::string(field) + "'");
    }
    return Status::Ok();
  }

 private:
  const std::string& path_;
  int line_;
};

// Reads the seven fields x y z qx qy qz qw into *pose; `first` is the
// 0-based index of x counted after the tag. The quaternion is normalised if
// its norm is within tolerance of 1.
Status ParsePose(const LineParser& parser,
                 const std::vector<std::string_view>& fields,
                 int first,
                 std::string (*field_name)(int),
                 Rigid3d* pose) {
  double v[7];
  for (int i = 0; i < 7; ++i) {
    const int index = first + i;
    // fields[0] is the tag; names are 0-based after it.
    const Status s = parser.Real(fields[index + 1], field_name(index), &v[i]);
    if (!s.ok()) return s;
  }
  Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);  // w, x, y, z
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= internal::kQuaternionNormTolerance)) {
    return parser.Error(
        "quaternion norm " + internal::Approx(norm) + " is not within " +
        internal::Approx(internal::kQuaternionNormTolerance) + " of 1");
  }
  q.coeffs() /= norm;
  *pose = Rigid3d(q, Eigen::Vector3d(v[0], v[1], v[2]));
  return Status::Ok();
}

}  // namespace

Status ReadG2oPoseGraph(const std::string& path,
                        PoseGraph* graph,
                        const G2oReadOptions& options) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    return Status::Error(path + ": is a directory");
  }
  std::ifstream in(path);
  if (!in) {
    return Status::Error(path + ": cannot open (" + std::strerror(errno) + ")");
  }
  PoseGraph result;
  std::map<int64_t, int> vertex_line;
  struct Reference {
    int64_t id;
    int line;
    const char* what;
  };
  std::vector<Reference> references;  // checked once all vertices are known

  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (line == 1) {
      text.erase(0, text.size() - internal::WithoutByteOrderMark(text).size());
    }
    const std::vector<std::string_view> fields = SplitFields(text);
    if (fields.empty() || fields[0][0] == '#') continue;
    const LineParser parser(path, line);
    const std::string_view tag = fields[0];
    const int count = static_cast<int>(fields.size()) - 1;

    if (tag == kVertexTag) {
      if (count != kVertexFields) {
        return parser.Error(
            "VERTEX_SE3:QUAT has " + std::to_string(count) +
            " fields after the tag, expected 8 (id x y z qx qy qz qw)");
      }
      int64_t id = 0;
      Status s = parser.Integer(fields[1], "id", &id);
      if (!s.ok()) return s;
      Rigid3d T_w;
      s = ParsePose(parser, fields, 1, &VertexFieldName, &T_w);
      if (!s.ok()) return s;
      const auto [it, inserted] = vertex_line.emplace(id, line);
      if (!inserted) {
        return parser.Error("duplicate vertex id " + std::to_string(id) +
                            " (first defined on line " +
                            std::to_string(it->second) + ")");
      }
      result.poses.emplace(id, T_w);
    } else if (tag == kEdgeTag) {
      if (count != kEdgeFields) {
        return parser.Error("EDGE_SE3:QUAT has " + std::to_string(count) +
                            " fields after the tag, expected 30 (from to x y "
                            "z qx qy qz qw and the 21 entries of the upper "
                            "triangle of the information)");
      }
      PoseGraphEdge edge;
      Status s = parser.Integer(fields[1], "from", &edge.from);
      if (!s.ok()) return s;
      s = parser.Integer(fields[2], "to", &edge.to);
      if (!s.ok()) return s;
      if (edge.from == edge.to) {
        return parser.Error("edge from vertex " + std::to_string(edge.from) +
                            " to itself");
      }
      s = ParsePose(parser, fields, 2, &EdgeFieldName, &edge.T_ab);
      if (!s.ok()) return s;
      int index = 9;
      for (int row = 0; row < 6; ++row) {
        for (int col = row; col < 6; ++col, ++index) {
          double value = 0.0;
          s = parser.Real(fields[index + 1], EdgeFieldName(index), &value);
          if (!s.ok()) return s;
          edge.information(row, col) = value;
          edge.information(col, row) = value;
        }
      }
      if (options.isotropic_information) {
        const Matrix6d as_written = edge.information;
        if (!IsotropicInformation(as_written, &edge.information)) {
          return parser.Error(
              "information has no isotropic approximation (tau or kappa is "
              "not positive)");
        }
      }
      Matrix6d sqrt_info;
      if (!UpperCholeskyFactor(edge.information, &sqrt_info)) {
        return parser.Error(internal::NotPositiveDefinite(edge.information));
      }
      references.push_back({edge.from, line, "edge"});
      references.push_back({edge.to, line, "edge"});
      result.edges.push_back(edge);
    } else if (tag == kFixTag) {
      if (count < 1) return parser.Error("FIX without a vertex id");
      for (int i = 1; i <= count; ++i) {
        int64_t id = 0;
        const Status s = parser.Integer(fields[i], "vertex id", &id);
        if (!s.ok()) return s;
        references.push_back({id, line, "FIX"});
        result.fixed.insert(id);
      }
    } else {
      return parser.Error("unsupported tag '" + std::string(tag) +
                          "' (accepted: VERTEX_SE3:QUAT, EDGE_SE3:QUAT, FIX)");
    }
  }
  if (in.bad()) {
    return Status::Error(path + ":" + std::to_string(line + 1) +
                         ": read error");
  }
  for (const Reference& ref : references) {
    if (result.poses.count(ref.id) == 0) {
      return Status::Error(path + ":" + std::to_string(ref.line) + ": " +
                           ref.what + " refers to vertex " +
                           std::to_string(ref.id) +
                           ", which no VERTEX_SE3:QUAT line defines");
    }
  }
  if (result.poses.empty()) {
    return Status::Error(path + ": no VERTEX_SE3:QUAT line");
  }
  *graph = std::move(result);
  return Status::Ok();
}

}  // namespace symba
