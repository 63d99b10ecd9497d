// Helpers shared by the cost-function tests: parameter-block storage for a
// pose, a gradient check on the manifolds of the blocks, and evaluation of a
// cost function into Eigen containers.
#ifndef SYMBA_TESTS_FACTORS_FACTOR_TEST_UTIL_H_
#define SYMBA_TESTS_FACTORS_FACTOR_TEST_UTIL_H_

#include <algorithm>
#include <string>
#include <vector>

#include <ceres/cost_function.h>
#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/factors/pose_component.h"
#include "symba/geometry/rigid3.h"
#include "test_support/random.h"

namespace symba::testing {

// How PoseBlocks stores the quaternion: normalised, or bit for bit as given
// (for tests that compare the blocks with the pose exactly or hand a factor
// a quaternion of their choosing).
enum class QuaternionStorage { kNormalised, kAsGiven };

// A pose as two Ceres parameter blocks: q in Eigen memory order
// [x, y, z, w] and t.
struct PoseBlocks {
  double q[4];
  double t[3];

  explicit PoseBlocks(
      const Rigid3d& T,
      QuaternionStorage storage = QuaternionStorage::kNormalised) {
    Eigen::Map<Eigen::Quaterniond> q_map(q);
    Eigen::Map<Eigen::Vector3d> t_map(t);
    q_map = storage == QuaternionStorage::kNormalised ? T.q.normalized() : T.q;
    t_map = T.t;
  }
  Rigid3d ToRigid() const {
    return Rigid3d(Eigen::Map<const Eigen::Quaterniond>(q),
                   Eigen::Map<const Eigen::Vector3d>(t));
  }
};

// Checks the analytic Jacobians of `cost` against numeric ones, both in the
// tangent spaces of the blocks' manifolds, with ceres::GradientChecker.
//
// The checker differentiates numerically with Ridders' method, whose first
// step is 2^5 ridders_relative_initial_step_size |x| (Ceres starts five
// halvings above the nominal step; the default factor is 1e-2). A max-mixture
// is smooth only within one winner's region, so the factor is set to 1e-7
// (first step about 3e-6 |x|): small enough not to cross a decision boundary
// at a random state, large enough for Ridders' extrapolation to be accurate.
//
// Ceres flags any entry whose error relative to the entry itself exceeds the
// precision, which fails on roundoff in entries of size ~1e-7 next to
// entries of size ~10. Here a block passes when
//   max |J - J_numeric| <= relative_precision * max(1, max |J_numeric|),
// the same precision measured against the block's scale.
inline bool GradientIsCorrect(
    const ceres::CostFunction& cost,
    const std::vector<const ceres::Manifold*>& manifolds,
    const std::vector<double*>& parameters,
    double relative_precision,
    std::string* message) {
  ceres::NumericDiffOptions numeric_options;
  numeric_options.ridders_relative_initial_step_size = 1e-7;
  ceres::GradientChecker checker(&cost, &manifolds, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(parameters.data(), relative_precision, &results);
  if (!results.return_value) {
    *message = "the cost function failed to evaluate";
    return false;
  }
  bool ok = true;
  for (size_t b = 0; b < results.local_jacobians.size(); ++b) {
    const auto& analytic = results.local_jacobians[b];
    const auto& numeric = results.local_numeric_jacobians[b];
    const double error = (analytic - numeric).cwiseAbs().maxCoeff();
    const double scale = std::max(1.0, numeric.cwiseAbs().maxCoeff());
    if (!(error <= relative_precision * scale)) {
      ok = false;
      *message += "block " + std::to_string(b) + ": max error " +
                  std::to_string(error) + " at scale " + std::to_string(scale) +
                  "\n";
    }
  }
  if (!ok) *message += results.error_log;
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

// Whether two evaluations agree: residuals and each Jacobian block within
// relative_precision * max(1, max |entry of b|) of that block; describes the
// differences in *message.
inline bool EvaluationsAgree(const Evaluation& a,
                             const Evaluation& b,
                             double relative_precision,
                             std::string* message) {
  if (!a.ok || !b.ok || a.jacobians.size() != b.jacobians.size()) {
    *message = "an evaluation failed";
    return false;
  }
  const auto agree =
      [&](const auto& x, const auto& y, const std::string& what) {
        const double scale = std::max(1.0, y.cwiseAbs().maxCoeff());
        const double error = (x - y).cwiseAbs().maxCoeff();
        if (error <= relative_precision * scale) return true;
        *message += what + ": max difference " + std::to_string(error) +
                    " at scale " + std::to_string(scale) + "\n";
        return false;
      };
  bool ok = agree(a.residuals, b.residuals, "residuals");
  for (size_t k = 0; k < a.jacobians.size(); ++k) {
    ok = agree(a.jacobians[k], b.jacobians[k], "block " + std::to_string(k)) &&
         ok;
  }
  return ok;
}

// A component of the pose edges' gradient checks at T_co: sigmas drawn from
// [0.02, 0.2] m and [0.05, 0.3] rad, a weight from [0.1, 1]. On every other
// ten trials its errors are taken as independent (DetectionSqrtInfo, a full
// upper-right block), so each kind of state a block of ten draws meets both
// informations.
inline PoseComponent RandomGradientCheckComponent(const Rigid3d& T_co,
                                                  int trial,
                                                  TestRandom* random) {
  Matrix6d sqrt_info = IsotropicPoseSqrtInfo(random->Uniform(0.02, 0.2),
                                             random->Uniform(0.05, 0.3));
  if ((trial / 10) % 2 == 1) sqrt_info = DetectionSqrtInfo(sqrt_info, T_co.t);
  return {T_co, sqrt_info, random->Uniform(0.1, 1.0)};
}

}  // namespace symba::testing

#endif  // SYMBA_TESTS_FACTORS_FACTOR_TEST_UTIL_H_
