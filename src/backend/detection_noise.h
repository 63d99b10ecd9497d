// The detector's noise and the front end's odometry weight, learned from the
// run (docs/backend.md "Detection noise learned from the run"). A detector
// may claim a noise that is not its own or claim none; its errors need not
// be independent from frame to frame (a pose estimator that puts a box 5 cm
// too deep does so for hundreds of frames); and the front end's stated
// odometry noise is a guess too, wrong by orders of magnitude when it
// drifts.
//
// Samples come from the joint solution: when a keyframe leaves the window
// its pose is final, and each of its detections is placed in the world with
// it (position, and rotation for asymmetric objects).
//
// Detections. Per class, the *level* is a placement's squared distance to
// its object's estimate, and a *lag* sample the squared distance between
// two placements of one object `lag` keyframes apart. Per axis, with a
// white (frame-to-frame) variance w and a persistent part of variance b
// that decays as an AR(1) process of correlation rho per keyframe:
//   level   E|e|^2 / 3          = w + b
//   lag     E|e_j - e_i|^2 / 3  = 2 w + 2 b (1 - rho^lag)
// White noise makes the lags as large as twice the level at once; a
// persistent error makes them small at short lags and grow towards it. Lags
// are binned by powers of two (1, 2-3, 4-7, ..., 256-511 keyframes); each
// bin's and the level's variance is the median of its squared distances
// over the median of chi-square with 3 degrees of freedom (robust to a
// detector's gross outliers). The fit weighs each bin's relative error by
// its count, over a grid of rho, with w, b >= 0. A detection is weighed
// with the variance that a run of detections of these errors carries per
// detection,
//   sigma^2 = w + b (1 + rho) / (1 - rho)
// (N errors of an AR(1) process inform like N (1 - rho) / (1 + rho)
// independent ones); the association gate uses the scatter sqrt(w + b).
//
// Odometry. Each keyframe step's residual in the joint solution, whitened
// by the sigmas the front end states (6 values), is summed over L
// consecutive steps; for errors as stated, |sum|^2 / L follows chi-square
// with 6 degrees of freedom at every L, while a drift (errors of one sign
// over many steps) makes it grow with L. The factor on the stated variance
// is s = max over L = 1, 2, 4, ..., 64 of median(|sum_L|^2) / (L median of
// chi-square(6)), within [kMinOdometryScale, kMaxOdometryScale]; the
// odometry's sigmas are multiplied by sqrt(s).
#ifndef SYMBA_SRC_BACKEND_DETECTION_NOISE_H_
#define SYMBA_SRC_BACKEND_DETECTION_NOISE_H_

#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace symba::internal {

// The median of a chi-square distribution with 3 degrees of freedom: the
// median squared norm of a 3-D isotropic Gaussian error of unit variance
// per axis.
inline constexpr double kChiSquare3Median = 2.3659739;
// The same for 6 degrees of freedom.
inline constexpr double kChiSquare6Median = 5.3481206;
// Estimates never go below these (a detector that agrees with the map to
// the last bit must not make an infinite weight).
inline constexpr double kMinSigmaT = 1e-3;  // m
inline constexpr double kMinSigmaR = 1e-3;  // rad
// The largest correlation of consecutive errors the fit believes.
inline constexpr double kMaxCorrelation = 0.999;
// Lag bins: 1, 2-3, 4-7, ..., 256-511 keyframes.
inline constexpr int kLagBins = 9;
// A bin takes part in the fit with at least this many samples.
inline constexpr int kMinBinSamples = 5;
// The odometry factor s (variance) is kept within these.
inline constexpr double kMinOdometryScale = 1e-2;
inline constexpr double kMaxOdometryScale = 1e4;
// The longest run of odometry steps summed (a power of two).
inline constexpr int kMaxOdometryRun = 64;

// One pair of detections of an object.
struct LagSample {
  int lag = 0;                    // keyframes between them (>= 1); 0: level
  double squared_distance = 0.0;  // |difference|^2 (m^2 or rad^2)
};

// What a bin says: its mean lag and its per-axis variance.
struct LagBinSummary {
  double lag = 0.0;  // 0: the level
  double variance = 0.0;
  int count = 0;
};

