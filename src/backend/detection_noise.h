// The detector's noise, estimated from the data (docs/backend.md "Real
// detectors"). Real detectors claim a noise that is not theirs, or claim
// none, and their errors are not independent from frame to frame: a pose
// estimator that puts a box 5 cm too deep does so for many frames in a row,
// and a backend that takes each such detection as a new independent
// measurement drags the cameras along with the bias.
//
// Samples, per class, taken where the front end alone places things (the
// keyframe poses chained from the front end's motion, never optimised, so
// that no solve can absorb the error it is meant to measure):
//   level      the distance between a detection's world position and the
//              running mean of the earlier detections of its object (m),
//              and the angle between its rotation and their running mean
//              rotation (rad, asymmetric objects);
//   increment  the same between two detections of one object in
//              consecutive keyframes.
// The last `window` samples of each kind are kept.
//
// Estimate: |e| of isotropic Gaussian noise follows a chi distribution with
// 3 degrees of freedom, whose median is 1.5382 sigma:
//   sigma_L = median(level) / 1.5382           the scatter,
//   sigma_I = median(increment) / (1.5382 sqrt 2)  the frame-to-frame part.
// For errors that decay as an AR(1) process, rho = 1 - sigma_I^2 /
// sigma_L^2 is the correlation of consecutive errors and a run of N of them
// carries the information of N (1 - rho) / (1 + rho) independent ones, so
// each detection is weighed with
//   sigma = sigma_L sqrt((1 + rho) / (1 - rho)),   rho clamped to [0, 0.98]
// (independent errors: sigma = sigma_L). The medians ignore the few gross
// outliers a real detector has. An estimate exists once `min_samples`
// levels do (without increments rho = 0); it is never below kMinSigmaT/R.
//
// Claims: for detections that declare their sigma, a change d between two
// of them in consecutive keyframes has, per axis, the variance
// f^2 (sigma_a^2 + sigma_b^2) + s^2 (s^2 the step's motion variance), f = 1
// when the claims hold (ClaimPairs makes the samples). The claim scale is
// the f that makes the changes chi-square consistent, the median of
//   r_i(f) = |d_i| / sqrt(f^2 (sigma_a^2 + sigma_b^2)_i + s_i^2)
// equal to 1.5382. Each r_i falls as f grows and passes 1.5382 at
//   f_i = sqrt(max(0, |d_i|^2 / 1.5382^2 - s_i^2) / (sigma_a^2 + sigma_b^2)_i),
// so the median of the r_i exceeds 1.5382 exactly when f is below the
// median of the f_i: the scale is median(f_i) (0 where the steps alone
// explain the changes).
#ifndef SYMBA_SRC_BACKEND_DETECTION_NOISE_H_
#define SYMBA_SRC_BACKEND_DETECTION_NOISE_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "backend/object_track.h"
#include "common/median.h"
#include "common/recent_values.h"
#include "symba/backend/estimates.h"

namespace symba::internal {

// Estimates never go below these (a detector that agrees with the map to
// the last bit must not make an infinite weight).
inline constexpr double kMinSigmaT = 1e-3;  // m
inline constexpr double kMinSigmaR = 1e-3;  // rad
// The largest correlation of consecutive errors the estimate believes.
inline constexpr double kMaxCorrelation = 0.98;

// The median of the last `window` values added, over kChi3Median.
class RobustScale {
 public:
  explicit RobustScale(int window) : values_(window) {}
  void Add(double value) { values_.Add(value); }
  int size() const { return values_.size(); }
  // The values must not be empty.
  double Median() const;
  double Sigma() const;  // Median() / kChi3Median

 private:
  RecentValues<double> values_;
  mutable std::vector<double> scratch_;
};

// The last `window` pairs of a class's claimed detections (see above), each
// as the f_i its |d|^2, sigma_a^2 + sigma_b^2 and s^2 give.
class ClaimSamples {
 public:
  explicit ClaimSamples(int window) : scales_(window) {}
  void Add(double change_squared,
           double claimed_variance,
           double step_variance);
  int size() const { return scales_.size(); }
  // The claim scale median(f_i) (see above); the samples must not be empty.
  double Scale() const { return scales_.Median(); }

 private:
  RobustScale scales_;
};

// rho = 1 - sigma_I^2 / sigma_L^2, clamped to [0, kMaxCorrelation] (0 for
// a zero sigma_L).
double IncrementCorrelation(double sigma_level, double sigma_increment);
// sigma_L sqrt((1 + rho) / (1 - rho)) from a scale of levels and one of
// increments (see above).
double CorrelatedSigma(double sigma_level, double sigma_increment);
// (1 + rho) / (1 - rho): how much more a mean of N errors that persist as
// an AR(1) process with correlation rho (in [0, kMaxCorrelation]) varies
// than a mean of N independent ones.
inline double PersistenceVarianceFactor(double rho) {
  return (1.0 + rho) / (1.0 - rho);
}

// The factor a claim (a detector's sigmas, a front end's step) is weighed
// with, given the scale its samples give and the factor applied before:
// the scale once it exceeds `tolerance`, and from then on while it exceeds
// 1 (a scale that wobbles about the tolerance must not switch the factor on
// and off); else 1.
inline double HeldFactor(double scale, double before, double tolerance) {
  return scale > (before > 1.0 ? 1.0 : tolerance) ? scale : 1.0;
}

struct ClassNoise {
  std::optional<double> sigma_t;  // m
  std::optional<double> sigma_r;  // rad
  // The frame-to-frame part sigma_I alone, once there are min_samples
  // increments and the class has detections weighed by their hypotheses'
  // scatter (what those are held to).
  std::optional<double> white_sigma_t;  // m
  std::optional<double> white_sigma_r;  // rad
  // The claim scale, once there are min_samples claim ratios (see above).
  // In the noise applied to edges (ObjectEdges::ApplyNoise): the factor a
  // claimed sigma is multiplied by.
  std::optional<double> claim_scale_t;
  std::optional<double> claim_scale_r;
  // How much wider the detections' position errors are along their line of
  // sight than across it, kappa = sigma_along / sigma_across (one axis
  // each), once there are min_samples levels (SightAnisotropy).
  std::optional<double> sight_anisotropy;
};

// kappa from the medians of the level errors' parts along the line of
// sight (|e . u|) and across it (|e - (e . u) u|), each over its Gaussian
// median (one and two degrees of freedom); none where the across median is
// not positive.
std::optional<double> SightAnisotropy(double along_median,
                                      double across_median);

// What one kind of sample (translation or rotation) of a class says: the
// counts, sigma_L and sigma_I where there are min_samples of each, and the
// correlation rho and the factor sqrt((1 + rho) / (1 - rho)) they give.
// The public report's type (symba/backend/estimates.h).
using NoiseSamplesReport = ClassNoiseEstimate::Samples;

class DetectionNoiseEstimator {
 public:
  DetectionNoiseEstimator(int window, int min_samples)
      : window_(window), min_samples_(min_samples) {}

