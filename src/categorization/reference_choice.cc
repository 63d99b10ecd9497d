#include "categorization/reference_choice.h"

#include <cmath>

namespace symba {
namespace categorization {

std::vector<int> RotationSupport(const HypothesisSet& set, double max_angle) {
  const int n = set.size();
  // |q_i . q_j| >= cos(angle / 2)  <=>  rotation angle between them <= angle.
  const double cos_half = std::cos(0.5 * max_angle);
  std::vector<int> support(n, 0);
  for (int i = 0; i < n; ++i) {
    if (!set.usable[i]) continue;
    ++support[i];
    for (int j = i + 1; j < n; ++j) {
      if (set.usable[j] &&
          std::abs(set.q[i].coeffs().dot(set.q[j].coeffs())) >= cos_half) {
        ++support[i];
        ++support[j];
      }
    }
  }
  return support;
}

int ChooseReference(const HypothesisSet& set,
                    double min_axis_angle,
                    int min_points) {
  const std::vector<int> support = RotationSupport(set, min_axis_angle);
  int best = -1;
  int best_any = -1;
  for (int j = 0; j < set.size(); ++j) {
    if (!set.usable[j]) continue;
    if (best_any < 0 || set.w[j] > set.w[best_any]) best_any = j;
    if (support[j] >= min_points && (best < 0 || set.w[j] > set.w[best])) {
      best = j;
    }
  }
  return best >= 0 ? best : best_any;
}

}  // namespace categorization
}  // namespace symba
