#include "backend/detection_noise.h"

#include <algorithm>
#include <cmath>

namespace symba::internal {

double RobustScale::Median() const {
  scratch_ = values_.values();
  return MedianInPlace(&scratch_);
}

double RobustScale::Sigma() const { return Median() / kChi3Median; }

double IncrementCorrelation(double sigma_level, double sigma_increment) {
  if (!(sigma_level > 0.0)) return 0.0;
  const double ratio = sigma_increment / sigma_level;
  return std::clamp(1.0 - ratio * ratio, 0.0, kMaxCorrelation);
}

double CorrelatedSigma(double sigma_level, double sigma_increment) {
  if (!(sigma_level > 0.0)) return 0.0;
  const double rho = IncrementCorrelation(sigma_level, sigma_increment);
  return sigma_level * std::sqrt(PersistenceVarianceFactor(rho));
}

void DetectionNoiseEstimator::AddTranslation(const std::string& class_name,
                                             Kind kind,
                                             double error) {
  Scales& scales = translation_.try_emplace(class_name, window_).first->second;
  (kind == Kind::kLevel ? scales.level : scales.increment).Add(error);
}

void DetectionNoiseEstimator::AddSightLevel(const std::string& class_name,
                                            double along,
                                            double across) {
  SightScales& scales = sight_.try_emplace(class_name, window_).first->second;
  scales.along.Add(along);
  scales.across.Add(across);
}

std::optional<double> SightAnisotropy(double along_median,
                                      double across_median) {
  if (!(across_median > 0.0) || !(along_median >= 0.0)) return std::nullopt;
  return (along_median / kChi1Median) / (across_median / kChi2Median);
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
  const std::optional<double> increment = IncrementSigma(scales, class_name);
  return increment ? CorrelatedSigma(level, *increment) : level;
}

std::optional<double> DetectionNoiseEstimator::IncrementSigma(
    const std::map<std::string, Scales>& scales,
    const std::string& class_name) const {
  const auto it = scales.find(class_name);
  if (it == scales.end() || it->second.increment.size() < min_samples_) {
    return std::nullopt;
  }
  // Increments are differences of two errors: sqrt(2) sigma each.
  return it->second.increment.Sigma() / std::sqrt(2.0);
}

NoiseSamplesReport DetectionNoiseEstimator::Report(
    const std::map<std::string, Scales>& scales,
    const std::string& class_name) const {
  NoiseSamplesReport report;
  const auto it = scales.find(class_name);
  if (it == scales.end()) return report;
  report.levels = it->second.level.size();
  report.increments = it->second.increment.size();
  if (report.levels >= min_samples_) {
    report.sigma_level = it->second.level.Sigma();
  }
  report.sigma_increment = IncrementSigma(scales, class_name);
  if (report.sigma_level && report.sigma_increment) {
    report.correlation =
        IncrementCorrelation(*report.sigma_level, *report.sigma_increment);
    report.inflation =
        std::sqrt((1.0 + report.correlation) / (1.0 - report.correlation));
  }
  return report;
}

NoiseSamplesReport DetectionNoiseEstimator::TranslationReport(
    const std::string& class_name) const {
  return Report(translation_, class_name);
}

NoiseSamplesReport DetectionNoiseEstimator::RotationReport(
    const std::string& class_name) const {
  return Report(rotation_, class_name);
}

void DetectionNoiseEstimator::AddScatter(const std::string& class_name,
                                         double sigma_t,
                                         double sigma_r) {
  ScatterScales& scales =
      scatter_.try_emplace(class_name, window_).first->second;
  ++scales.detections;
  scales.sigma_t.Add(sigma_t);
  scales.sigma_r.Add(sigma_r);
}

ClassNoiseEstimate::Scatter DetectionNoiseEstimator::ScatterReport(
    const std::string& class_name) const {
  ClassNoiseEstimate::Scatter report;
  const auto it = scatter_.find(class_name);
  if (it == scatter_.end()) return report;
  report.detections = it->second.detections;
  report.sigma_t = it->second.sigma_t.Median();
  report.sigma_r = it->second.sigma_r.Median();
  return report;
}

void ClaimSamples::Add(double change_squared,
                       double claimed_variance,
                       double step_variance) {
  const double excess =
      change_squared / (kChi3Median * kChi3Median) - step_variance;
  scales_.Add(excess > 0.0 && claimed_variance > 0.0
                  ? std::sqrt(excess / claimed_variance)
                  : 0.0);
}

void DetectionNoiseEstimator::AddClaimPair(const std::string& class_name,
                                           Component component,
                                           double change_squared,
                                           double claimed_variance,
                                           double step_variance) {
  auto& claims = component == Component::kTranslation ? claim_t_ : claim_r_;
  claims.try_emplace(class_name, window_)
      .first->second.Add(change_squared, claimed_variance, step_variance);
}

std::optional<double> DetectionNoiseEstimator::ClaimScale(
    const std::map<std::string, ClaimSamples>& claims,
    const std::string& class_name) const {
  const auto it = claims.find(class_name);
  if (it == claims.end() || it->second.size() < min_samples_) {
    return std::nullopt;
  }
  return it->second.Scale();
}

void DetectionNoiseEstimator::AddTrackStep(const std::string& class_name,
                                           const TrackStep& step) {
  tracks_.try_emplace(class_name, window_).first->second.Add(step);
}

std::optional<double> DetectionNoiseEstimator::TrackRatio(
    const std::string& class_name, double sigma_increment) const {
  const auto it = tracks_.find(class_name);
  if (it == tracks_.end() || it->second.size() < min_samples_) {
    return std::nullopt;
  }
  return it->second.Ratio(sigma_increment);
}

ClassNoiseEstimate::Claims DetectionNoiseEstimator::ClaimsReport(
    const std::string& class_name) const {
  ClassNoiseEstimate::Claims report;
  if (const auto it = claim_t_.find(class_name); it != claim_t_.end()) {
    report.translation_samples = it->second.size();
  }
  if (const auto it = claim_r_.find(class_name); it != claim_r_.end()) {
    report.rotation_samples = it->second.size();
  }
  report.scale_t = ClaimScale(claim_t_, class_name);
  report.scale_r = ClaimScale(claim_r_, class_name);
  return report;
}

std::vector<std::string> DetectionNoiseEstimator::Classes() const {
  std::vector<std::string> names;
  for (const auto& [name, scales] : translation_) names.push_back(name);
  for (const auto& [name, scales] : rotation_) names.push_back(name);
  for (const auto& [name, scales] : scatter_) names.push_back(name);
  for (const auto& [name, scales] : claim_t_) names.push_back(name);
  for (const auto& [name, scales] : claim_r_) names.push_back(name);
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
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
  noise.claim_scale_t = ClaimScale(claim_t_, class_name);
  noise.claim_scale_r = ClaimScale(claim_r_, class_name);
  const auto sight = sight_.find(class_name);
  if (sight != sight_.end() && sight->second.along.size() >= min_samples_) {
    noise.sight_anisotropy = SightAnisotropy(sight->second.along.Median(),
                                             sight->second.across.Median());
  }
  // The white part holds the detections weighed by their scatter: a
  // class without any has none.
  if (scatter_.count(class_name) == 0) return noise;
  if (auto t = IncrementSigma(translation_, class_name)) {
    noise.white_sigma_t = std::max(kMinSigmaT, *t);
  }
  if (auto r = IncrementSigma(rotation_, class_name)) {
    noise.white_sigma_r = std::max(kMinSigmaR, *r);
  }
  return noise;
}

double ObjectMeanSigma(double sigma, int n, const NoiseSamplesReport& samples) {
  const double persistent =
      samples.sigma_level
          ? *samples.sigma_level * *samples.sigma_level * samples.correlation
          : 0.0;
  return std::sqrt(sigma * sigma / std::max(1, n) + persistent);
}

}  // namespace symba::internal
