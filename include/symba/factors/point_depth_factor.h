// Measured depth of a map point, as an RGB-D camera gives it
// (docs/method.md, Eq. 23):
//
//   p_c = R_wc^T (p_w - t_wc)         point in the camera (m)
//   residual = (p_c.z - depth) / sigma      (1, sigma in m)
//
// Reprojection (Eq. 22) alone fixes a point's direction but not its
// distance; with depth, a point observed from several keyframes also fixes
// the scale of the camera motion between them.
// Parameter blocks: q_wc 4 (Eigen order [x, y, z, w]), t_wc 3, p_w 3.
#ifndef SYMBA_FACTORS_POINT_DEPTH_FACTOR_H_
#define SYMBA_FACTORS_POINT_DEPTH_FACTOR_H_

#include <ceres/cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/geometry/so3.h"

namespace symba {

class PointDepthFactor {
 public:
  PointDepthFactor(double depth, double sigma)
      : depth_(depth), inverse_sigma_(1.0 / sigma) {}

  template <typename T>
  bool operator()(const T* q_wc,
                  const T* t_wc,
                  const T* p_w,
                  T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> R_wc(q_wc);
    const Vector3<T> p_c =
        R_wc.conjugate() * (Eigen::Map<const Vector3<T>>(p_w) -
                            Eigen::Map<const Vector3<T>>(t_wc));
    residual[0] = (p_c.z() - T(depth_)) * T(inverse_sigma_);
    return true;
  }

  // `depth` and `sigma` must be positive and finite (the backend validates
  // its input).
  // The factor as a Ceres cost function (automatic differentiation), in
  // src/factors/point_depth_factor.cc: its Jets are compiled once, not in
  // every file that builds a problem.
  static ceres::CostFunction* Create(double depth, double sigma);

 private:
  double depth_;
  double inverse_sigma_;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_POINT_DEPTH_FACTOR_H_
