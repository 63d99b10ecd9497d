#include "symba/manifolds/axis_manifold.h"

#include <cmath>

#include <Eigen/Core>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/tangent_basis.h"

namespace symba {
namespace {

using ConstAmbient = Eigen::Map<const Eigen::Vector3d>;
using ConstTangent = Eigen::Map<const Eigen::Vector2d>;

}  // namespace

bool AxisManifold::Plus(const double* x_ptr,
                        const double* delta_ptr,
                        double* x_plus_delta_ptr) const {
  const Eigen::Vector3d x = ConstAmbient(x_ptr).normalized();
  const Eigen::Vector2d delta = ConstTangent(delta_ptr);
  const double theta_sq = delta.squaredNorm();
  double sinc;  // sin(theta) / theta
  double cos_theta;
  if (theta_sq < kSmallAngleSquared) {
    sinc = 1.0 - theta_sq / 6.0;
    cos_theta = 1.0 - 0.5 * theta_sq;
  } else {
    const double theta = std::sqrt(theta_sq);
    sinc = std::sin(theta) / theta;
    cos_theta = std::cos(theta);
  }
  const Eigen::Vector3d y = cos_theta * x + sinc * (TangentBasis(x) * delta);
  const double norm = y.norm();
  if (!(norm > 0.0) || !std::isfinite(norm)) return false;
  Eigen::Map<Eigen::Vector3d> x_plus_delta(x_plus_delta_ptr);
  x_plus_delta = y / norm;
  return true;
}

bool AxisManifold::PlusJacobian(const double* x_ptr,
                                double* jacobian_ptr) const {
  const Eigen::Vector3d x = ConstAmbient(x_ptr).normalized();
  Eigen::Map<Eigen::Matrix<double, 3, 2, Eigen::RowMajor>> jacobian(
      jacobian_ptr);
  jacobian = TangentBasis(x);
  return true;
}

bool AxisManifold::Minus(const double* y_ptr,
                         const double* x_ptr,
                         double* y_minus_x_ptr) const {
  const Eigen::Vector3d x = ConstAmbient(x_ptr).normalized();
  const Eigen::Vector3d y = ConstAmbient(y_ptr);
  const Eigen::Vector2d w = TangentBasis(x).transpose() * y;
  const double c = x.dot(y);
  const double s_sq = w.squaredNorm();
  Eigen::Map<Eigen::Vector2d> y_minus_x(y_minus_x_ptr);
  if (s_sq == 0.0) {
    // y = +x gives 0; y = -x is a half-turn in an arbitrary (fixed) direction.
    y_minus_x = c >= 0.0 ? Eigen::Vector2d::Zero() : Eigen::Vector2d(kPi, 0.0);
    return true;
  }
  double factor;  // theta / s, theta = atan2(s, c)
  if (c > 0.0 && s_sq < kSmallAngleSquared * c * c) {
    factor = (1.0 - s_sq / (3.0 * c * c)) / c;
  } else {
    const double s = std::sqrt(s_sq);
    factor = std::atan2(s, c) / s;
  }
  y_minus_x = factor * w;
  return true;
}

bool AxisManifold::MinusJacobian(const double* x_ptr,
                                 double* jacobian_ptr) const {
  const Eigen::Vector3d x = ConstAmbient(x_ptr).normalized();
  Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> jacobian(
      jacobian_ptr);
  jacobian = TangentBasis(x).transpose();
  return true;
}

}  // namespace symba
