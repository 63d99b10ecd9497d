// Plane angles: wrapping to (-pi, pi] and the distance between two angles on
// the circle.
//
//   WrapToPi(x) = x - 2 pi k, the representative in (-pi, pi]   (radians)
//   CircularDistance(a, b) = |WrapToPi(a - b)|  in [0, pi]
//
// The reduction is std::remainder by 2 pi (the double kTwoPi), which is exact
// for every finite input, so the result is in (-pi, pi] however large x is,
// and x in (-pi, pi] comes back bit for bit. For ceres::Jet the value wraps
// exactly as the double does and the derivatives pass through unchanged (the
// wrap is a shift by a constant).
#ifndef SYMBA_GEOMETRY_ANGLE_H_
#define SYMBA_GEOMETRY_ANGLE_H_

#include <cmath>

#include <ceres/jet.h>

#include "symba/geometry/pi.h"

namespace symba {

// The representative of `angle` (radians) in (-pi, pi]. Non-finite input is
// returned unchanged (the caller validates input; this never loops).
template <typename T>
T WrapToPi(const T& angle) {
  using std::isfinite;
  using std::remainder;
  if (!isfinite(angle)) return angle;
  // angle - n 2pi for the integer n nearest angle / 2pi, computed exactly;
  // it is in [-pi, pi], and -pi (a tie) belongs at +pi.
  const T wrapped = remainder(angle, T(kTwoPi));
  return wrapped <= T(-kPi) ? T(kPi) : wrapped;
}

// ceres::Jet: wraps the value like the scalar, keeps the derivatives.
template <typename T, int N>
ceres::Jet<T, N> WrapToPi(const ceres::Jet<T, N>& angle) {
  ceres::Jet<T, N> wrapped = angle;
  wrapped.a = WrapToPi(angle.a);
  return wrapped;
}

// Geodesic distance on the unit circle between two angles, in [0, pi].
inline double CircularDistance(double a, double b) {
  return std::abs(WrapToPi(a - b));
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_ANGLE_H_
