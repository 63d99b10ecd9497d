#include "front_end_drift.h"

#include <Eigen/Geometry>

namespace symba::bench {
namespace {

// One keyframe step with its translation scaled and then turned about the
// camera's y axis by yaw_per_metre times its original length.
Rigid3d DriftStep(const Rigid3d& step, const FrontEndDrift& drift) {
  const double yaw = drift.yaw_per_metre * step.t.norm();
  const Rigid3d turn(
      Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d::Zero());
  return turn * Rigid3d(step.q, drift.scale * step.t);
}

}  // namespace

std::vector<Rigid3d> DriftFrontEnd(const std::vector<Rigid3d>& T_wc,
                                   int stride,
                                   const FrontEndDrift& drift) {
  const std::size_t n = static_cast<std::size_t>(stride);
  std::vector<Rigid3d> drifted(T_wc.size());
  for (std::size_t f = 0; f < T_wc.size(); ++f) {
    const std::size_t keyframe = f - f % n;
    if (f == 0) {
      drifted[f] = T_wc[f];
    } else if (f == keyframe) {
      const std::size_t previous = keyframe - n;
      const Rigid3d step = T_wc[previous].Inverse() * T_wc[f];
      drifted[f] = drifted[previous] * DriftStep(step, drift);
    } else {
      drifted[f] = drifted[keyframe] * (T_wc[keyframe].Inverse() * T_wc[f]);
    }
  }
  return drifted;
}

}  // namespace symba::bench
