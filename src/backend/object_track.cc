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

namespace {

// The median r over `steps` (0 without steps), with `ratios` as scratch.
double MedianStepRatio(const std::vector<TrackStep>& steps,
                       double sigma_increment,
                       std::vector<double>* ratios) {
  if (steps.empty()) return 0.0;
  ratios->clear();
  for (const TrackStep& step : steps) {
    ratios->push_back(StepRatio(step, sigma_increment));
  }
  return MedianInPlace(ratios);
}

}  // namespace

double MedianStepRatio(const std::vector<TrackStep>& steps,
                       double sigma_increment) {
  std::vector<double> ratios;
  ratios.reserve(steps.size());
  return MedianStepRatio(steps, sigma_increment, &ratios);
}

double TrackReference::Ratio(double sigma_increment) const {
  return MedianStepRatio(steps_.values(), sigma_increment, &scratch_);
}

}  // namespace symba::internal
