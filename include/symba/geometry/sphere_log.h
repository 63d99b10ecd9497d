// The logarithm of the unit sphere at a base point, in tangent coordinates
// (docs/method.md, Eq. 10):
//
//   SphereLog(x, y) = theta / |B(x)^T y| * B(x)^T y,
//   theta = atan2(|B(x)^T y|, x.y)   (the angle between x and y, rad)
//
// with B(x) = TangentBasis(x). |SphereLog(x, y)| is the great-circle distance
// from x to y, and the direction is that of y seen from x on the tangent
// plane. Near y = x the factor theta/s uses its series in s^2 (no square root
// of zero, so ceres::Jet derivatives stay finite). At y = -x the direction is
// undefined and (pi, 0) is returned.
#ifndef SYMBA_GEOMETRY_SPHERE_LOG_H_
#define SYMBA_GEOMETRY_SPHERE_LOG_H_

#include <cmath>

#include <Eigen/Core>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/geometry/tangent_basis.h"

namespace symba {

// Tangent coordinates of y at x, in the basis `basis_at_x` of the tangent
// plane at x (pass TangentBasis(x); a caller with a fixed x precomputes it).
template <typename T>
Eigen::Matrix<T, 2, 1> SphereLog(const Vector3<T>& x,
                                 const Eigen::Matrix<T, 3, 2>& basis_at_x,
                                 const Vector3<T>& y) {
  using std::atan2;
  using std::sqrt;
  const Eigen::Matrix<T, 2, 1> w = basis_at_x.transpose() * y;
  const T c = x.dot(y);
  const T s_sq = w.squaredNorm();
  if (c > T(0) && s_sq < T(kSmallAngleSquared) * c * c) {
    // atan(s/c)/s = (1/c) (1 - s^2/(3 c^2) + ...)
    return ((T(1) - s_sq / (T(3) * c * c)) / c) * w;
  }
  if (s_sq <= T(0)) {
    return Eigen::Matrix<T, 2, 1>(T(kPi), T(0));
  }
  const T s = sqrt(s_sq);
  return (atan2(s, c) / s) * w;
}

template <typename T>
Eigen::Matrix<T, 2, 1> SphereLog(const Vector3<T>& x, const Vector3<T>& y) {
  return SphereLog(x, Eigen::Matrix<T, 3, 2>(TangentBasis(x)), y);
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_SPHERE_LOG_H_
