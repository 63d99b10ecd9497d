#include "backend/detection_noise.h"

#include <algorithm>
#include <cmath>

namespace symba::internal {

void RobustScale::Add(double value) {
  if (static_cast<int>(values_.size()) < window_) {
    values_.push_back(value);
    return;
  }
  values_[next_] = value;
  next_ = (next_ + 1) % values_.size();
}

double RobustScale::Sigma() const {
  scratch_ = values_;
  const size_t middle = scratch_.size() / 2;
  std::nth_element(scratch_.begin(), scratch_.begin() + middle, scratch_.end());
  double median = scratch_[middle];
  if (scratch_.size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(scratch_.begin(),
                                               scratch_.begin() + middle));
  }
  return median / kChi3Median;
}

double CorrelatedSigma(double sigma_level, double sigma_increment) {
  if (!(sigma_level > 0.0)) return 0.0;
  const double ratio = sigma_increment / sigma_level;
  const double rho = std::clamp(1.0 - ratio * ratio, 0.0, kMaxCorrelation);
  return sigma_level * std::sqrt((1.0 + rho) / (1.0 - rho));
}

void DetectionNoiseEstimator::AddTranslation(const std::string& class_name,
                                             Kind kind,
                                             double error) {
  Scales& scales = translation_.try_emplace(class_name, window_).first->second;
  (kind == Kind::kLevel ? scales.level : scales.increment).Add(error);
}

void DetectionNoiseEstimator::AddRotation(const std::string& class_name,
                                          Kind kind,
                                          double error) {
  Scales& scales = rotation_.try_emplace(class_name, window_).first->second;
  (kind == Kind::kLevel ? scales.level : scales.increment).Add(error);
}

std::optional<double> DetectionNoiseEstimator::Sigma(
    const std::map<std::string, Scales>& scales,
    const std::string& class_name) const {
  const auto it = scales.find(class_name);
  if (it == scales.end() || it->second.level.size() < min_samples_) {
    return std::nullopt;
  }
  const double level = it->second.level.Sigma();
  if (it->second.increment.size() < min_samples_) return level;
  // Increments are differences of two errors: sqrt(2) sigma each.
  return CorrelatedSigma(level, it->second.increment.Sigma() / std::sqrt(2.0));
}

ClassNoise DetectionNoiseEstimator::Estimate(
    const std::string& class_name) const {
  ClassNoise noise;
  if (auto t = Sigma(translation_, class_name)) {
    noise.sigma_t = std::max(kMinSigmaT, *t);
  }
  if (auto r = Sigma(rotation_, class_name)) {
    noise.sigma_r = std::max(kMinSigmaR, *r);
  }
  return noise;
}

}  // namespace symba::internal
