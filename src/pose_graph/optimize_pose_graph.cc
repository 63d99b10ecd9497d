#include "symba/pose_graph/optimize_pose_graph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "io/text_file.h"
#include "pose_graph/pose_graph_checks.h"
#include "symba/pose_graph/chordal_initialization.h"

namespace symba {
namespace {

Status CheckQuaternion(const Eigen::Quaterniond& q, const std::string& what) {
  const double norm = q.norm();
  if (!q.coeffs().allFinite() ||
      !(std::abs(norm - 1.0) <= internal::kQuaternionNormTolerance)) {
    return Status::Error(what + ": quaternion norm " + internal::Approx(norm) +
                         " is not within " +
                         internal::Approx(internal::kQuaternionNormTolerance) +
                         " of 1");
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

// The problem's cost with the states set to `poses` (the states are put
// back after); infinity where it cannot be evaluated or is not finite, so
// that such a start is never preferred.
double CostAt(const std::vector<Rigid3d>& poses,
              std::vector<Rigid3d>* states,
              ceres::Problem* problem) {
  std::vector<Rigid3d> kept = *states;
  *states = poses;
  double cost = 0.0;
  const bool evaluated = problem->Evaluate(
      ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
  *states = kept;
  return evaluated && std::isfinite(cost)
             ? cost
             : std::numeric_limits<double>::infinity();
}

// Levenberg-Marquardt starts from the chordal guess where it costs less
// than the given poses (a graph solved already keeps its start), and from
// the given poses where the chordal initialisation fails.
void ChooseChordalStart(const std::vector<ChordalEdge>& edges,
                        const std::vector<bool>& held,
                        std::vector<Rigid3d>* states,
                        ceres::Problem* problem,
                        PoseGraphSolveSummary* summary) {
  std::vector<Rigid3d> chordal = *states;
  const auto start = std::chrono::steady_clock::now();
  const bool made = ChordalInitialization(edges, held, &chordal);
  summary->initialization_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  if (!made) return;
  const double cost = CostAt(chordal, states, problem);
  if (cost < summary->given_cost) {
    *states = chordal;
    summary->initial_cost = cost;
    summary->chordal_start = true;
  }
}

}  // namespace

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
                           internal::Approx(value) +
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
    Matrix6d isotropic;  // SE-Sync's weights, for the initialisation
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
    if (!UpperCholeskyFactor(edge.information, &p.sqrt_info) ||
        !IsotropicInformation(edge.information, &p.isotropic)) {
      return Status::Error(what + ": " +
                           internal::NotPositiveDefinite(edge.information));
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

  std::vector<ChordalEdge> prepared_chordal;
  if (options.initialization == PoseGraphInitialization::kChordal) {
    prepared_chordal.reserve(prepared.size());
    for (const PreparedEdge& p : prepared) {
      prepared_chordal.push_back(
          {p.a, p.b, p.T_ab, p.isotropic(0, 0), 0.5 * p.isotropic(3, 3)});
    }
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

  summary->given_cost = CostAt(states, &states, &problem);
  summary->initial_cost = summary->given_cost;
  if (options.initialization == PoseGraphInitialization::kChordal) {
    ChooseChordalStart(prepared_chordal, constant, &states, &problem, summary);
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

}  // namespace symba
