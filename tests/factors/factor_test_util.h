// Helpers shared by the cost-function tests: parameter-block storage for a
// pose, a gradient check on the manifolds of the blocks, and evaluation of a
// cost function into Eigen containers.
#ifndef SYMBA_TESTS_FACTORS_FACTOR_TEST_UTIL_H_
#define SYMBA_TESTS_FACTORS_FACTOR_TEST_UTIL_H_

#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/geometry/rigid3.h"

namespace symba::testing {

// A pose as two Ceres parameter blocks: q [x, y, z, w] and t.
struct PoseBlocks {
  double q[4];
  double t[3];

  explicit PoseBlocks(const Rigid3d& T) {
    Eigen::Map<Eigen::Quaterniond> q_map(q);
    Eigen::Map<Eigen::Vector3d> t_map(t);
    q_map = T.q.normalized();
    t_map = T.t;
  }
  Rigid3d ToRigid() const {
    return Rigid3d(Eigen::Map<const Eigen::Quaterniond>(q),
                   Eigen::Map<const Eigen::Vector3d>(t));
  }
};

// Runs ceres::GradientChecker; on failure `message` holds the details.
// The checker differentiates numerically with Ridders' method, whose first
// step is ridders_relative_initial_step_size * |x| (1e-2 by default). A
// max-mixture is smooth only within one winner's region, so the first step
// is kept to 1e-5: small enough not to cross a decision boundary at a random
// state, large enough for Ridders' extrapolation to stay accurate.
inline bool GradientIsCorrect(
    const ceres::CostFunction& cost,
    const std::vector<const ceres::Manifold*>& manifolds,
    const std::vector<double*>& parameters,
    double relative_precision,
    std::string* message) {
  ceres::NumericDiffOptions numeric_options;
  numeric_options.ridders_relative_initial_step_size = 1e-5;
  ceres::GradientChecker checker(&cost, &manifolds, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  const bool ok =
      checker.Probe(parameters.data(), relative_precision, &results);
  if (!ok) *message = results.error_log;
  return ok;
}

// Residuals and (row-major) Jacobians of `cost` at `parameters`.
struct Evaluation {
  bool ok = false;
  Eigen::VectorXd residuals;
  std::vector<
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
      jacobians;
};

inline Evaluation EvaluateWithJacobians(
    const ceres::CostFunction& cost, const std::vector<double*>& parameters) {
  Evaluation e;
  const int rows = cost.num_residuals();
  e.residuals.resize(rows);
  std::vector<double*> jacobian_ptrs;
  for (int size : cost.parameter_block_sizes()) {
    e.jacobians.emplace_back(rows, size);
  }
  for (auto& J : e.jacobians) jacobian_ptrs.push_back(J.data());
  e.ok = cost.Evaluate(
      parameters.data(), e.residuals.data(), jacobian_ptrs.data());
  return e;
}

}  // namespace symba::testing

#endif  // SYMBA_TESTS_FACTORS_FACTOR_TEST_UTIL_H_
