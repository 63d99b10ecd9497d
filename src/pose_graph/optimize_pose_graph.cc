#include "symba/pose_graph/optimize_pose_graph.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <ceres/manifold.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include "io/text_file.h"
#include "pose_graph/pose_graph_problem.h"
#include "symba/pose_graph/chordal_initialization.h"

namespace symba {
namespace {

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

  internal::PreparedPoseGraph prepared;
  s = internal::PreparePoseGraph(*graph, &prepared);
  if (!s.ok()) return s;
  summary->num_vertices = static_cast<int>(prepared.ids.size());
  summary->num_edges = static_cast<int>(prepared.edges.size());
  if (prepared.edges.empty()) {
    summary->converged = true;
    summary->message = "no edges: nothing to optimise";
    return Status::Ok();
  }
  std::vector<Rigid3d>& states = prepared.states;
  const std::vector<bool>& constant = prepared.constant;

  std::vector<ChordalEdge> prepared_chordal;
  if (options.initialization == PoseGraphInitialization::kChordal) {
    prepared_chordal.reserve(prepared.edges.size());
    for (const internal::PreparedPoseEdge& p : prepared.edges) {
      prepared_chordal.push_back(
          {p.a, p.b, p.T_ab, p.isotropic(0, 0), 0.5 * p.isotropic(3, 3)});
    }
  }

  internal::PoseGraphProblem pose_graph_problem(options.rotation_error,
                                                &prepared);
  ceres::Problem& problem = pose_graph_problem.problem();

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
  for (size_t i = 0; i < states.size(); ++i) {
    if (!constant[i]) {
      graph->poses[prepared.ids[i]] =
          Rigid3d(states[i].q.normalized(), states[i].t);
    }
  }
  return Status::Ok();
}

}  // namespace symba
