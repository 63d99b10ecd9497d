// Checks a function's derivatives through ceres::Jet against numeric central
// differences.
//
// The function under test is a generic callable
//   f(const Eigen::Matrix<T, kIn, 1>& x) -> Eigen::Matrix<T, kOut, 1>
// called with T = double and T = ceres::Jet<double, kIn>. A generic lambda
// taking `const auto& x` and using `typename std::decay_t<decltype(x)>::Scalar`
// as T is the usual form.
//
//   JetJacobian(f, x)            d f / d x by forward-mode automatic
//                                differentiation (one Jet evaluation)
//   NumericJacobian(f, x, h)     (f(x + h e_i) - f(x - h e_i)) / 2h, column i
//   JetMatchesNumeric(f, x, tol, h)
//                                an AssertionResult: the Jet value equals
//                                f(x) (to 1e-12 relative: the two scalar
//                                types may round differently), every Jet
//                                derivative is finite, and
//                                max |J_jet - J_numeric| <= tol * max(1,
//                                max |J_jet|)
//
// The central difference has error about h^2 |f'''| / 6 + eps |f| / h, so the
// default h = 1e-6 gives about 1e-10 for well-scaled functions; a tolerance of
// 1e-7 is loose enough for that and tight enough that a wrong derivative
// (wrong sign, missing term, a branch that drops the dependence) fails.
#ifndef SYMBA_TESTS_TEST_SUPPORT_JET_CHECK_H_
#define SYMBA_TESTS_TEST_SUPPORT_JET_CHECK_H_

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>

#include <ceres/jet.h>
#include <gtest/gtest.h>
#include <Eigen/Core>

namespace symba::testing {

// The output type of f for scalar T, checked to be a fixed-size column.
template <typename Function, typename T, int kIn>
using JetCheckOutput = std::decay_t<decltype(std::declval<const Function&>()(
    std::declval<const Eigen::Matrix<T, kIn, 1>&>()))>;

template <typename Function, int kIn>
inline constexpr int kJetCheckOutputSize =
    JetCheckOutput<Function, double, kIn>::RowsAtCompileTime;

// d f / d x at x through ceres::Jet<double, kIn>.
template <typename Function, int kIn>
Eigen::Matrix<double, kJetCheckOutputSize<Function, kIn>, kIn> JetJacobian(
    const Function& f, const Eigen::Matrix<double, kIn, 1>& x) {
  using Jet = ceres::Jet<double, kIn>;
  constexpr int kOut = kJetCheckOutputSize<Function, kIn>;
  static_assert(kOut > 0, "f must return a fixed-size column vector");
  Eigen::Matrix<Jet, kIn, 1> x_jet;
  for (int i = 0; i < kIn; ++i) x_jet(i) = Jet(x(i), i);
  const Eigen::Matrix<Jet, kOut, 1> y = f(x_jet);
  Eigen::Matrix<double, kOut, kIn> jacobian;
  for (int r = 0; r < kOut; ++r) jacobian.row(r) = y(r).v.transpose();
  return jacobian;
}

// d f / d x at x by central differences with step `step`.
template <typename Function, int kIn>
Eigen::Matrix<double, kJetCheckOutputSize<Function, kIn>, kIn> NumericJacobian(
    const Function& f, const Eigen::Matrix<double, kIn, 1>& x, double step) {
  constexpr int kOut = kJetCheckOutputSize<Function, kIn>;
  Eigen::Matrix<double, kOut, kIn> jacobian;
  for (int i = 0; i < kIn; ++i) {
    Eigen::Matrix<double, kIn, 1> plus = x;
    Eigen::Matrix<double, kIn, 1> minus = x;
    plus(i) += step;
    minus(i) -= step;
    const Eigen::Matrix<double, kOut, 1> f_plus = f(plus);
    const Eigen::Matrix<double, kOut, 1> f_minus = f(minus);
    // The step actually taken (x +- step is rounded).
    jacobian.col(i) = (f_plus - f_minus) / (plus(i) - minus(i));
  }
  return jacobian;
}

// Passes when f's Jet value matches its double value, its Jet Jacobian is
// finite, and that Jacobian agrees with central differences to `tolerance`
// (absolute, or relative to the largest entry when that exceeds 1).
template <typename Function, int kIn>
::testing::AssertionResult JetMatchesNumeric(
    const Function& f,
    const Eigen::Matrix<double, kIn, 1>& x,
    double tolerance,
    double step = 1e-6) {
  using Jet = ceres::Jet<double, kIn>;
  constexpr int kOut = kJetCheckOutputSize<Function, kIn>;
  static_assert(std::is_same_v<JetCheckOutput<Function, double, kIn>,
                               Eigen::Matrix<double, kOut, 1>>,
                "f must return Eigen::Matrix<T, kOut, 1>");

  const Eigen::IOFormat format(Eigen::FullPrecision, 0, ", ", "\n", "  [", "]");
  const Eigen::Matrix<double, kOut, 1> value = f(x);
  Eigen::Matrix<Jet, kIn, 1> x_jet;
  for (int i = 0; i < kIn; ++i) x_jet(i) = Jet(x(i), i);
  const Eigen::Matrix<Jet, kOut, 1> y = f(x_jet);
  for (int r = 0; r < kOut; ++r) {
    const double value_scale = std::max(1.0, std::abs(value(r)));
    if (!(std::abs(y(r).a - value(r)) <= 1e-12 * value_scale)) {
      return ::testing::AssertionFailure()
             << "Jet value " << y(r).a << " != double value " << value(r)
             << " in output " << r << " at x =\n"
             << x.transpose().format(format);
    }
  }

  const Eigen::Matrix<double, kOut, kIn> jet = JetJacobian(f, x);
  const Eigen::Matrix<double, kOut, kIn> numeric = NumericJacobian(f, x, step);
  std::ostringstream details;
  details << " at x =\n"
          << x.transpose().format(format) << "\nJet Jacobian:\n"
          << jet.format(format) << "\nnumeric Jacobian (step " << step << "):\n"
          << numeric.format(format);
  if (!jet.allFinite()) {
    return ::testing::AssertionFailure()
           << "non-finite Jet Jacobian" << details.str();
  }
  if (!numeric.allFinite()) {
    return ::testing::AssertionFailure()
           << "non-finite numeric Jacobian" << details.str();
  }
  const double scale = std::max(1.0, jet.cwiseAbs().maxCoeff());
  const double error = (jet - numeric).cwiseAbs().maxCoeff();
  if (error > tolerance * scale) {
    return ::testing::AssertionFailure()
           << "max |J_jet - J_numeric| = " << error << " > " << tolerance
           << " * " << scale << details.str();
  }
  return ::testing::AssertionSuccess();
}

}  // namespace symba::testing

#endif  // SYMBA_TESTS_TEST_SUPPORT_JET_CHECK_H_
