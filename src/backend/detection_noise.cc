#include "backend/detection_noise.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Dense>

namespace symba::internal {

namespace {

// The correlations the fit tries (rho = 0: no persistent part apart from
// the white one).
constexpr std::array<double, 16> kCorrelationGrid = {0.0,
                                                     0.3,
                                                     0.5,
                                                     0.6,
                                                     0.7,
                                                     0.8,
                                                     0.85,
                                                     0.9,
                                                     0.93,
                                                     0.95,
                                                     0.97,
                                                     0.98,
                                                     0.99,
                                                     kMaxCorrelation};

double Median(std::vector<double>* values) {
  const size_t middle = values->size() / 2;
  std::nth_element(values->begin(), values->begin() + middle, values->end());
  double median = (*values)[middle];
  if (values->size() % 2 == 0) {
    median = 0.5 * (median + *std::max_element(values->begin(),
                                               values->begin() + middle));
  }
  return median;
}

// One weighted least-squares fit of V = X theta over the columns in `used`
// (bit j: column j); false if singular or a parameter is negative.
bool FitSubset(const Eigen::MatrixXd& X,
               const Eigen::VectorXd& V,
               const Eigen::VectorXd& weight,
               int used,
               Eigen::VectorXd* theta,
               double* cost) {
  std::vector<int> columns;
  for (int j = 0; j < X.cols(); ++j) {
    if (used & (1 << j)) columns.push_back(j);
  }
  const int n = static_cast<int>(columns.size());
  Eigen::MatrixXd A(X.rows(), n);
  for (int c = 0; c < n; ++c) A.col(c) = X.col(columns[c]);
  const Eigen::MatrixXd normal = A.transpose() * weight.asDiagonal() * A;
  const Eigen::VectorXd rhs = A.transpose() * weight.asDiagonal() * V;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(normal);
  if (lu.rank() < n) return false;
  const Eigen::VectorXd solution = lu.solve(rhs);
  if ((solution.array() < 0.0).any() || !solution.allFinite()) return false;
  *theta = Eigen::VectorXd::Zero(X.cols());
  for (int c = 0; c < n; ++c) (*theta)[columns[c]] = solution[c];
  const Eigen::VectorXd residual = V - X * *theta;
  *cost = residual.dot(weight.asDiagonal() * residual);
  return true;
}

}  // namespace

int LagBinIndex(int lag) {
  if (lag < 1) return -1;
  int bin = 0;
  while ((lag >> (bin + 1)) > 0) ++bin;
  return bin < kLagBins ? bin : -1;
}

void LagBin::Add(const LagSample& sample) {
  if (static_cast<int>(samples_.size()) < window_) {
    samples_.push_back(sample);
    return;
  }
  samples_[next_] = sample;
  next_ = (next_ + 1) % samples_.size();
}

LagBinSummary LagBin::Summary() const {
  LagBinSummary summary;
  summary.count = size();
  scratch_.clear();
  for (const LagSample& s : samples_) {
    scratch_.push_back(s.squared_distance);
    summary.lag += s.lag;
  }
  summary.lag /= summary.count;
  summary.variance = Median(&scratch_) / kChiSquare3Median;
  return summary;
}

double VariogramFit::EffectiveVariance() const {
  return white + persistent * (1.0 + rho) / (1.0 - rho);
}

double VariogramFit::Inflation() const {
  return std::sqrt((1.0 + rho) / (1.0 - rho));
}

std::optional<VariogramFit> FitVariogram(
    const std::vector<LagBinSummary>& bins) {
  std::vector<LagBinSummary> used;
  bool level = false;
  for (const LagBinSummary& bin : bins) {
    if (bin.count < kMinBinSamples) continue;
    used.push_back(bin);
    level = level || bin.lag == 0.0;
  }
  if (!level || used.size() < 2) return std::nullopt;
  const int n = static_cast<int>(used.size());
  // Relative errors: each bin's squared error over its variance squared,
  // times its count (the variances span orders of magnitude).
  double largest = 0.0;
  for (const LagBinSummary& bin : used) {
    largest = std::max(largest, bin.variance);
  }
  if (!(largest > 0.0)) return VariogramFit{};  // every sample identical
  Eigen::VectorXd V(n), weight(n);
  for (int i = 0; i < n; ++i) {
    const double v = std::max(used[i].variance, 1e-12 * largest);
    V[i] = used[i].variance;
    weight[i] = used[i].count / (v * v);
  }
  std::optional<VariogramFit> best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (double rho : kCorrelationGrid) {
    // The level: w + b; a lag: 2 w + 2 b (1 - rho^lag).
    Eigen::MatrixXd X(n, 2);
    for (int i = 0; i < n; ++i) {
      const bool is_level = used[i].lag == 0.0;
      X(i, 0) = is_level ? 1.0 : 2.0;
      X(i, 1) = is_level ? 1.0 : 2.0 * (1.0 - std::pow(rho, used[i].lag));
    }
    for (int subset = 1; subset < 4; ++subset) {
      Eigen::VectorXd theta;
      double cost = 0.0;
      if (!FitSubset(X, V, weight, subset, &theta, &cost)) continue;
      if (cost < best_cost) {
        best_cost = cost;
        best = VariogramFit{theta[0], theta[1], rho};
      }
    }
  }
  return best;
}

DetectionNoiseEstimator::Variogram::Variogram(int window)
    : level(window), lags(kLagBins, LagBin(window)) {}

void DetectionNoiseEstimator::Add(const LagSample& sample,
                                  Variogram* variogram) {
  if (sample.lag == 0) {
    variogram->level.Add(sample);
    ++variogram->levels;
    return;
  }
  const int bin = LagBinIndex(sample.lag);
  if (bin >= 0) variogram->lags[bin].Add(sample);
}

void DetectionNoiseEstimator::AddTranslation(const std::string& class_name,
                                             const LagSample& sample) {
  Add(sample, &translation_.try_emplace(class_name, window_).first->second);
}

void DetectionNoiseEstimator::AddRotation(const std::string& class_name,
                                          const LagSample& sample) {
  Add(sample, &rotation_.try_emplace(class_name, window_).first->second);
}

std::optional<VariogramFit> DetectionNoiseEstimator::Fit(
    const Variogram& variogram) const {
  if (variogram.levels < min_samples_) return std::nullopt;
  std::vector<LagBinSummary> summaries = {variogram.level.Summary()};
  for (const LagBin& bin : variogram.lags) {
    if (bin.size() > 0) summaries.push_back(bin.Summary());
  }
  return FitVariogram(summaries);
}

void DetectionNoiseEstimator::Update(const std::string& class_name) {
  ClassNoise noise;
  const auto t = translation_.find(class_name);
  if (t != translation_.end()) {
    noise.samples_t = t->second.levels;
    noise.translation = Fit(t->second);
  }
  const auto r = rotation_.find(class_name);
  if (r != rotation_.end()) {
    noise.samples_r = r->second.levels;
    noise.rotation = Fit(r->second);
  }
  if (noise.translation) {
    noise.sigma_t =
        std::max(kMinSigmaT, std::sqrt(noise.translation->EffectiveVariance()));
    noise.scatter_t =
        std::max(kMinSigmaT, std::sqrt(noise.translation->ScatterVariance()));
  }
  if (noise.rotation) {
    noise.sigma_r =
        std::max(kMinSigmaR, std::sqrt(noise.rotation->EffectiveVariance()));
  }
  estimates_[class_name] = noise;
}

ClassNoise DetectionNoiseEstimator::Estimate(
    const std::string& class_name) const {
  const auto it = estimates_.find(class_name);
  return it == estimates_.end() ? ClassNoise{} : it->second;
}

std::vector<std::string> DetectionNoiseEstimator::Classes() const {
  std::vector<std::string> names;
  for (const auto& [name, variogram] : translation_) names.push_back(name);
  for (const auto& [name, variogram] : rotation_) {
    if (translation_.count(name) == 0) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

void OdometryNoiseEstimator::Add(const Eigen::Matrix<double, 6, 1>& whitened,
                                 bool follows) {
  residuals_.push_back(whitened);
  follows_.push_back(follows);
  ++samples_;
  if (static_cast<int>(residuals_.size()) > window_) {
    residuals_.pop_front();
    follows_.pop_front();
  }
}

void OdometryNoiseEstimator::Update() {
  const int n = static_cast<int>(residuals_.size());
  // Prefix sums, and the start of the run each residual belongs to.
  std::vector<Eigen::Matrix<double, 6, 1>> prefix(n + 1);
  std::vector<int> run_start(n);
  prefix[0].setZero();
  for (int i = 0; i < n; ++i) {
    prefix[i + 1] = prefix[i] + residuals_[i];
    run_start[i] = i > 0 && follows_[i] ? run_start[i - 1] : i;
  }
  std::optional<double> scale;
  std::vector<double> squared;
  for (int run = 1; run <= kMaxOdometryRun; run *= 2) {
    squared.clear();
    for (int end = run; end <= n; ++end) {
      if (run_start[end - 1] > end - run) continue;  // crosses a restart
      squared.push_back((prefix[end] - prefix[end - run]).squaredNorm());
    }
    if (static_cast<int>(squared.size()) < min_samples_) break;
    const double s = Median(&squared) / (run * kChiSquare6Median);
    scale = std::max(scale.value_or(0.0), s);
  }
  if (scale) {
    scale_ = std::clamp(*scale, kMinOdometryScale, kMaxOdometryScale);
  }
}

double EffectiveSigma(double given,
                      bool claimed,
                      const std::optional<double>& estimate,
                      double contradiction_ratio) {
  if (!estimate) return given;
  if (!claimed) return *estimate;
  return *estimate > contradiction_ratio * given ? *estimate : given;
}

}  // namespace symba::internal
