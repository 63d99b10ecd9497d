// SE(3): exponential and logarithm (docs/method.md, Eq. 3-5).
//
// A twist is the 6-vector xi = [rho; omega] (translation part first, as in
// Sophus): omega is the rotation vector (rad), rho is in metres.
//
//   ExpSE3(xi) = (ExpSO3(omega), V(omega) rho)
//   LogSE3(T)  = [V(omega)^-1 t; omega],  omega = LogSO3(T.q), |omega| <= pi
//
//   V(w)    = I + A(theta) W + B(theta) W^2,       W = Hat(w), theta = |w|
//             A = (1 - cos theta) / theta^2,  B = (theta - sin theta) / theta^3
//   V(w)^-1 = I - W/2 + C(theta) W^2,
//             C = (1 - (theta/2) cot(theta/2)) / theta^2
//
// Near theta = 0 the coefficients use Taylor series in theta^2; C is finite
// for all theta in [0, pi] (C(pi) = 1/pi^2), so the logarithm is stable near
// pi too. Templated on the scalar for ceres::Jet.
#ifndef SYMBA_GEOMETRY_SE3_H_
#define SYMBA_GEOMETRY_SE3_H_

#include <cmath>

#include <Eigen/Core>

#include "symba/geometry/rigid3.h"
#include "symba/geometry/so3.h"

namespace symba {

template <typename T>
using Vector6 = Eigen::Matrix<T, 6, 1>;

// Below this squared angle (rad^2) the V coefficients use Taylor series.
inline constexpr double kSeriesAngleSquared = 1e-4;

// V(omega): the left Jacobian of SO(3), mapping rho to the translation.
template <typename T>
Matrix3<T> SO3LeftJacobian(const Vector3<T>& omega) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T theta_sq = omega.squaredNorm();
  T a;
  T b;
  if (theta_sq < T(kSeriesAngleSquared)) {
    a = T(0.5) - theta_sq / T(24) + theta_sq * theta_sq / T(720);
    b = T(1.0 / 6.0) - theta_sq / T(120) + theta_sq * theta_sq / T(5040);
  } else {
    const T theta = sqrt(theta_sq);
    a = (T(1) - cos(theta)) / theta_sq;
    b = (theta - sin(theta)) / (theta_sq * theta);
  }
  const Matrix3<T> W = Hat(omega);
  return Matrix3<T>::Identity() + a * W + b * (W * W);
}

// V(omega)^-1, valid for |omega| <= pi.
template <typename T>
Matrix3<T> SO3LeftJacobianInverse(const Vector3<T>& omega) {
  using std::sqrt;
  using std::tan;
  const T theta_sq = omega.squaredNorm();
  T c;
  if (theta_sq < T(kSeriesAngleSquared)) {
    c = T(1.0 / 12.0) + theta_sq / T(720) + theta_sq * theta_sq / T(30240);
  } else {
    const T theta = sqrt(theta_sq);
    const T half = T(0.5) * theta;
    c = (T(1) - half / tan(half)) / theta_sq;
  }
  const Matrix3<T> W = Hat(omega);
  return Matrix3<T>::Identity() - T(0.5) * W + c * (W * W);
}

template <typename T>
Rigid3<T> ExpSE3(const Vector6<T>& xi) {
  const Vector3<T> rho = xi.template head<3>();
  const Vector3<T> omega = xi.template tail<3>();
  return Rigid3<T>(ExpSO3(omega), SO3LeftJacobian(omega) * rho);
}

// The logarithm reuses the quaternion's half angle: with q = [w, v] (w >= 0),
// s = |v|, theta/2 = atan2(s, w) and (theta/2) cot(theta/2) = (theta/2) w / s,
// so V^-1 t = t - omega x t / 2 + C omega x (omega x t) needs one atan2 and
// no 3 x 3 matrix (this runs once per mixture component per evaluation).
template <typename T>
Vector6<T> LogSE3(const Rigid3<T>& T_ab) {
  using std::atan2;
  using std::sqrt;
  const bool flip = T_ab.q.w() < T(0);
  const T w = flip ? T(-T_ab.q.w()) : T_ab.q.w();
  const Vector3<T> v = flip ? Vector3<T>(-T_ab.q.vec()) : T_ab.q.vec();
  const T s_sq = v.squaredNorm();
  Vector3<T> omega;
  T c;  // C(theta) of V^-1
  if (s_sq < T(kSmallAngleSquared)) {
    omega = (T(2) / w * (T(1) - s_sq / (T(3) * w * w))) * v;
    const T theta_sq = omega.squaredNorm();
    c = T(1.0 / 12.0) + theta_sq / T(720) + theta_sq * theta_sq / T(30240);
  } else {
    const T s = sqrt(s_sq);
    const T half_theta = atan2(s, w);
    omega = (T(2) * half_theta / s) * v;
    const T theta_sq = T(4) * half_theta * half_theta;
    if (theta_sq < T(kSeriesAngleSquared)) {
      c = T(1.0 / 12.0) + theta_sq / T(720) + theta_sq * theta_sq / T(30240);
    } else {
      c = (T(1) - half_theta * w / s) / theta_sq;
    }
  }
  const Vector3<T> omega_x_t = omega.cross(T_ab.t);
  Vector6<T> xi;
  xi.template head<3>() =
      T_ab.t - T(0.5) * omega_x_t + c * omega.cross(omega_x_t);
  xi.template tail<3>() = omega;
  return xi;
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_SE3_H_
