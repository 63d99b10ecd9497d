// Pinhole reprojection of a map point (the paper's E_reproj;
// docs/method.md, Eq. 22):
//
//   p_c = R_wc^T (p_w - t_wc)                        point in the camera (m)
//   u   = [fx p_c.x / p_c.z + cx, fy p_c.y / p_c.z + cy]   (pixels)
//   residual = L (u - uv_measured)                    (L: 2 x 2, 1/pixel)
//
// Camera frame: x right, y down, z forward. A point at or behind the camera
// (p_c.z <= kMinDepth) cannot be projected: Evaluate returns false, which
// Ceres treats as an invalid step.
// Parameter blocks: q_wc 4 (Eigen order [x, y, z, w]), t_wc 3, p_w 3.
#ifndef SYMBA_FACTORS_REPROJECTION_FACTOR_H_
#define SYMBA_FACTORS_REPROJECTION_FACTOR_H_

#include <ceres/cost_function.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/geometry/pinhole_intrinsics.h"
#include "symba/geometry/so3.h"

namespace symba {

class ReprojectionFactor {
 public:
  static constexpr double kMinDepth = 1e-6;  // m

  ReprojectionFactor(const PinholeIntrinsics& intrinsics,
                     const Eigen::Vector2d& uv_measured,
                     const Eigen::Matrix2d& sqrt_info)
      : intrinsics_(intrinsics),
        uv_measured_(uv_measured),
        sqrt_info_(sqrt_info) {}

  template <typename T>
  bool operator()(const T* q_wc,
                  const T* t_wc,
                  const T* p_w,
                  T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> R_wc(q_wc);
    const Vector3<T> p_c =
        R_wc.conjugate() * (Eigen::Map<const Vector3<T>>(p_w) -
                            Eigen::Map<const Vector3<T>>(t_wc));
    if (p_c.z() <= T(kMinDepth)) return false;
    const Eigen::Matrix<T, 2, 1> uv(
        T(intrinsics_.fx) * p_c.x() / p_c.z() + T(intrinsics_.cx),
        T(intrinsics_.fy) * p_c.y() / p_c.z() + T(intrinsics_.cy));
    Eigen::Map<Eigen::Matrix<T, 2, 1>> r(residual);
    r = sqrt_info_.template cast<T>() * (uv - uv_measured_.template cast<T>());
    return true;
  }

  // The factor as a Ceres cost function (automatic differentiation), in
  // src/factors/reprojection_factor.cc: its Jets are compiled once, not in
  // every file that builds a problem.
  static ceres::CostFunction* Create(const PinholeIntrinsics& intrinsics,
                                     const Eigen::Vector2d& uv_measured,
                                     const Eigen::Matrix2d& sqrt_info);

 private:
  PinholeIntrinsics intrinsics_;
  Eigen::Vector2d uv_measured_;
  Eigen::Matrix2d sqrt_info_;
};

}  // namespace symba

#endif  // SYMBA_FACTORS_REPROJECTION_FACTOR_H_
