// SO(3): hat operator, exponential and logarithm (docs/method.md, Eq. 1-2).
//
//   Hat(w) v = w x v
//   ExpSO3(w)  = unit quaternion [cos(|w|/2), sin(|w|/2) w/|w|]   (rotation by
//                |w| radians about w/|w|)
//   LogSO3(q)  = w with ExpSO3(w) = q and |w| in [0, pi]
//
// Quaternions are Eigen::Quaternion<T> (Hamilton, coefficients stored as
// x, y, z, w in memory). Everything is templated on the scalar so that
// ceres::Jet flows through. Near the identity both maps switch to Taylor
// series in |w|^2 (no square root of zero, so Jet derivatives stay finite);
// near pi the logarithm uses atan2 on the quaternion, which is well
// conditioned there. LogSO3 picks the sign of q with w >= 0, so a rotation by
// exactly pi returns one of its two equal-norm logarithms.
#ifndef SYMBA_GEOMETRY_SO3_H_
#define SYMBA_GEOMETRY_SO3_H_

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace symba {

template <typename T>
using Vector3 = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Matrix3 = Eigen::Matrix<T, 3, 3>;

// Below this squared angle (rad^2) exp and log use their Taylor series.
inline constexpr double kSmallAngleSquared = 1e-8;

template <typename T>
Matrix3<T> Hat(const Vector3<T>& w) {
  Matrix3<T> W;
  W << T(0), -w.z(), w.y(),  //
      w.z(), T(0), -w.x(),   //
      -w.y(), w.x(), T(0);
  return W;
}

// Unit quaternion of the rotation vector `omega` (radians).
template <typename T>
Eigen::Quaternion<T> ExpSO3(const Vector3<T>& omega) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T theta_sq = omega.squaredNorm();
  T real;
  T imag_factor;  // sin(theta/2) / theta
  if (theta_sq < T(kSmallAngleSquared)) {
    real = T(1) - theta_sq / T(8) + theta_sq * theta_sq / T(384);
    imag_factor = T(0.5) - theta_sq / T(48) + theta_sq * theta_sq / T(3840);
  } else {
    const T theta = sqrt(theta_sq);
    const T half = T(0.5) * theta;
    real = cos(half);
    imag_factor = sin(half) / theta;
  }
  const Vector3<T> imag = imag_factor * omega;
  return Eigen::Quaternion<T>(real, imag.x(), imag.y(), imag.z());
}

// Rotation vector of the unit quaternion `q`, with norm in [0, pi].
template <typename T>
Vector3<T> LogSO3(const Eigen::Quaternion<T>& q) {
  using std::atan2;
  using std::sqrt;
  // q and -q are the same rotation; the one with w >= 0 has angle <= pi.
  const bool flip = q.w() < T(0);
  const T w = flip ? T(-q.w()) : q.w();
  const Vector3<T> v = flip ? Vector3<T>(-q.vec()) : Vector3<T>(q.vec());
  const T s_sq = v.squaredNorm();
  T factor;  // theta / |v|, with theta = 2 atan2(|v|, w)
  if (s_sq < T(kSmallAngleSquared)) {
    // 2 atan(s/w)/s = (2/w) (1 - s^2/(3 w^2) + s^4/(5 w^4) - ...)
    const T w_sq = w * w;
    factor = T(2) / w * (T(1) - s_sq / (T(3) * w_sq));
  } else {
    const T s = sqrt(s_sq);
    factor = T(2) * atan2(s, w) / s;
  }
  return factor * v;
}

// Rotation vector of the rotation matrix `R` (assumed orthonormal, det +1).
template <typename T>
Vector3<T> LogSO3(const Matrix3<T>& R) {
  return LogSO3(Eigen::Quaternion<T>(R));
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_SO3_H_
