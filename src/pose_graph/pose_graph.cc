#include "symba/pose_graph/pose_graph.h"

#include <cmath>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "io/text_file.h"
#include "pose_graph/pose_graph_checks.h"

namespace symba {

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

std::vector<std::pair<double, Rigid3d>> PoseGraphTrajectory(
    const PoseGraph& graph) {
  std::vector<std::pair<double, Rigid3d>> trajectory;
  trajectory.reserve(graph.poses.size());
  for (const auto& [id, T_w] : graph.poses) {
    trajectory.emplace_back(static_cast<double>(id), T_w);
  }
  return trajectory;
}

std::string internal::NotPositiveDefinite(const Matrix6d& information) {
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(information,
                                                      Eigen::EigenvaluesOnly);
  return "information matrix is not positive definite (smallest eigenvalue " +
         internal::Approx(eigen.eigenvalues()(0)) + ")";
}

}  // namespace symba
