#include "symba/evaluation/trajectory_error.h"
#include "symba/io/format_double.h"

#include <algorithm>
#include <cmath>

#include "symba/evaluation/evaluate.h"

namespace symba {

Status CompareTrajectories(const std::vector<TrajectoryPose>& estimate,
                           const std::string& estimate_name,
                           const std::vector<TrajectoryPose>& reference,
                           const std::string& reference_name,
                           TrajectoryError* error) {
  if (estimate.empty()) return Status::Error(estimate_name + ": no poses");
  double sum = 0.0;
  double max = 0.0;
  for (const TrajectoryPose& pose : estimate) {
    const auto it = std::lower_bound(
        reference.begin(),
        reference.end(),
        pose.timestamp - kTimestampTolerance,
        [](const TrajectoryPose& r, double t) { return r.timestamp < t; });
    if (it == reference.end() ||
        !(std::abs(it->timestamp - pose.timestamp) <= kTimestampTolerance)) {
      return Status::Error(estimate_name + ": pose at timestamp " +
                           FormatDouble(pose.timestamp) + ": no pose of " +
                           reference_name + " at that time");
    }
    const double d = (pose.T_wc.t - it->T_wc.t).norm();
    sum += d * d;
    max = std::max(max, d);
  }
  error->poses = static_cast<int>(estimate.size());
  error->position_rmse = std::sqrt(sum / static_cast<double>(estimate.size()));
  error->max_position_error = max;
  return Status::Ok();
}

}  // namespace symba
