// Swing-twist decomposition about an axis, and the minimal rotation between
// two unit vectors (docs/method.md, Eq. 6-8).
//
// For a unit quaternion q = [w, v] and a unit axis a:
//   twist = [w, (v.a) a] / |[w, v.a]|      (rotation about a)
//   swing = q twist^-1                      (rotation about an axis _|_ a)
//   q     = swing * twist
//   TwistAngle(q, a) = 2 atan2(v.a, w), wrapped to (-pi, pi]   (signed, rad)
// The sign is that of the right-hand rule about a: rotating by +90 deg and
// by -90 deg about a give +pi/2 and -pi/2 (the unsigned |log q| would fold
// them together). The twist is undefined when w = v.a = 0 (a half-turn about
// an axis perpendicular to a); there the twist is the identity, angle 0.
//
//   MinimalRotation(u, v) = the rotation of least angle taking unit u to
//                           unit v: axis u x v / |u x v|, angle acos(u.v)
//                         = [1 + u.v, u x v] / |.|              (quaternion)
//   evaluated as [|u + v|^2 / 2, u x (u + v)] / |.|
//   (equal for unit u, v; free of cancellation as v -> -u, where u + v is
//   computed exactly, so q * u = v to rounding even 1e-13 rad from
//   antiparallel). Only for u + v = 0 (|u + v|^2 < 2e-100) is it a half-turn
//   about an axis perpendicular to u (any one: the choice is deterministic,
//   not unique).
#ifndef SYMBA_GEOMETRY_SWING_TWIST_H_
#define SYMBA_GEOMETRY_SWING_TWIST_H_

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"

namespace symba {

template <typename T>
struct SwingTwist {
  Eigen::Quaternion<T> swing;
  Eigen::Quaternion<T> twist;
  T twist_angle;  // signed, (-pi, pi], right-hand rule about the axis
};

// Decomposes unit `q` as swing * twist with twist about the unit `axis`.
template <typename T>
SwingTwist<T> DecomposeSwingTwist(const Eigen::Quaternion<T>& q,
                                  const Vector3<T>& axis) {
  using std::atan2;
  using std::sqrt;
  // q and -q are one rotation; w >= 0 keeps the twist angle in [-pi, pi].
  const bool flip = q.w() < T(0);
  const T w = flip ? T(-q.w()) : q.w();
  const T p = flip ? T(-q.vec().dot(axis)) : T(q.vec().dot(axis));
  const T norm_sq = w * w + p * p;
  SwingTwist<T> result;
  if (norm_sq < T(1e-24)) {
    result.twist = Eigen::Quaternion<T>::Identity();
    result.twist_angle = T(0);
  } else {
    const T norm = sqrt(norm_sq);
    const Vector3<T> twist_vec = (p / norm) * axis;
    result.twist = Eigen::Quaternion<T>(
        w / norm, twist_vec.x(), twist_vec.y(), twist_vec.z());
    result.twist_angle = WrapToPi(T(2) * atan2(p, w));
  }
  result.swing = q * result.twist.conjugate();
  return result;
}

// Signed twist angle of unit `q` about unit `axis`, in (-pi, pi].
template <typename T>
T TwistAngle(const Eigen::Quaternion<T>& q, const Vector3<T>& axis) {
  return DecomposeSwingTwist(q, axis).twist_angle;
}

// A unit vector perpendicular to unit `u` (deterministic).
template <typename T>
Vector3<T> AnyPerpendicular(const Vector3<T>& u) {
  using std::abs;
  // Cross with the coordinate axis least aligned with u.
  Vector3<T> e = Vector3<T>::Zero();
  if (abs(u.x()) <= abs(u.y()) && abs(u.x()) <= abs(u.z())) {
    e.x() = T(1);
  } else if (abs(u.y()) <= abs(u.z())) {
    e.y() = T(1);
  } else {
    e.z() = T(1);
  }
  return u.cross(e).normalized();
}

// The minimal rotation q with q * from = to, for unit `from` and `to`.
template <typename T>
Eigen::Quaternion<T> MinimalRotation(const Vector3<T>& from,
                                     const Vector3<T>& to) {
  // 1 + u.v, computed as such, loses its digits to cancellation near v = -u;
  // |u + v|^2 / 2 and u x (u + v) do not (u + v is exact there).
  const Vector3<T> sum = from + to;
  const T real = T(0.5) * sum.squaredNorm();
  if (real < T(1e-100)) {
    const Vector3<T> axis = AnyPerpendicular(from);
    return Eigen::Quaternion<T>(T(0), axis.x(), axis.y(), axis.z());
  }
  const Vector3<T> imag = from.cross(sum);  // = from x to
  Eigen::Quaternion<T> q(real, imag.x(), imag.y(), imag.z());
  q.normalize();
  return q;
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_SWING_TWIST_H_
