// AxisManifold: the unit sphere S^2 as a ceres::Manifold for a symmetry axis
// (ambient size 3: the axis [x, y, z]; tangent size 2) (docs/method.md,
// Eq. 9-10).
//
//   Plus(x, d)  = cos(|d|) x + sin(|d|) / |d| * B(x) d     (then normalised)
//   Minus(y, x) = theta / |B(x)^T y| * B(x)^T y,
//                 theta = atan2(|B(x)^T y|, x.y)
//
// B(x) is TangentBasis(x) (symba/geometry/tangent_basis.h), an orthonormal
// basis of the tangent plane at x that is defined and well conditioned at
// every x, both poles and the equator included. Plus is the exact exponential
// map of the sphere, so a tangent step of norm r moves the axis by r radians
// along a great circle and tangent coordinates are in radians.
//
// Invariants (checked by tests with ceres/manifold_test_utils.h):
//   Plus(x, 0) = x,  Minus(x, x) = 0,
//   Minus(Plus(x, d), x) = d    for |d| < pi,
//   Plus(x, Minus(y, x)) = y    for y != -x.
//   PlusJacobian(x) = B(x) (3 x 2), MinusJacobian(x) = B(x)^T (2 x 3), both
//   row-major as Ceres expects.
//
// Why not ceres::SphereManifold<3>: its Plus moves the point by |d|/2 rather
// than |d| (tangent units are half-radians, which would distort every axis
// prior and tangent-plane residual that is stated in radians), and its
// Householder basis is built by a helper in Ceres's internal namespace that
// is not part of the public API. The manifold here is the plain exponential
// map with a documented public basis that residuals can share.
#ifndef SYMBA_MANIFOLDS_AXIS_MANIFOLD_H_
#define SYMBA_MANIFOLDS_AXIS_MANIFOLD_H_

#include <ceres/manifold.h>

namespace symba {

class AxisManifold final : public ceres::Manifold {
 public:
  static constexpr int kAmbientSize = 3;
  static constexpr int kTangentSize = 2;

  int AmbientSize() const override { return kAmbientSize; }
  int TangentSize() const override { return kTangentSize; }

  bool Plus(const double* x,
            const double* delta,
            double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y,
             const double* x,
             double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace symba

#endif  // SYMBA_MANIFOLDS_AXIS_MANIFOLD_H_
