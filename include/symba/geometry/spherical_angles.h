// The paper's spherical angles of a unit axis (paper Sec. V, f(phi, psi)):
//
//   a = f(phi, psi) = [sin(phi) cos(psi), sin(phi) sin(psi), cos(phi)]
//   phi in [0, pi]   polar angle from +z      (rad)
//   psi in (-pi, pi] azimuth from +x toward +y (rad)
//
// f^-1 is singular at the poles (a = +-z: psi is undefined and returned as
// 0). On the half-plane x < 0, y = -0 atan2 gives -pi; that is returned as
// +pi, so psi stays in (-pi, pi]. symba optimises axes on the
// singularity-free AxisManifold instead; these functions state the paper's
// parameterisation and are exercised only by their tests.
#ifndef SYMBA_GEOMETRY_SPHERICAL_ANGLES_H_
#define SYMBA_GEOMETRY_SPHERICAL_ANGLES_H_

#include <cmath>

#include <Eigen/Core>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"

namespace symba {

template <typename T>
struct SphericalAngles {
  T phi;  // polar angle, [0, pi]
  T psi;  // azimuth, (-pi, pi]
};

template <typename T>
Vector3<T> UnitVectorFromSpherical(const T& phi, const T& psi) {
  using std::cos;
  using std::sin;
  return Vector3<T>(sin(phi) * cos(psi), sin(phi) * sin(psi), cos(phi));
}

// Spherical angles of a unit (or any non-zero) vector.
template <typename T>
SphericalAngles<T> SphericalFromUnitVector(const Vector3<T>& a) {
  using std::atan2;
  using std::sqrt;
  const T rho_sq = a.x() * a.x() + a.y() * a.y();
  SphericalAngles<T> angles;
  if (rho_sq <= T(0)) {
    angles.phi = a.z() >= T(0) ? T(0) : T(kPi);
    angles.psi = T(0);
    return angles;
  }
  angles.phi = atan2(sqrt(rho_sq), a.z());
  // atan2 is in [-pi, pi]; WrapToPi maps its -pi (y = -0, x < 0) to +pi and
  // leaves everything else, derivatives included, unchanged.
  angles.psi = WrapToPi(atan2(a.y(), a.x()));
  return angles;
}

}  // namespace symba

#endif  // SYMBA_GEOMETRY_SPHERICAL_ANGLES_H_
