#include "backend/motion_claims.h"

#include <cmath>
#include <limits>

namespace symba::internal {

StatedSigmasKey StatedSigmasKeyOf(double stated_t, double stated_r) {
  const auto quarter_octaves = [](double sigma) {
    return static_cast<int>(std::lround(4.0 * std::log2(sigma)));
  };
  return {quarter_octaves(stated_t), quarter_octaves(stated_r)};
}

void MotionClaims::Add(double stated_t,
                       double stated_r,
                       double change_squared,
                       double detection_variance,
                       double stated_variance) {
  if (!(stated_t > 0.0) || !(stated_r > 0.0) || !(stated_variance > 0.0)) {
    return;
  }
  const auto [it, inserted] =
      groups_.try_emplace(StatedSigmasKeyOf(stated_t, stated_r), window_);
  Group& group = it->second;
  if (inserted) {  // the group's sigmas as its first step stated them
    group.stated_t = stated_t;
    group.stated_r = stated_r;
  }
  // ClaimSamples' g_i with the roles swapped: the step's statement is what
  // is tested, the detections' noise (with the benefit of the doubt) what
  // is subtracted.
  const double detections =
      detection_tolerance_ * detection_tolerance_ * detection_variance;
  group.samples.Add(change_squared, stated_variance, detections);
  group.step_share.Add(detections > 0.0
                           ? stated_variance / detections
                           : std::numeric_limits<double>::infinity());
}

double MotionClaims::Factor(double stated_t, double stated_r) {
  if (!(stated_t > 0.0) || !(stated_r > 0.0)) return 1.0;
  const auto it = groups_.find(StatedSigmasKeyOf(stated_t, stated_r));
  if (it == groups_.end()) return 1.0;
  Group& group = it->second;
  if (group.samples.size() < min_samples_) return group.factor;
  if (!DetectionsVouchedFor(it->first)) {
    group.factor = 1.0;
    return 1.0;
  }
  group.factor = HeldFactor(group.samples.Scale(), group.factor, tolerance_);
  return group.factor;
}

bool MotionClaims::DetectionsVouchedFor(const Key& key) const {
  for (const auto& [other_key, other] : groups_) {
    if (other_key != key && other.samples.size() >= min_samples_ &&
        other.samples.Scale() <= 1.0 && other.step_share.Median() <= 1.0) {
      return true;
    }
  }
  return false;
}

std::vector<MotionNoiseReport::Group> MotionClaims::Report() const {
  std::vector<MotionNoiseReport::Group> groups;
  for (const auto& [key, group] : groups_) {
    MotionNoiseReport::Group report;
    report.stated_sigma_t = group.stated_t;
    report.stated_sigma_r = group.stated_r;
    report.pairs = group.samples.size();
    if (group.samples.size() >= min_samples_) {
      report.scale = group.samples.Scale();
    }
    report.factor = group.factor;
    groups.push_back(report);
  }
  return groups;
}

}  // namespace symba::internal
