#include "symba/factors/pose_prior_factor.h"

#include <ceres/autodiff_cost_function.h>

namespace symba {

ceres::CostFunction* PosePriorFactor::Create(const Rigid3d& T_prior,
                                             const Matrix6d& sqrt_info) {
  return new ceres::AutoDiffCostFunction<PosePriorFactor, 6, 4, 3>(
      new PosePriorFactor(T_prior, sqrt_info));
}

}  // namespace symba
