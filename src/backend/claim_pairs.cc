#include "backend/claim_pairs.h"

#include <cmath>
#include <limits>
#include <utility>

namespace symba::internal {

const ClaimedDetection* ClaimPairs::Nearest(const ClaimedDetection& detection,
                                            bool claimed) const {
  const ClaimedDetection* nearest = nullptr;
  double best = max_distance_;
  for (const ClaimedDetection& other : previous_) {
    if (other.class_name != detection.class_name) continue;
    if (claimed ? !other.sigma_t.has_value() : !(other.variance_t > 0.0)) {
      continue;
    }
    const double d = (other.p_w - detection.p_w).norm();
    if (d <= best) {
      best = d;
      nearest = &other;
    }
  }
  return nearest;
}

void ClaimPairs::Add(int k,
                     const ClaimedDetection& detection,
                     const std::optional<StepVariance>& step,
                     DetectionNoiseEstimator* noise,
                     MotionClaims* motion) {
  if (k != keyframe_) {
    previous_ = std::move(current_);
    current_.clear();
    previous_keyframe_ = keyframe_;
    keyframe_ = k;
  }
  current_.push_back(detection);
  if (previous_keyframe_ != k - 1 || !step) return;
  const double step_variance_t = step->t;
  const double step_variance_r = step->r;
  const double distance_squared = detection.distance * detection.distance;
  if (motion != nullptr && detection.variance_t > 0.0) {
    const ClaimedDetection* m = Nearest(detection, /*claimed=*/false);
    if (m != nullptr) {
      motion->Add(step->stated_t,
                  step->stated_r,
                  (detection.p_w - m->p_w).squaredNorm(),
                  m->variance_t + detection.variance_t,
                  step->stated_t * step->stated_t +
                      distance_squared * step->stated_r * step->stated_r);
    }
  }
  if (!detection.sigma_t) return;
  const ClaimedDetection* a = Nearest(detection, /*claimed=*/true);
  if (a == nullptr) return;
  using Component = DetectionNoiseEstimator::Component;
  if (a->sigma_t && detection.sigma_t) {
    noise->AddClaimPair(
        detection.class_name,
        Component::kTranslation,
        (detection.p_w - a->p_w).squaredNorm(),
        *a->sigma_t * *a->sigma_t + *detection.sigma_t * *detection.sigma_t,
        step_variance_t + distance_squared * step_variance_r);
  }
  if (a->sigma_r && detection.sigma_r && a->R_w && detection.R_w) {
    const double angle = a->R_w->angularDistance(*detection.R_w);
    if (angle <= max_angle_) {
      noise->AddClaimPair(
          detection.class_name,
          Component::kRotation,
          angle * angle,
          *a->sigma_r * *a->sigma_r + *detection.sigma_r * *detection.sigma_r,
          step_variance_r);
    }
  }
}

}  // namespace symba::internal
