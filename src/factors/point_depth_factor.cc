#include "symba/factors/point_depth_factor.h"

#include <ceres/autodiff_cost_function.h>

namespace symba {

ceres::CostFunction* PointDepthFactor::Create(double depth, double sigma) {
  return new ceres::AutoDiffCostFunction<PointDepthFactor, 1, 4, 3, 3>(
      new PointDepthFactor(depth, sigma));
}

}  // namespace symba