  enum class Kind { kLevel, kIncrement };
  void AddTranslation(const std::string& class_name, Kind kind, double error);
  void AddRotation(const std::string& class_name, Kind kind, double error);
  // A level error's parts along and across the detection's line of sight
  // (m; ClassNoise::sight_anisotropy).
  void AddSightLevel(const std::string& class_name,
                     double along,
                     double across);
  // Each sigma once it has min_samples levels.
  ClassNoise Estimate(const std::string& class_name) const;
  // The samples behind Estimate, for the report.
  NoiseSamplesReport TranslationReport(const std::string& class_name) const;
  NoiseSamplesReport RotationReport(const std::string& class_name) const;
  // A detection of the class weighed by its hypotheses' scatter, for the
  // report (it changes no estimate).
  void AddScatter(const std::string& class_name,
                  double sigma_t,
                  double sigma_r);
  // One pair of claimed detections (see above), translation or rotation.
  enum class Component { kTranslation, kRotation };
  void AddClaimPair(const std::string& class_name,
                    Component component,
                    double change_squared,
                    double claimed_variance,
                    double step_variance);
  // The class's translation sigma_I alone (TranslationReport's
  // sigma_increment, without the rest of the report).
  std::optional<double> TranslationIncrementSigma(
      const std::string& class_name) const {
    return IncrementSigma(translation_, class_name);
  }
  // One step of a confirmed object of the class (object_track.h), and the
  // class's reference ratio R over the last `window` steps with the given
  // sigma_I, once there are min_samples.
  void AddTrackStep(const std::string& class_name, const TrackStep& step);
  std::optional<double> TrackRatio(const std::string& class_name,
                                   double sigma_increment) const;
  ClassNoiseEstimate::Scatter ScatterReport(
      const std::string& class_name) const;
  ClassNoiseEstimate::Claims ClaimsReport(const std::string& class_name) const;
  // The classes with samples, sorted.
  std::vector<std::string> Classes() const;

 private:
  struct Scales {
    explicit Scales(int window) : level(window), increment(window) {}
    RobustScale level;
    RobustScale increment;
  };
  std::optional<double> Sigma(const std::map<std::string, Scales>& scales,
                              const std::string& class_name) const;
  std::optional<double> IncrementSigma(
      const std::map<std::string, Scales>& scales,
      const std::string& class_name) const;
  NoiseSamplesReport Report(const std::map<std::string, Scales>& scales,
                            const std::string& class_name) const;

  struct ScatterScales {
    explicit ScatterScales(int window) : sigma_t(window), sigma_r(window) {}
    int detections = 0;
    RobustScale sigma_t;
    RobustScale sigma_r;
  };

  std::optional<double> ClaimScale(
      const std::map<std::string, ClaimSamples>& claims,
      const std::string& class_name) const;

  int window_;
  int min_samples_;
  std::map<std::string, Scales> translation_;
  std::map<std::string, Scales> rotation_;
  std::map<std::string, ScatterScales> scatter_;
  struct SightScales {
    explicit SightScales(int window) : along(window), across(window) {}
    RobustScale along;
    RobustScale across;
  };
  std::map<std::string, SightScales> sight_;
  std::map<std::string, ClaimSamples> claim_t_;
  std::map<std::string, ClaimSamples> claim_r_;
  std::map<std::string, TrackReference> tracks_;
};

// The position noise (m) of an object's mean over its detections in n
// keyframes, each weighed with the class's estimate `sigma` (m): sigma^2 /
// n, plus the persistent part of the class's errors, sigma_L^2 rho from
// `samples` (0 before there is a sigma_L): errors that last longer than the
// AR(1) model's correlation time (a detector's bias for one viewpoint) do
// not average down over one object's views.
double ObjectMeanSigma(double sigma, int n, const NoiseSamplesReport& samples);

// The noise an edge is built with: a detection's own sigma (the detector's
// word) where it gives one; otherwise the larger of `given` (the options'
// floor for uncalibrated detectors, or the hypotheses' scatter) and the
// estimate (for a scatter, the class's white part), where there is one.
inline double EffectiveSigma(double given,
                             bool claimed,
                             const std::optional<double>& estimate) {
  return claimed || !estimate || *estimate < given ? given : *estimate;
}

}  // namespace symba::internal

#endif  // SYMBA_SRC_BACKEND_DETECTION_NOISE_H_
