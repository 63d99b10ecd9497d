#include "symba/factors/relative_pose_factor.h"

#include <ceres/autodiff_cost_function.h>

namespace symba {

ceres::CostFunction* RelativePoseFactor::Create(const Rigid3d& T_ab_measured,
                                                const Matrix6d& sqrt_info) {
  return new ceres::AutoDiffCostFunction<RelativePoseFactor, 6, 4, 3, 4, 3>(
      new RelativePoseFactor(T_ab_measured, sqrt_info));
}

}  // namespace symba
