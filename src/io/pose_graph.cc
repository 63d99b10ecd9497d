#include "symba/io/pose_graph.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <numeric>
#include <string_view>
#include <system_error>
#include <unordered_map>

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

namespace symba {
namespace {

constexpr std::string_view kVertexTag = "VERTEX_SE3:QUAT";
constexpr std::string_view kEdgeTag = "EDGE_SE3:QUAT";
constexpr std::string_view kFixTag = "FIX";
// Quaternions whose norm is within this of 1 are normalised, others rejected
// (the same rule as for every file symba reads, docs/conventions.md).
constexpr double kQuaternionNormTolerance = 1e-3;
constexpr int kVertexFields = 8;     // id x y z qx qy qz qw
constexpr int kEdgeFields = 9 + 21;  // from to x y z qx qy qz qw, upper Omega

std::string FormatNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

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
  if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
    return parser.Error("quaternion norm " + FormatNumber(norm) +
                        " is not within " +
                        FormatNumber(kQuaternionNormTolerance) + " of 1");
  }
  q.coeffs() /= norm;
  *pose = Rigid3d(q, Eigen::Vector3d(v[0], v[1], v[2]));
  return Status::Ok();
}

std::string NotPositiveDefinite(const Matrix6d& information) {
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(information,
                                                      Eigen::EigenvaluesOnly);
  return "information matrix is not positive definite (smallest eigenvalue " +
         FormatNumber(eigen.eigenvalues()(0)) + ")";
}

Status CheckQuaternion(const Eigen::Quaterniond& q, const std::string& what) {
  const double norm = q.norm();
  if (!q.coeffs().allFinite() ||
      !(std::abs(norm - 1.0) <= kQuaternionNormTolerance)) {
    return Status::Error(what + ": quaternion norm " + FormatNumber(norm) +
                         " is not within " +
                         FormatNumber(kQuaternionNormTolerance) + " of 1");
  }
  return Status::Ok();
}

Status CheckPose(const Rigid3d& T, const std::string& what) {
  if (!T.t.allFinite()) {
    return Status::Error(what + ": translation is not finite");
  }
  return CheckQuaternion(T.q, what);
}

Rigid3d Normalized(const Rigid3d& T) { return Rigid3d(T.q.normalized(), T.t); }

// Disjoint sets over vertex indices (connected components of the edges).
class DisjointSets {
 public:
  explicit DisjointSets(int size) : parent_(size) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int Find(int i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  void Union(int a, int b) { parent_[Find(a)] = Find(b); }

 private:
  std::vector<int> parent_;
};

}  // namespace

bool IsotropicInformation(const Matrix6d& information, Matrix6d* isotropic) {
  const Eigen::Matrix3d info_t = information.topLeftCorner<3, 3>();
  const Eigen::Matrix3d info_r = information.bottomRightCorner<3, 3>();
  const double tau = 3.0 / info_t.inverse().trace();
  const double kappa = 3.0 / (2.0 * info_r.inverse().trace());
  if (!(std::isfinite(tau) && tau > 0.0 && std::isfinite(kappa) &&
        kappa > 0.0)) {
    return false;
  }
  isotropic->setZero();
  isotropic->diagonal() << Eigen::Vector3d::Constant(tau),
      Eigen::Vector3d::Constant(2.0 * kappa);
  return true;
}

