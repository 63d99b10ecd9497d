#include "symba/pose_graph/pose_graph_covariance.h"

#include <set>
#include <string>
#include <utility>
#include <vector>

#include <ceres/covariance.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include "pose_graph/pose_graph_problem.h"

namespace symba {
namespace {

// Ceres's quaternion tangent d moves R to Exp(2 d) R (left, world frame):
// the rotation vector is twice it.
constexpr double kRotationPerTangent = 2.0;

// A requested vertex's blocks, each null where the problem holds it.
struct FreeBlocks {
  const double* t = nullptr;
  const double* q = nullptr;
};

FreeBlocks FreeBlocksOf(const Rigid3d& T, ceres::Problem* problem) {
  FreeBlocks free;
  if (!problem->IsParameterBlockConstant(T.t.data())) free.t = T.t.data();
  if (!problem->IsParameterBlockConstant(T.q.coeffs().data())) {
    free.q = T.q.coeffs().data();
  }
  return free;
}

// Every pair of free blocks within each vertex, once (Ceres refuses a pair
// asked twice).
std::vector<std::pair<const double*, const double*>> Pairs(
    const std::vector<FreeBlocks>& vertices) {
  std::set<std::pair<const double*, const double*>> pairs;
  for (const FreeBlocks& v : vertices) {
    if (v.t != nullptr) pairs.emplace(v.t, v.t);
    if (v.q != nullptr) pairs.emplace(v.q, v.q);
    if (v.t != nullptr && v.q != nullptr) pairs.emplace(v.t, v.q);
  }
  return {pairs.begin(), pairs.end()};
}

// [t; w] from the tangent blocks; zero where a block is held.
Matrix6d VertexCovariance(const ceres::Covariance& covariance,
                          const FreeBlocks& v) {
  Matrix6d c = Matrix6d::Zero();
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block;
  if (v.t != nullptr) {
    covariance.GetCovarianceBlockInTangentSpace(v.t, v.t, block.data());
    c.topLeftCorner<3, 3>() = block;
  }
  if (v.q != nullptr) {
    covariance.GetCovarianceBlockInTangentSpace(v.q, v.q, block.data());
    c.bottomRightCorner<3, 3>() =
        kRotationPerTangent * kRotationPerTangent * block;
  }
  if (v.t != nullptr && v.q != nullptr) {
    covariance.GetCovarianceBlockInTangentSpace(v.t, v.q, block.data());
    c.topRightCorner<3, 3>() = kRotationPerTangent * block;
    c.bottomLeftCorner<3, 3>() = c.topRightCorner<3, 3>().transpose();
  }
  // Exactly symmetric (Ceres's round-off is not).
  return 0.5 * (c + c.transpose());
}

}  // namespace

Status PoseGraphCovariances(const PoseGraph& graph,
                            const std::vector<int64_t>& vertices,
                            const PoseGraphCovarianceOptions& options,
                            std::vector<Matrix6d>* covariances) {
  if (options.num_threads < 1) {
    return Status::Error("pose graph covariance: num_threads = " +
                         std::to_string(options.num_threads) + " is below 1");
  }
  internal::PreparedPoseGraph prepared;
  const Status s = internal::PreparePoseGraph(graph, &prepared);
  if (!s.ok()) return s;
  for (const int64_t id : vertices) {
    if (prepared.index_of.count(id) == 0) {
      return Status::Error("pose graph covariance: vertex " +
                           std::to_string(id) + " has no edge");
    }
  }

  internal::PoseGraphProblem pose_graph_problem(options.rotation_error,
                                                &prepared);
  ceres::Problem& problem = pose_graph_problem.problem();
  for (const int64_t id : options.rotation_held) {
    const auto found = prepared.index_of.find(id);
    if (found == prepared.index_of.end()) continue;
    problem.SetParameterBlockConstant(
        prepared.states[found->second].q.coeffs().data());
  }

  std::vector<FreeBlocks> free;
  free.reserve(vertices.size());
  for (const int64_t id : vertices) {
    free.push_back(
        FreeBlocksOf(prepared.states[prepared.index_of.at(id)], &problem));
  }
  const std::vector<std::pair<const double*, const double*>> pairs =
      Pairs(free);
  ceres::Covariance::Options covariance_options;
  covariance_options.num_threads = options.num_threads;
  ceres::Covariance covariance(covariance_options);
  if (!pairs.empty() && !covariance.Compute(pairs, &problem)) {
    return Status::Error(
        "pose graph covariance: the information is rank deficient (a vertex "
        "is not determined by its edges)");
  }
  std::vector<Matrix6d> out;
  out.reserve(free.size());
  for (const FreeBlocks& v : free)
    out.push_back(VertexCovariance(covariance, v));
  *covariances = std::move(out);
  return Status::Ok();
}

}  // namespace symba