// The last `window` samples of one lag bin.
class LagBin {
 public:
  explicit LagBin(int window) : window_(window) {}
  void Add(const LagSample& sample);
  int size() const { return static_cast<int>(samples_.size()); }
  // The bin must not be empty.
  LagBinSummary Summary() const;

 private:
  int window_;
  std::vector<LagSample> samples_;  // a ring once full
  size_t next_ = 0;
  mutable std::vector<double> scratch_;
};

// The fit (per-axis variances, m^2 or rad^2).
struct VariogramFit {
  double white = 0.0;
  double persistent = 0.0;
  double rho = 0.0;
  // The variance each detection is weighed with (above).
  double EffectiveVariance() const;
  // The spread of one detection around the truth.
  double ScatterVariance() const { return white + persistent; }
  // sqrt((1 + rho) / (1 - rho)): how much the persistence inflates the
  // persistent part's sigma.
  double Inflation() const;
};

// Fits the level (lag 0) and lag bins with at least kMinBinSamples samples;
// nullopt without the level or a lag bin.
std::optional<VariogramFit> FitVariogram(
    const std::vector<LagBinSummary>& bins);

// A class's noise, as the backend applies it.
struct ClassNoise {
  std::optional<double> sigma_t;    // m: weighs a detection's position
  std::optional<double> sigma_r;    // rad: weighs its rotation
  std::optional<double> scatter_t;  // m: gates its position
  std::optional<VariogramFit> translation;
  std::optional<VariogramFit> rotation;
  int samples_t = 0;  // levels
  int samples_r = 0;
};

class DetectionNoiseEstimator {
 public:
  // An estimate needs min_samples levels.
  DetectionNoiseEstimator(int window, int min_samples)
      : window_(window), min_samples_(min_samples) {}

  // lag 0: a level.
  void AddTranslation(const std::string& class_name, const LagSample& sample);
  void AddRotation(const std::string& class_name, const LagSample& sample);
  // Refits the class's variograms; Estimate returns the last refit.
  void Update(const std::string& class_name);
  ClassNoise Estimate(const std::string& class_name) const;
  // The classes with samples, sorted.
  std::vector<std::string> Classes() const;

 private:
  struct Variogram {
    explicit Variogram(int window);
    LagBin level;
    std::vector<LagBin> lags;
    int levels = 0;
  };
  static void Add(const LagSample& sample, Variogram* variogram);
  std::optional<VariogramFit> Fit(const Variogram& variogram) const;

  int window_;
  int min_samples_;
  std::map<std::string, Variogram> translation_;
  std::map<std::string, Variogram> rotation_;
  std::map<std::string, ClassNoise> estimates_;
};

// The odometry's residuals and the factor s on its stated variance (above).
class OdometryNoiseEstimator {
 public:
  // s needs min_samples sums at some L.
  OdometryNoiseEstimator(int window, int min_samples)
      : window_(window), min_samples_(min_samples) {}
  // One step's whitened residual; `follows` is false when the step does
  // not continue the previous one (a run of sums restarts).
  void Add(const Eigen::Matrix<double, 6, 1>& whitened, bool follows);
  // Recomputes s from the last `window` residuals.
  void Update();
  std::optional<double> Scale() const { return scale_; }
  int samples() const { return samples_; }

 private:
  int window_;
  int min_samples_;
  // The last `window` residuals, oldest first, and where runs restart.
  std::deque<Eigen::Matrix<double, 6, 1>> residuals_;
  std::deque<bool> follows_;
  int samples_ = 0;
  std::optional<double> scale_;
};

// The bin of a lag (>= 1), or -1 past the last bin.
int LagBinIndex(int lag);

// The noise an edge is built with. A detection that gives a sigma (the
// detector's word) is weighed with it unless the estimate exceeds it by
// more than `contradiction_ratio`: then the data win. A detection that
// gives none is weighed with the estimate once there is one, and with
// `given` (the options' initial noise) before.
double EffectiveSigma(double given,
                      bool claimed,
                      const std::optional<double>& estimate,
                      double contradiction_ratio);

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_DETECTION_NOISE_H_