Status ReadG2oPoseGraph(const std::string& path,
                        PoseGraph* graph,
                        const G2oReadOptions& options) {
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
        return parser.Error(NotPositiveDefinite(edge.information));
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

Status PoseGraphSolveOptions::Validate() const {
  if (max_iterations < 1) {
    return Status::Error("pose graph: max_iterations = " +
                         std::to_string(max_iterations) + " is below 1");
  }
  if (num_threads < 1) {
    return Status::Error("pose graph: num_threads = " +
                         std::to_string(num_threads) + " is below 1");
  }
  const std::pair<const char*, double> tolerances[] = {
      {"function_tolerance", function_tolerance},
      {"gradient_tolerance", gradient_tolerance},
      {"parameter_tolerance", parameter_tolerance}};
  for (const auto& [name, value] : tolerances) {
    if (!(value >= 0.0 && std::isfinite(value))) {
      return Status::Error(std::string("pose graph: ") + name + " = " +
                           FormatNumber(value) +
                           " is not a finite non-negative number");
    }
  }
  return Status::Ok();
}

Status OptimizePoseGraph(const PoseGraphSolveOptions& options,
                         PoseGraph* graph,
                         PoseGraphSolveSummary* summary) {
  Status s = options.Validate();
  if (!s.ok()) return s;
  *summary = PoseGraphSolveSummary();

  // Working copies of the vertices that have edges, by dense index.
  std::unordered_map<int64_t, int> index_of;
  std::vector<int64_t> ids;
  std::vector<Rigid3d> states;
  const auto add_vertex = [&](int64_t id, int* index) -> Status {
    const auto found = index_of.find(id);
    if (found != index_of.end()) {
      *index = found->second;
      return Status::Ok();
    }
    const auto pose = graph->poses.find(id);
    if (pose == graph->poses.end()) {
      return Status::Error("vertex " + std::to_string(id) + " does not exist");
    }
    const Status check =
        CheckPose(pose->second, "vertex " + std::to_string(id));
    if (!check.ok()) return check;
    *index = static_cast<int>(ids.size());
    index_of.emplace(id, *index);
    ids.push_back(id);
    states.push_back(Normalized(pose->second));
    return Status::Ok();
  };

  struct PreparedEdge {
    int a;
    int b;
    Rigid3d T_ab;
    Matrix6d sqrt_info;
  };
  std::vector<PreparedEdge> prepared;
  prepared.reserve(graph->edges.size());
  for (size_t k = 0; k < graph->edges.size(); ++k) {
    const PoseGraphEdge& edge = graph->edges[k];
    const std::string what = "pose graph: edge " + std::to_string(k) + " (" +
                             std::to_string(edge.from) + " -> " +
                             std::to_string(edge.to) + ")";
    PreparedEdge p;
    s = add_vertex(edge.from, &p.a);
    if (!s.ok()) return Status::Error(what + ": " + s.message());
    s = add_vertex(edge.to, &p.b);
    if (!s.ok()) return Status::Error(what + ": " + s.message());
    if (p.a == p.b) return Status::Error(what + ": from a vertex to itself");
    s = CheckPose(edge.T_ab, what + ": measurement");
    if (!s.ok()) return s;
    if (!edge.information.allFinite()) {
      return Status::Error(what + ": information is not finite");
    }
    // The factor reads the lower triangle; a programmatic graph might not be
    // symmetric, so insist on it.
    if (!edge.information.isApprox(edge.information.transpose(), 1e-12)) {
      return Status::Error(what + ": information is not symmetric");
    }
    if (!UpperCholeskyFactor(edge.information, &p.sqrt_info)) {
      return Status::Error(what + ": " + NotPositiveDefinite(edge.information));
    }
    p.T_ab = Normalized(edge.T_ab);
    prepared.push_back(p);
  }
  for (const int64_t id : graph->fixed) {
    if (graph->poses.count(id) == 0) {
      return Status::Error("pose graph: fixed vertex " + std::to_string(id) +
                           " does not exist");
    }
  }
  summary->num_vertices = static_cast<int>(ids.size());
  summary->num_edges = static_cast<int>(prepared.size());
  if (prepared.empty()) {
    summary->converged = true;
    summary->message = "no edges: nothing to optimise";
    return Status::Ok();
  }

  // Gauge: FIX vertices, plus the smallest id of every component without one.
  const int n = static_cast<int>(ids.size());
  DisjointSets components(n);
  for (const PreparedEdge& p : prepared) components.Union(p.a, p.b);
  std::vector<bool> constant(n, false);
  std::vector<bool> anchored(n, false);  // by component root
  for (int i = 0; i < n; ++i) {
    if (graph->fixed.count(ids[i]) != 0) {
      constant[i] = true;
      anchored[components.Find(i)] = true;
    }
  }
  std::vector<int> smallest(n, -1);  // by component root
  for (int i = 0; i < n; ++i) {
    int& best = smallest[components.Find(i)];
    if (best < 0 || ids[i] < ids[best]) best = i;
  }
  for (int root = 0; root < n; ++root) {
    if (smallest[root] >= 0 && !anchored[root]) constant[smallest[root]] = true;
  }

  // Declared before the problem, which does not own it and must not outlive
  // it.
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (const PreparedEdge& p : prepared) {
    Rigid3d& T_wa = states[p.a];
    Rigid3d& T_wb = states[p.b];
    problem.AddResidualBlock(PoseGraphEdgeFactor::Create(
                                 p.T_ab, p.sqrt_info, options.rotation_error),
                             nullptr,
                             T_wa.q.coeffs().data(),
                             T_wa.t.data(),
                             T_wb.q.coeffs().data(),
                             T_wb.t.data());
  }
  for (int i = 0; i < n; ++i) {
    double* q = states[i].q.coeffs().data();
    problem.SetManifold(q, &quaternion_manifold);
    if (constant[i]) {
      problem.SetParameterBlockConstant(q);
      problem.SetParameterBlockConstant(states[i].t.data());
    }
  }

  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = options.num_threads;
  solver_options.function_tolerance = options.function_tolerance;
  solver_options.gradient_tolerance = options.gradient_tolerance;
  solver_options.parameter_tolerance = options.parameter_tolerance;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  std::string why;
  if (!solver_options.IsValid(&why)) {
    return Status::Error("pose graph: invalid Ceres options: " + why);
  }

  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, &problem, &ceres_summary);
  summary->initial_cost = ceres_summary.initial_cost;
  summary->final_cost = ceres_summary.final_cost;
  // Ceres records the initial state as iteration 0.
  summary->iterations = ceres_summary.iterations.empty()
                            ? 0
                            : ceres_summary.iterations.back().iteration;
  summary->converged = ceres_summary.termination_type == ceres::CONVERGENCE;
  summary->seconds = ceres_summary.total_time_in_seconds;
  summary->message = ceres_summary.message;
  if (!ceres_summary.IsSolutionUsable()) {
    return Status::Error("pose graph: Ceres failed: " + ceres_summary.message);
  }
  for (int i = 0; i < n; ++i) {
    if (!constant[i]) graph->poses[ids[i]] = Normalized(states[i]);
  }
  return Status::Ok();
}

std::vector<std::pair<double, Rigid3d>> PoseGraphTrajectory(
    const PoseGraph& graph) {
  std::vector<std::pair<double, Rigid3d>> trajectory;
  trajectory.reserve(graph.poses.size());
  for (const auto& [id, T_w] : graph.poses) {
    trajectory.emplace_back(static_cast<double>(id), T_w);
  }
  return trajectory;
}

}  // namespace symba
