// Deterministic random inputs for tests: unit quaternions (uniform on SO(3)),
// unit vectors (uniform on S^2) and rotations of a chosen angle.
#ifndef SYMBA_TESTS_TEST_SUPPORT_RANDOM_H_
#define SYMBA_TESTS_TEST_SUPPORT_RANDOM_H_

#include <cmath>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace symba::testing {

class TestRandom {
 public:
  explicit TestRandom(unsigned seed) : engine_(seed) {}

  double Uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(engine_);
  }
  double Normal(double sigma) {
    return std::normal_distribution<double>(0.0, sigma)(engine_);
  }
  Eigen::Vector3d NormalVector(double sigma) {
    return Eigen::Vector3d(Normal(sigma), Normal(sigma), Normal(sigma));
  }
  // Uniform on the unit sphere.
  Eigen::Vector3d UnitVector() {
    Eigen::Vector3d v;
    do {
      v = NormalVector(1.0);
    } while (v.squaredNorm() < 1e-12);
    return v.normalized();
  }
  // Uniform on SO(3) (normalised 4-D Gaussian).
  Eigen::Quaterniond Rotation() {
    Eigen::Vector4d v;
    do {
      v = Eigen::Vector4d(Normal(1.0), Normal(1.0), Normal(1.0), Normal(1.0));
    } while (v.squaredNorm() < 1e-12);
    v.normalize();
    return Eigen::Quaterniond(v(3), v(0), v(1), v(2));
  }
  // A rotation by exactly `angle` radians about a random axis.
  Eigen::Quaterniond RotationOfAngle(double angle) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(angle, UnitVector()));
  }
  std::mt19937& engine() { return engine_; }

 private:
  std::mt19937 engine_;
};

}  // namespace symba::testing

#endif  // SYMBA_TESTS_TEST_SUPPORT_RANDOM_H_
