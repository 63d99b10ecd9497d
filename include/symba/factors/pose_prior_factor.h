// Pose prior factor on one pose (docs/method.md, Eq. 21):
//
//   e = LogSE3(T_prior^-1 * T_wc)      (6: [rho; omega])
//   residual = L e                      (L: 6 x 6 sqrt information)
//
// Parameter blocks: q_wc 4 (Eigen order [x, y, z, w]), t_wc 3.
#ifndef SYMBA_FACTORS_POSE_PRIOR_FACTOR_H_
#define SYMBA_FACTORS_POSE_PRIOR_FACTOR_H_

#include <ceres/cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/se3.h"

namespace symba {

class PosePriorFactor {
 public:
  PosePriorFactor(const Rigid3d& T_prior, const Matrix6d& sqrt_info)
      : T_prior_inverse_(T_prior.Inverse()), sqrt_info_(sqrt_info) {}

  template <typename T>
  bool operator()(const T* q_wc, const T* t_wc, T* residual) const {
    const Rigid3<T> T_wc{Eigen::Map<const Eigen::Quaternion<T>>(q_wc),
                         Eigen::Map<const Vector3<T>>(t_wc)};
    Eigen::Map<Vector6<T>> r(residual);
    r = sqrt_info_.template cast<T>() *
        LogSE3(T_prior_inverse_.template Cast<T>() * T_wc);
    return true;
  }

  // The factor as a Ceres cost function (automatic differentiation), in
  // src/factors/pose_prior_factor.cc: its Jets are compiled once, not in
  // every file that builds a problem.
  static ceres::CostFunction* Create(const Rigid3d& T_prior,
                                     const Matrix6d& sqrt_info);

 private:
  Rigid3d T_prior_inverse_;
  Matrix6d sqrt_info_;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_POSE_PRIOR_FACTOR_H_
