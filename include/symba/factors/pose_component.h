// One component of a pose max-mixture: a hypothesis T_co^j with its
// square-root information L_j (6 x 6, acting on the SE(3) log error
// [rho; omega], metres and radians) and its weight w_j > 0.
//
// IsotropicPoseSqrtInfo builds L = diag(1/sigma_t x3, 1/sigma_r x3).
// DetectionSqrtInfo turns an L of independent position and rotation errors
// into the L on the log error (see there).
// ValidatePoseComponents rejects what must never reach a Ceres problem:
// non-finite numbers, a non-positive weight, a singular L, a quaternion that
// is not unit within 1e-6 (after which it is normalised by the edges).
#ifndef SYMBA_FACTORS_POSE_COMPONENT_H_
#define SYMBA_FACTORS_POSE_COMPONENT_H_

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/so3.h"

namespace symba {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct PoseComponent {
  Rigid3d T_co;
  Matrix6d sqrt_info = Matrix6d::Identity();
  double weight = 1.0;
};

inline Matrix6d IsotropicPoseSqrtInfo(double sigma_t, double sigma_r) {
  Matrix6d sqrt_info = Matrix6d::Zero();
  sqrt_info.diagonal() << Eigen::Vector3d::Constant(1.0 / sigma_t),
      Eigen::Vector3d::Constant(1.0 / sigma_r);
  return sqrt_info;
}

// A detector's errors of one pose T_co = (R_co, t_co) taken as its position
// error e_t (camera frame, m) and its rotation error omega (camera frame,
// rad; R_measured = Exp(omega) R_co), independent of each other and
// whitened by `independent` = diag(L_t, L_r) (e.g. IsotropicPoseSqrtInfo).
// The edges' log error [rho; omega] = LogSE3(T_co_measured T_co^-1) mixes
// them: to first order
//
//   rho = e_t - omega x t_co,
//
// the rotation error swinging the measured position about the camera by the
// object's distance (5 cm per 3 degrees at 1 m). The square-root
// information on [rho; omega] that whitens [e_t; omega] = [rho + omega x
// t_co; omega] instead:
//
//   L = diag(L_t, L_r) [I  -Hat(t_co); 0  I]     (det L = det L_t det L_r)
//
// with t_co the measured position (the estimate's differs from it at second
// order). A constant matrix per component: the edges' Jacobians and their
// max-mixture normalisation are unchanged.
inline Matrix6d DetectionSqrtInfo(const Matrix6d& independent,
                                  const Eigen::Vector3d& t_co) {
  Matrix6d decouple = Matrix6d::Identity();
  decouple.topRightCorner<3, 3>() = -Hat<double>(t_co);
  return independent * decouple;
}

// Checks a square-root information matrix and a weight of one component.
template <int kRows>
Status ValidateSqrtInfoAndWeight(
    const Eigen::Matrix<double, kRows, kRows>& sqrt_info,
    double weight,
    const std::string& what) {
  if (!sqrt_info.allFinite()) {
    return Status::Error(what + ": square-root information is not finite");
  }
  const double det = sqrt_info.determinant();
  if (!(std::abs(det) > 0.0) || !std::isfinite(std::log(std::abs(det)))) {
    return Status::Error(what + ": square-root information is singular");
  }
  if (!std::isfinite(weight) || !(weight > 0.0)) {
    return Status::Error(what + ": weight must be positive and finite");
  }
  return Status::Ok();
}

inline Status ValidatePoseComponents(
    const std::vector<PoseComponent>& components) {
  if (components.empty()) {
    return Status::Error("a pose mixture needs at least one hypothesis");
  }
  for (size_t j = 0; j < components.size(); ++j) {
    const PoseComponent& c = components[j];
    const std::string what = "hypothesis " + std::to_string(j);
    if (!c.T_co.t.allFinite() || !c.T_co.q.coeffs().allFinite()) {
      return Status::Error(what + ": pose is not finite");
    }
    if (std::abs(c.T_co.q.norm() - 1.0) > 1e-6) {
      return Status::Error(what + ": quaternion is not unit");
    }
    Status status = ValidateSqrtInfoAndWeight<6>(c.sqrt_info, c.weight, what);
    if (!status.ok()) return status;
  }
  return Status::Ok();
}

}  // namespace symba

#endif  // SYMBA_FACTORS_POSE_COMPONENT_H_
