#include "symba/pose_graph/pose_graph_covariance.h"

#include <string>
#include <utility>

#include <ceres/covariance.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include "pose_graph/pose_graph_problem.h"

namespace symba {
namespace {

// Ceres's quaternion tangent d moves R to Exp(2 d) R (left, world frame):
// the rotation vector is twice it.
constexpr double kRotationPerTangent = 2.0;

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

  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  internal::AddPoseGraphEdges(
      options.rotation_error, &quaternion_manifold, &prepared, &problem);
  for (const int64_t id : options.rotation_held) {
    const auto found = prepared.index_of.find(id);
    if (found == prepared.index_of.end()) continue;
    problem.SetParameterBlockConstant(
        prepared.states[found->second].q.coeffs().data());
  }

  // The free blocks of each requested vertex, and every pair among them
  // (once: Ceres refuses a pair asked twice).
  std::vector<std::pair<const double*, const double*>> pairs;
  const std::set<int64_t> distinct(vertices.begin(), vertices.end());
  for (const int64_t id : distinct) {
    const Rigid3d& T = prepared.states[prepared.index_of.at(id)];
    const double* t = T.t.data();
    const double* q = T.q.coeffs().data();
    const bool t_free = !problem.IsParameterBlockConstant(t);
    const bool q_free = !problem.IsParameterBlockConstant(q);
    if (t_free) pairs.emplace_back(t, t);
    if (q_free) pairs.emplace_back(q, q);
    if (t_free && q_free) pairs.emplace_back(t, q);
  }
  ceres::Covariance::Options covariance_options;
  covariance_options.num_threads = options.num_threads;
  ceres::Covariance covariance(covariance_options);
  if (!pairs.empty() && !covariance.Compute(pairs, &problem)) {
    return Status::Error(
        "pose graph covariance: the information is rank deficient (a vertex "
        "is not determined by its edges)");
  }

  std::vector<Matrix6d> out;
  out.reserve(vertices.size());
  for (const int64_t id : vertices) {
    const Rigid3d& T = prepared.states[prepared.index_of.at(id)];
    const double* t = T.t.data();
    const double* q = T.q.coeffs().data();
    const bool t_free = !problem.IsParameterBlockConstant(t);
    const bool q_free = !problem.IsParameterBlockConstant(q);
    Matrix6d c = Matrix6d::Zero();
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> block;
    if (t_free) {
      covariance.GetCovarianceBlockInTangentSpace(t, t, block.data());
      c.topLeftCorner<3, 3>() = block;
    }
    if (q_free) {
      covariance.GetCovarianceBlockInTangentSpace(q, q, block.data());
      c.bottomRightCorner<3, 3>() =
          kRotationPerTangent * kRotationPerTangent * block;
    }
    if (t_free && q_free) {
      covariance.GetCovarianceBlockInTangentSpace(t, q, block.data());
      c.topRightCorner<3, 3>() = kRotationPerTangent * block;
      c.bottomLeftCorner<3, 3>() = c.topRightCorner<3, 3>().transpose();
    }
    out.push_back(0.5 * (c + c.transpose()));
  }
  *covariances = std::move(out);
  return Status::Ok();
}

}  // namespace symba
