#include "backend/object_track.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "backend/association.h"
#include "common/median.h"

namespace symba::internal {

double StepRatio(const TrackStep& step,
                 double sigma_increment,
                 const std::vector<std::unique_ptr<KeyframeState>>& keyframes) {
  const int n = static_cast<int>(keyframes.size());
  const double growth =
      step.from >= 0 && step.from < step.to && step.to < n
          ? PlaceGrowth(keyframes, step.from, step.to, step.distance)
          : 0.0;
  const double variance =
      2.0 * sigma_increment * sigma_increment + std::max(0.0, growth);
  if (variance > 0.0) return step.change / std::sqrt(variance);
  return step.change > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
}

double MedianStepRatio(
    const std::deque<TrackStep>& steps,
    double sigma_increment,
    const std::vector<std::unique_ptr<KeyframeState>>& keyframes) {
  if (steps.empty()) return 0.0;
  std::vector<double> ratios;
  ratios.reserve(steps.size());
  for (const TrackStep& step : steps) {
    ratios.push_back(StepRatio(step, sigma_increment, keyframes));
  }
  return MedianInPlace(&ratios);
}

}  // namespace symba::internal
