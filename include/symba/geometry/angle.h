// Plane angles: wrapping to (-pi, pi] and the distance between two angles on
// the circle.
//
//   WrapToPi(x) = x - 2 pi k, the representative in (-pi, pi]   (radians)
//   CircularDistance(a, b) = |WrapToPi(a - b)|  in [0, pi]
//
// Templated on the scalar; with ceres::Jet the wrap is a shift by a constant,
// so derivatives pass through unchanged.
#ifndef SYMBA_GEOMETRY_ANGLE_H_
#define SYMBA_GEOMETRY_ANGLE_H_

#include <cmath>

namespace symba {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;

// The representative of `angle` (radians) in (-pi, pi]. Non-finite input is
// returned unchanged (the caller validates input; this never loops).
template <typename T>
T WrapToPi(const T& angle) {
  using std::floor;
  const T k = floor((angle + T(kPi)) / T(kTwoPi));
  T wrapped = angle - T(kTwoPi) * k;
  // floor puts exactly -pi at -pi; the convention here is (-pi, pi].
  if (wrapped <= T(-kPi)) wrapped += T(kTwoPi);
  if (wrapped > T(kPi)) wrapped -= T(kTwoPi);
  return wrapped;
}

// Geodesic distance on the unit circle between two angles, in [0, pi].
inline double CircularDistance(double a, double b) {
  return std::abs(WrapToPi(a - b));
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_ANGLE_H_
