// The backend benchmark's keyframes (backend_bench_sequence.h).
#include "backend_bench_sequence.h"

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "symba/geometry/so3.h"

namespace symba {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kHypotheses = 30;
constexpr int kPointsPerKeyframe = 100;

struct BenchObject {
  const char* class_name;
  int order;  // 0 = continuous, 1 = asymmetric, k = k-fold about z
  Rigid3d T_wo;
};

Rigid3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  Eigen::Matrix3d R;
  R << x, z.cross(x), z;
  return Rigid3d(Eigen::Quaterniond(R), eye);
}

Eigen::Quaterniond Yaw(double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
}

}  // namespace

std::vector<KeyframeInput> MakeBackendBenchSequence(
    PinholeIntrinsics* intrinsics) {
  *intrinsics = {525.0, 525.0, 319.5, 239.5};
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::vector<BenchObject> objects = {
      {"table", 2, Rigid3d(Yaw(0.3), Eigen::Vector3d(0.0, 0.0, 0.4))},
      {"round_table", 0, Rigid3d(Yaw(0.0), Eigen::Vector3d(1.2, 0.3, 0.4))},
      {"round_table", 0, Rigid3d(Yaw(0.0), Eigen::Vector3d(-1.2, 0.3, 0.4))},
      {"square_table", 4, Rigid3d(Yaw(0.5), Eigen::Vector3d(0.2, 1.1, 0.4))},
      {"chair", 1, Rigid3d(Yaw(1.0), Eigen::Vector3d(0.1, -1.0, 0.45))}};
  std::vector<Eigen::Vector3d> wall;
  for (int i = 0; i < 2000; ++i) {
    const double a = 2.0 * kPi * uniform(rng);
    wall.emplace_back(6.0 * std::cos(a), 6.0 * std::sin(a), 3.0 * uniform(rng));
  }
  std::vector<KeyframeInput> keyframes;
  const int n = kBackendBenchWarmupKeyframes + kBackendBenchTimedKeyframes;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / 48.0;
    const Rigid3d T_wc =
        LookAt(Eigen::Vector3d(4.0 * std::cos(a), 4.0 * std::sin(a), 1.4),
               Eigen::Vector3d(0, 0, 0.4));
    KeyframeInput kf;
    kf.id = k;
    kf.timestamp = 0.1 * k;
    kf.T_wc = T_wc;
    for (size_t o = 0; o < objects.size(); ++o) {
      DetectionInput det;
      det.id = std::to_string(k) + "/" + std::to_string(o);
      det.class_name = objects[o].class_name;
      for (int j = 0; j < kHypotheses; ++j) {
        const BenchObject& obj = objects[o];
        const double mode = obj.order == 0 ? 2.0 * kPi * uniform(rng)
                            : obj.order == 1
                                ? 0.0
                                : 2.0 * kPi * (j % obj.order) / obj.order;
        const Eigen::Vector3d rot_noise(noise(rng), noise(rng), noise(rng));
        const Eigen::Vector3d t_noise(noise(rng), noise(rng), noise(rng));
        const Rigid3d T_wo_mode(obj.T_wo.q * Yaw(mode), obj.T_wo.t);
        Rigid3d T_co = T_wc.Inverse() * T_wo_mode;
        T_co.q = T_co.q * ExpSO3(Eigen::Vector3d(0.03 * rot_noise));
        T_co.t += 0.02 * t_noise;
        det.hypotheses.push_back({T_co, 1.0});
      }
      kf.detections.push_back(std::move(det));
    }
    for (size_t i = 0; i < wall.size() && kf.points.size() < kPointsPerKeyframe;
         ++i) {
      const Eigen::Vector3d p_c = T_wc.Inverse() * wall[i];
      if (p_c.z() < 0.5) continue;
      const Eigen::Vector2d uv(
          intrinsics->fx * p_c.x() / p_c.z() + intrinsics->cx,
          intrinsics->fy * p_c.y() / p_c.z() + intrinsics->cy);
      if (uv.x() < 0 || uv.x() > 640 || uv.y() < 0 || uv.y() > 480) continue;
      kf.points.push_back({static_cast<int64_t>(i), uv, p_c.z()});
    }
    keyframes.push_back(std::move(kf));
  }
  return keyframes;
}

}  // namespace symba
