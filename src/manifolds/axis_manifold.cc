#include "symba/manifolds/axis_manifold.h"

#include <cmath>

#include <Eigen/Core>

#include "symba/geometry/so3.h"
#include "symba/geometry/sphere_log.h"
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
  Eigen::Map<Eigen::Vector2d> y_minus_x(y_minus_x_ptr);
  y_minus_x = SphereLog(x, Eigen::Vector3d(ConstAmbient(y_ptr)));
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
