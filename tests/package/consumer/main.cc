// A consumer of the symba package (installed, or the build tree), linking
// symba::core alone: uses a header-only part (SE(3)
// math) and a compiled part (AxisManifold) and checks one value of each.
#include <cmath>
#include <cstdio>

#include <symba/geometry/se3.h>
#include <symba/manifolds/axis_manifold.h>

int main() {
  const Eigen::Vector3d omega(0.1, -0.2, 0.3);
  const Eigen::Vector3d back = symba::LogSO3(symba::ExpSO3(omega));
  const symba::AxisManifold manifold;
  const double x[3] = {0.0, 0.0, 1.0};
  const double delta[2] = {0.5, 0.0};
  double y[3];
  const bool ok = manifold.Plus(x, delta, y);
  const double angle = std::acos(y[2]);
  if (!ok || (back - omega).norm() > 1e-12 || std::abs(angle - 0.5) > 1e-12) {
    std::fprintf(stderr, "symba consumer: unexpected values\n");
    return 1;
  }
  std::printf("symba consumer: ok\n");
  return 0;
}
