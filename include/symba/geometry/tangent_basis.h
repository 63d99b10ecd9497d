// An orthonormal basis of the tangent plane of the unit sphere at x.
//
//   TangentBasis(x) = [b1 b2] (3 x 2), with b1 . x = b2 . x = b1 . b2 = 0,
//   |b1| = |b2| = 1 and (b1, b2, x) right-handed.
//
// The construction (Frisvad's, in the branch-on-sign form of Duff et al.,
// "Building an Orthonormal Basis, Revisited", JCGT 2017) has no singular
// point: it is defined and well conditioned at both poles and on the equator.
// It switches branch at x_z = 0, so the basis is not continuous in x there;
// every use here fixes x while the tangent coordinate varies, which is all a
// manifold's Plus/Minus and a tangent-plane residual need.
#ifndef SYMBA_GEOMETRY_TANGENT_BASIS_H_
#define SYMBA_GEOMETRY_TANGENT_BASIS_H_

#include <Eigen/Core>

#include "symba/geometry/so3.h"

namespace symba {

template <typename T>
Eigen::Matrix<T, 3, 2> TangentBasis(const Vector3<T>& x) {
  const T sign = x.z() >= T(0) ? T(1) : T(-1);
  const T a = T(-1) / (sign + x.z());
  const T b = x.x() * x.y() * a;
  Eigen::Matrix<T, 3, 2> basis;
  basis.col(0) << T(1) + sign * x.x() * x.x() * a, sign * b, -sign * x.x();
  basis.col(1) << b, sign + x.y() * x.y() * a, -x.y();
  return basis;
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_TANGENT_BASIS_H_
