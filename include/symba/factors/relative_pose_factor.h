// Relative pose (odometry) factor between two keyframes a and b
// (docs/method.md, Eq. 20):
//
//   e = LogSE3(T_ab_meas^-1 * T_wa^-1 * T_wb)     (6: [rho; omega])
//   residual = L e                                 (L: 6 x 6 sqrt information)
//
// T_ab_meas is the measured pose of b in a's frame (the log format's
// odometry T = T_{prev,cur}). Zero when the estimate reproduces it.
// Parameter blocks: q_wa 4, t_wa 3, q_wb 4, t_wb 3 (Eigen quaternion order).
#ifndef SYMBA_FACTORS_RELATIVE_POSE_FACTOR_H_
#define SYMBA_FACTORS_RELATIVE_POSE_FACTOR_H_

#include <ceres/cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"
#include "symba/geometry/se3.h"

namespace symba {

class RelativePoseFactor {
 public:
  RelativePoseFactor(const Rigid3d& T_ab_measured, const Matrix6d& sqrt_info)
      : T_ba_measured_(T_ab_measured.Inverse()), sqrt_info_(sqrt_info) {}

  template <typename T>
  bool operator()(const T* q_wa,
                  const T* t_wa,
                  const T* q_wb,
                  const T* t_wb,
                  T* residual) const {
    const Rigid3<T> T_wa{Eigen::Map<const Eigen::Quaternion<T>>(q_wa),
                         Eigen::Map<const Vector3<T>>(t_wa)};
    const Rigid3<T> T_wb{Eigen::Map<const Eigen::Quaternion<T>>(q_wb),
                         Eigen::Map<const Vector3<T>>(t_wb)};
    const Rigid3<T> delta =
        T_ba_measured_.template Cast<T>() * (T_wa.Inverse() * T_wb);
    Eigen::Map<Vector6<T>> r(residual);
    r = sqrt_info_.template cast<T>() * LogSE3(delta);
    return true;
  }

  // The factor as a Ceres cost function (automatic differentiation), in
  // src/factors/relative_pose_factor.cc: its Jets are compiled once, not in
  // every file that builds a problem.
  static ceres::CostFunction* Create(const Rigid3d& T_ab_measured,
                                     const Matrix6d& sqrt_info);

 private:
  Rigid3d T_ba_measured_;
  Matrix6d sqrt_info_;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_RELATIVE_POSE_FACTOR_H_
