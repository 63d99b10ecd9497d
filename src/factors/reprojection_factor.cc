#include "symba/factors/reprojection_factor.h"

#include <ceres/autodiff_cost_function.h>

namespace symba {

ceres::CostFunction* ReprojectionFactor::Create(
    const PinholeIntrinsics& intrinsics,
    const Eigen::Vector2d& uv_measured,
    const Eigen::Matrix2d& sqrt_info) {
  return new ceres::AutoDiffCostFunction<ReprojectionFactor, 2, 4, 3, 3>(
      new ReprojectionFactor(intrinsics, uv_measured, sqrt_info));
}

}  // namespace symba
