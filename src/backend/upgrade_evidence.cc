#include "backend/upgrade_evidence.h"

#include <algorithm>
#include <cmath>

#include "backend/association.h"
#include "symba/geometry/angle.h"

namespace symba::internal {

bool FitsOrder(double angle, int order, double tolerance) {
  const double step = 2.0 * kPi / order;
  const double a = std::abs(WrapToPi(angle));
  // The nearest multiple j of the step, j in 1..order/2 covers [0, pi].
  const double j = std::max(1.0, std::round(a / step));
  return std::abs(a - j * step) <= tolerance;
}

int PlausibleOrder(double angle, int max_order, double tolerance) {
  for (int order = 2; order <= max_order; ++order) {
    if (FitsOrder(angle, order, tolerance)) return order;
  }
  return 0;
}

FlipConsensus ConsistentFlips(const std::vector<FlipEvidence>& flips,
                              const FlipEvidence& flip,
                              double gate_axis,
                              double gate_angle) {
  FlipConsensus consensus;
  int last_keyframe = -1;
  double sum = 0.0;
  for (const FlipEvidence& other : flips) {
    if (other.keyframe == last_keyframe) continue;  // one per keyframe
    if (AxisDistance(other.a_o, flip.a_o) > gate_axis) continue;
    if (std::abs(std::abs(other.angle) - std::abs(flip.angle)) > gate_angle) {
      continue;
    }
    last_keyframe = other.keyframe;
    ++consensus.count;
    sum += std::abs(other.angle);
  }
  if (consensus.count > 0) consensus.mean_angle = sum / consensus.count;
  return consensus;
}

double TwoRotationsLogOdds(int unflipped, int flipped, double confusion_rate) {
  constexpr double kLeastShare = 1.0 / 3.0;
  const int minority = std::min(unflipped, flipped);
  const int majority = std::max(unflipped, flipped);
  return minority * std::log(kLeastShare / confusion_rate) +
         majority * std::log((1.0 - kLeastShare) / (1.0 - confusion_rate));
}

bool FlipsOutvoteTheRotation(int unflipped,
                             int flipped,
                             double confusion_rate,
                             double odds) {
  const double log_odds = std::log(odds);
  const double against_own =
      (flipped - unflipped) * std::log((1.0 - confusion_rate) / confusion_rate);
  const double against_symmetry =
      -TwoRotationsLogOdds(unflipped, flipped, confusion_rate);
  return flipped > unflipped && against_own >= log_odds &&
         against_symmetry >= log_odds;
}

bool ClassFlipCounts::FlipsAsSymmetric(int order, double fraction) const {
  const auto it = flip_keyframes_by_order.find(order);
  const int flips = it == flip_keyframes_by_order.end() ? 0 : it->second;
  return flips > 0 && flips >= fraction * keyframes;
}

}  // namespace symba::internal
