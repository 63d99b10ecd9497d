#include "backend/object_track.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/median.h"

namespace symba::internal {

double StepRatio(const TrackStep& step, double sigma_increment) {
  const double variance =
      2.0 * sigma_increment * sigma_increment + std::max(0.0, step.growth);
  if (variance > 0.0) return step.change / std::sqrt(variance);
  return step.change > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
}

double MedianStepRatio(const std::vector<TrackStep>& steps,
                       double sigma_increment) {
  if (steps.empty()) return 0.0;
  std::vector<double> ratios;
  ratios.reserve(steps.size());
  for (const TrackStep& step : steps) {
    ratios.push_back(StepRatio(step, sigma_increment));
  }
  return MedianInPlace(&ratios);
}

void TrackReference::Add(const TrackStep& step) {
  if (static_cast<int>(steps_.size()) < window_) {
    steps_.push_back(step);
    return;
  }
  steps_[next_] = step;
  next_ = (next_ + 1) % steps_.size();
}

double TrackReference::Ratio(double sigma_increment) const {
  return MedianStepRatio(steps_, sigma_increment);
}

}  // namespace symba::internal
