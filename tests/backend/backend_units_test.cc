// Unit tests of the backend's internal units (src/backend/*.h): the noise
// estimator, the upgrade evidence, the association gates on hand-built
// object sets and the persistent window problem. Every expected value is
// derived in the comment next to it.
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "backend/association.h"
#include "backend/claim_pairs.h"
#include "backend/detection_noise.h"
#include "backend/detection_observations.h"
#include "backend/motion_claims.h"
#include "backend/upgrade_evidence.h"
#include "backend/window_problem.h"
#include "symba/categorization/categorize.h"
#include "symba/geometry/angle.h"
#include "test_support/hypothesis_generator.h"
#include "test_support/random.h"

namespace symba::internal {
namespace {

constexpr double kDeg = kPi / 180.0;

Eigen::Quaterniond Rot(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// ---------------------------------------------------------------------------
// Detection noise.

TEST(RobustScale, IsTheMedianOverTheChi3Median) {
  RobustScale scale(10);
  for (double v : {0.5, 0.1, 0.3, 9.0, 0.2}) scale.Add(v);
  // Sorted 0.1 0.2 0.3 0.5 9.0: median 0.3, the outlier does not count.
  EXPECT_DOUBLE_EQ(scale.Sigma(), 0.3 / kChi3Median);
  scale.Add(0.4);
  // 0.1 0.2 0.3 0.4 0.5 9.0: median (0.3 + 0.4) / 2.
  EXPECT_DOUBLE_EQ(scale.Sigma(), 0.35 / kChi3Median);
}

TEST(RobustScale, KeepsOnlyTheLastWindowValues) {
  RobustScale scale(3);
  for (double v : {1.0, 1.0, 1.0, 5.0, 6.0, 7.0}) scale.Add(v);
  EXPECT_EQ(scale.size(), 3);
  EXPECT_DOUBLE_EQ(scale.Sigma(), 6.0 / kChi3Median);
}

TEST(CorrelatedSigma, InflatesCorrelatedErrorsByTheirEffectiveCount) {
  // Independent errors: increments have the level's sigma, rho = 0.
  EXPECT_DOUBLE_EQ(CorrelatedSigma(0.1, 0.1), 0.1);
  // sigma_I = sigma_L / 2: rho = 1 - 1/4 = 0.75, factor sqrt(1.75 / 0.25).
  EXPECT_DOUBLE_EQ(CorrelatedSigma(0.1, 0.05), 0.1 * std::sqrt(7.0));
  // Larger increments than levels: rho clamps at 0.
  EXPECT_DOUBLE_EQ(CorrelatedSigma(0.1, 0.2), 0.1);
  // No increment: rho clamps at 0.98, factor sqrt(1.98 / 0.02) = sqrt(99).
  EXPECT_DOUBLE_EQ(CorrelatedSigma(0.1, 0.0), 0.1 * std::sqrt(99.0));
}

// A factor starts at the tolerance and holds while above 1.
TEST(HeldFactor, PassesTheToleranceThenHoldsAboveOne) {
  EXPECT_EQ(HeldFactor(1.4, 1.0, 1.5), 1.0);  // below the tolerance
  EXPECT_EQ(HeldFactor(1.6, 1.0, 1.5), 1.6);
  EXPECT_EQ(HeldFactor(1.1, 1.6, 1.5), 1.1);  // held while above 1
  EXPECT_EQ(HeldFactor(0.9, 1.6, 1.5), 1.0);
}

// The claim scale f makes the median of |d| / sqrt(f^2 c + s) the chi
// median: samples built so that f = 2 holds exactly give 2; samples the
// steps alone explain give 0.
TEST(ClaimSamples, TheScaleMakesTheChangesChiSquareConsistent) {
  ClaimSamples samples(10);
  for (const auto& [c, s] :
       {std::pair{1e-4, 0.0}, std::pair{4e-4, 1e-4}, std::pair{1e-4, 3e-4}}) {
    samples.Add(kChi3Median * kChi3Median * (4.0 * c + s), c, s);
  }
  EXPECT_NEAR(samples.Scale(), 2.0, 1e-9);
  ClaimSamples steps(10);
  for (int i = 0; i < 3; ++i) steps.Add(1e-4, 1e-4, 1.0);
  EXPECT_EQ(steps.Scale(), 0.0);
  // The window keeps the last 10: ten pairs at f = 5 outvote the rest.
  for (int i = 0; i < 10; ++i) {
    samples.Add(kChi3Median * kChi3Median * 25.0 * 1e-4, 1e-4, 0.0);
  }
  EXPECT_EQ(samples.size(), 10);
  EXPECT_NEAR(samples.Scale(), 5.0, 1e-9);
  // Pairs that each pass the chi median at another f_i (1, 3, 10): the
  // median of the ratios is the chi median at f = median f_i = 3.
  ClaimSamples mixed(10);
  for (const double f : {1.0, 3.0, 10.0}) {
    mixed.Add(kChi3Median * kChi3Median * (f * f * 1e-4 + 1e-5), 1e-4, 1e-5);
  }
  EXPECT_NEAR(mixed.Scale(), 3.0, 1e-9);
}

// A claimed detection pairs with the nearest one of its class in the
// previous keyframe: the change, the claims' variances and the step's
// (translation: s_t^2 + d^2 s_r^2) go into its class's claim scale, here
// from one pair (min_samples 1), so f solves f^2 c + s = |d|^2 / 1.5382^2.
TEST(ClaimPairs, PairsConsecutiveKeyframesOfAClassByDistance) {
  DetectionNoiseEstimator noise(100, 1);
  ClaimPairs pairs(0.5, 0.5);
  ClaimedDetection a;
  a.class_name = "box";
  a.p_w = Eigen::Vector3d(1.0, 0.0, 0.0);
  a.R_w = Eigen::Quaterniond::Identity();
  a.sigma_t = 0.01;
  a.sigma_r = 0.02;
  a.distance = 2.0;
  ClaimedDetection far = a;  // another box, 0.4 m from b
  far.p_w = Eigen::Vector3d(1.5, 0.0, 0.0);
  ClaimedDetection can = a;
  can.class_name = "can";
  pairs.Add(3, a, StepVariance{}, &noise, nullptr);
  pairs.Add(3, far, StepVariance{}, &noise, nullptr);
  pairs.Add(3, can, StepVariance{}, &noise, nullptr);
  EXPECT_EQ(noise.ClaimsReport("box").translation_samples, 0);
  ClaimedDetection b = a;
  b.p_w = Eigen::Vector3d(1.1, 0.0, 0.0);
  b.R_w = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  b.sigma_t = 0.02;
  const double s_t2 = 1e-6;
  const double s_r2 = 4e-6;
  pairs.Add(4, b, StepVariance{s_t2, s_r2}, &noise, nullptr);
  const ClassNoiseEstimate::Claims claims = noise.ClaimsReport("box");
  EXPECT_EQ(claims.translation_samples, 1);
  EXPECT_EQ(claims.rotation_samples, 1);
  const double chi2 = kChi3Median * kChi3Median;
  // Nearest: a at 0.1 m (not `far` at 0.4 m).
  const double f_t = std::sqrt((0.01 / chi2 - (s_t2 + 4.0 * s_r2)) /
                               (0.01 * 0.01 + 0.02 * 0.02));
  const double f_r =
      std::sqrt((0.01 / chi2 - s_r2) / (0.02 * 0.02 + 0.02 * 0.02));
  EXPECT_NEAR(*claims.scale_t, f_t, 1e-6 * f_t);
  EXPECT_NEAR(*claims.scale_r, f_r, 1e-6 * f_r);
  EXPECT_EQ(noise.ClaimsReport("can").translation_samples, 0);

  // Not consecutive (keyframe 6 after 4): no pair; a rotation pair turned
  // beyond max_angle gives a translation sample only; beyond max_distance
  // there is no pair.
  pairs.Add(6, a, StepVariance{}, &noise, nullptr);
  ClaimedDetection turned = a;
  turned.R_w =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ()));
  pairs.Add(7, turned, StepVariance{}, &noise, nullptr);
  EXPECT_EQ(noise.ClaimsReport("box").translation_samples, 2);
  EXPECT_EQ(noise.ClaimsReport("box").rotation_samples, 1);
  ClaimedDetection away = a;
  away.p_w = Eigen::Vector3d(1.0, 0.6, 0.0);
  pairs.Add(8, away, StepVariance{}, &noise, nullptr);
  EXPECT_EQ(noise.ClaimsReport("box").translation_samples, 2);
  // An unclaimed component gives no sample.
  ClaimedDetection unclaimed = away;
  unclaimed.sigma_r.reset();
  pairs.Add(9, unclaimed, StepVariance{}, &noise, nullptr);
  EXPECT_EQ(noise.ClaimsReport("box").translation_samples, 3);
  EXPECT_EQ(noise.ClaimsReport("box").rotation_samples, 1);
  // A keyframe whose motion factor does not start at the previous one
  // pairs with nothing, but the next keyframe pairs with it.
  pairs.Add(10, away, std::nullopt, &noise, nullptr);
  EXPECT_EQ(noise.ClaimsReport("box").translation_samples, 3);
  pairs.Add(11, away, StepVariance{}, &noise, nullptr);
  EXPECT_EQ(noise.ClaimsReport("box").translation_samples, 4);
}

// An object's mean: sigma / sqrt(n) without samples; with a level sigma
// of 2 cm and rho 0.81, the persistent 0.02^2 0.81 stays however many
// keyframes saw it.
TEST(ObjectMeanSigma, KeepsThePersistentPartOfTheErrors) {
  NoiseSamplesReport none;
  EXPECT_DOUBLE_EQ(ObjectMeanSigma(0.04, 16, none), 0.01);
  EXPECT_DOUBLE_EQ(ObjectMeanSigma(0.04, 0, none), 0.04);
  NoiseSamplesReport persistent;
  persistent.sigma_level = 0.02;
  persistent.correlation = 0.81;
  EXPECT_NEAR(ObjectMeanSigma(0.04, 16, persistent),
              std::sqrt(0.01 * 0.01 + 0.02 * 0.02 * 0.81),
              1e-15);
  EXPECT_NEAR(ObjectMeanSigma(0.04, 1000000, persistent), 0.018, 1e-6);
}

TEST(DetectionNoiseEstimator, EstimatesPerClassOnceThereAreEnoughSamples) {
  using Kind = DetectionNoiseEstimator::Kind;
  DetectionNoiseEstimator noise(100, 3);
  noise.AddTranslation("box", Kind::kLevel, 0.2);
  noise.AddTranslation("box", Kind::kLevel, 0.2);
  EXPECT_FALSE(noise.Estimate("box").sigma_t.has_value());
  noise.AddTranslation("box", Kind::kLevel, 0.2);
  // Levels only: sigma_L.
  ASSERT_TRUE(noise.Estimate("box").sigma_t.has_value());
  EXPECT_DOUBLE_EQ(*noise.Estimate("box").sigma_t, 0.2 / kChi3Median);
  EXPECT_FALSE(noise.Estimate("box").sigma_r.has_value());
  EXPECT_FALSE(noise.Estimate("can").sigma_t.has_value());
  // Increments of 0.2 sqrt(2) / 2: sigma_I = sigma_L / 2 (rho = 0.75).
  for (int i = 0; i < 3; ++i) {
    noise.AddTranslation("box", Kind::kIncrement, 0.1 * std::sqrt(2.0));
  }
  EXPECT_NEAR(*noise.Estimate("box").sigma_t,
              0.2 / kChi3Median * std::sqrt(7.0),
              1e-12);
  // Never below the floor.
  for (int i = 0; i < 3; ++i) noise.AddRotation("can", Kind::kLevel, 0.0);
  EXPECT_DOUBLE_EQ(*noise.Estimate("can").sigma_r, kMinSigmaR);
}

TEST(DetectionNoiseEstimator, TheSightAnisotropyIsAlongOverAcross) {
  // Gaussian errors of sigma 3 along the line of sight and 1 across (per
  // axis): medians 3 kChi1Median and kChi2Median, kappa 3.
  EXPECT_NEAR(*SightAnisotropy(3.0 * kChi1Median, kChi2Median), 3.0, 1e-12);
  EXPECT_FALSE(SightAnisotropy(0.1, 0.0).has_value());
  DetectionNoiseEstimator noise(100, 3);
  noise.AddSightLevel("box", 0.04, 0.01);
  noise.AddSightLevel("box", 0.02, 0.03);
  EXPECT_FALSE(noise.Estimate("box").sight_anisotropy.has_value());
  noise.AddSightLevel("box", 0.06, 0.02);
  // Medians 0.04 and 0.02.
  ASSERT_TRUE(noise.Estimate("box").sight_anisotropy.has_value());
  EXPECT_NEAR(*noise.Estimate("box").sight_anisotropy,
              (0.04 / kChi1Median) / (0.02 / kChi2Median),
              1e-12);
}

TEST(DetectionNoiseEstimator, ReportsTheSamplesBehindEachEstimate) {
  using Kind = DetectionNoiseEstimator::Kind;
  DetectionNoiseEstimator noise(100, 3);
  EXPECT_TRUE(noise.Classes().empty());
  for (int i = 0; i < 3; ++i) {
    noise.AddTranslation("box", Kind::kLevel, 0.2);
    noise.AddRotation("can", Kind::kLevel, 0.1);
  }
  noise.AddTranslation("box", Kind::kIncrement, 0.1 * std::sqrt(2.0));
  EXPECT_EQ(noise.Classes(), (std::vector<std::string>{"box", "can"}));
  NoiseSamplesReport report = noise.TranslationReport("box");
  EXPECT_EQ(report.levels, 3);
  EXPECT_EQ(report.increments, 1);
  ASSERT_TRUE(report.sigma_level.has_value());
  EXPECT_DOUBLE_EQ(*report.sigma_level, 0.2 / kChi3Median);
  // One increment is fewer than min_samples: no sigma_I, no correlation.
  EXPECT_FALSE(report.sigma_increment.has_value());
  EXPECT_DOUBLE_EQ(report.correlation, 0.0);
  EXPECT_DOUBLE_EQ(report.inflation, 1.0);
  // sigma_I = sigma_L / 2: rho = 0.75, inflation sqrt(7), as the estimate.
  noise.AddTranslation("box", Kind::kIncrement, 0.1 * std::sqrt(2.0));
  noise.AddTranslation("box", Kind::kIncrement, 0.1 * std::sqrt(2.0));
  report = noise.TranslationReport("box");
  EXPECT_NEAR(*report.sigma_increment, 0.1 / kChi3Median, 1e-15);
  EXPECT_NEAR(report.correlation, 0.75, 1e-12);
  EXPECT_NEAR(report.inflation, std::sqrt(7.0), 1e-12);
  EXPECT_NEAR(*report.sigma_level * report.inflation,
              *noise.Estimate("box").sigma_t,
              1e-12);
  EXPECT_EQ(noise.RotationReport("box").levels, 0);
  EXPECT_EQ(noise.RotationReport("can").levels, 3);
}

// The white part (sigma_I alone) exists only for a class with detections
// measured by their scatter; the scatter report gives their count and
// median sigmas.
TEST(DetectionNoiseEstimator, TheWhitePartHoldsOnlyAScatteredClass) {
  using Kind = DetectionNoiseEstimator::Kind;
  DetectionNoiseEstimator noise(100, 3);
  for (int i = 0; i < 3; ++i) {
    noise.AddTranslation("box", Kind::kLevel, 0.2);
    noise.AddTranslation("box", Kind::kIncrement, 0.1 * std::sqrt(2.0));
  }
  EXPECT_FALSE(noise.Estimate("box").white_sigma_t.has_value());
  EXPECT_EQ(noise.ScatterReport("box").detections, 0);
  EXPECT_FALSE(noise.ScatterReport("box").sigma_t.has_value());
  noise.AddScatter("box", 0.03, 0.05);
  noise.AddScatter("box", 0.01, 0.07);
  noise.AddScatter("box", 0.02, 0.06);
  // sigma_I = median(0.1 sqrt 2) / (kChi3Median sqrt 2).
  ASSERT_TRUE(noise.Estimate("box").white_sigma_t.has_value());
  EXPECT_NEAR(*noise.Estimate("box").white_sigma_t, 0.1 / kChi3Median, 1e-15);
  EXPECT_FALSE(noise.Estimate("box").white_sigma_r.has_value());
  const ClassNoiseEstimate::Scatter report = noise.ScatterReport("box");
  EXPECT_EQ(report.detections, 3);
  EXPECT_DOUBLE_EQ(*report.sigma_t, 0.02);
  EXPECT_DOUBLE_EQ(*report.sigma_r, 0.06);
  // A class with scatters only is listed too.
  noise.AddScatter("can", 0.01, 0.01);
  EXPECT_EQ(noise.Classes(), (std::vector<std::string>{"box", "can"}));
}

// A detection is weighed by its scatter only when it gives no sigma, the
// noise is estimated, scatter_min_hypotheses allows it, and its inliers are
// that many and spread at all.
TEST(UsableScatter, OnlyAnUndeclaredSpreadDetectionOfEnoughHypotheses) {
  testing::TestRandom random(3);
  testing::HypothesisSetSpec spec;
  spec.type = SymmetryType::kAsymmetric;
  DetectionInput detection;
  detection.class_name = "box";
  detection.hypotheses = testing::GenerateDetection(spec, &random).hypotheses;
  const BackendOptions options;
  auto scatter = [](const DetectionInput& d, const BackendOptions& o) {
    CategorizedDetection cat;
    EXPECT_TRUE(Categorize(d.hypotheses, o.categorization, nullptr, &cat).ok());
    return UsableScatter(d, cat, o);
  };
  const std::optional<HypothesisScatter> measured = scatter(detection, options);
  ASSERT_TRUE(measured.has_value());
  EXPECT_NEAR(
      measured->sigma_t, spec.translation_sigma, 0.5 * spec.translation_sigma);
  // The detection's own word wins, even on one sigma.
  DetectionInput declared = detection;
  declared.sigma_r = 0.1;
  EXPECT_FALSE(scatter(declared, options).has_value());
  BackendOptions off = options;
  off.scatter_min_hypotheses = 0;
  EXPECT_FALSE(scatter(detection, off).has_value());
  off = options;
  off.estimate_noise = false;
  EXPECT_FALSE(scatter(detection, off).has_value());
  // Four hypotheses, five needed.
  DetectionInput few = detection;
  few.hypotheses.resize(4);
  EXPECT_FALSE(scatter(few, options).has_value());
  // Thirty copies of one pose say nothing of the noise.
  DetectionInput copies = detection;
  copies.hypotheses.assign(30, detection.hypotheses.front());
  EXPECT_FALSE(scatter(copies, options).has_value());
}

TEST(EffectiveSigma, ClaimsWinThenTheLargerOfFloorAndEstimate) {
  EXPECT_DOUBLE_EQ(EffectiveSigma(0.03, true, 0.5), 0.03);  // the claim
  EXPECT_DOUBLE_EQ(EffectiveSigma(2.0, false, 0.5), 2.0);   // the floor
  EXPECT_DOUBLE_EQ(EffectiveSigma(2.0, false, 3.0), 3.0);   // the estimate
  EXPECT_DOUBLE_EQ(EffectiveSigma(2.0, false, std::nullopt), 2.0);
}

// ---------------------------------------------------------------------------
// Upgrade evidence.

TEST(PlausibleOrder, IsTheSmallestOrderTheAngleFits) {
  const double tolerance = 10 * kDeg;
  EXPECT_EQ(PlausibleOrder(kPi, 4, tolerance), 2);
  EXPECT_EQ(PlausibleOrder(-kPi + 5 * kDeg, 4, tolerance), 2);
  EXPECT_EQ(PlausibleOrder(90 * kDeg, 4, tolerance), 4);
  EXPECT_EQ(PlausibleOrder(-95 * kDeg, 4, tolerance), 4);
  EXPECT_EQ(PlausibleOrder(120 * kDeg, 4, tolerance), 3);
  // 60 deg needs order 6 and 150 deg order 5 (144 deg), beyond 4: the
  // default max_upgrade_order keeps such "symmetries" out. 5 deg fits none.
  EXPECT_EQ(PlausibleOrder(60 * kDeg, 4, tolerance), 0);
  EXPECT_EQ(PlausibleOrder(60 * kDeg, 6, tolerance), 6);
  EXPECT_EQ(PlausibleOrder(150 * kDeg, 4, tolerance), 0);
  EXPECT_EQ(PlausibleOrder(150 * kDeg, 6, tolerance), 5);
  EXPECT_EQ(PlausibleOrder(5 * kDeg, 6, tolerance), 0);
  EXPECT_TRUE(FitsOrder(240 * kDeg, 3, tolerance));  // -120 deg
  EXPECT_FALSE(FitsOrder(100 * kDeg, 2, tolerance));
}

TEST(ConsistentFlips, CountsAgreeingFlipsOncePerKeyframe) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  std::vector<FlipEvidence> flips = {
      {1, z, 178 * kDeg},
      {1, z, 176 * kDeg},                  // same keyframe: not again
      {3, -z, 174 * kDeg},                 // the axis sign is free
      {4, Eigen::Vector3d::UnitX(), kPi},  // another axis
      {5, z, 90 * kDeg},                   // another angle
      {6, Rot(Eigen::Vector3d::UnitX(), 10 * kDeg) * z, 170 * kDeg},
  };
  const FlipConsensus consensus =
      ConsistentFlips(flips, {6, z, 176 * kDeg}, 20 * kDeg, 20 * kDeg);
  EXPECT_EQ(consensus.count, 3);  // keyframes 1, 3, 6
  EXPECT_NEAR(consensus.mean_angle, (178 + 174 + 170) / 3.0 * kDeg, 1e-12);
}

// ln[(1/3)^m (2/3)^(n-m) / (c^m (1-c)^(n-m))], m the smaller count, n both.
TEST(TwoRotationsLogOdds, IsTheLikelihoodRatioOfTwoRecurringRotations) {
  // m = 3, n = 6, c = 0.05: 3 ln(20/3) + 3 ln((2/3)/0.95).
  EXPECT_NEAR(TwoRotationsLogOdds(3, 3, 0.05), 4.628844513495802, 1e-12);
  // m = 2, n = 5: 2 ln(20/3) + 3 ln((2/3)/0.95).
  EXPECT_NEAR(TwoRotationsLogOdds(2, 3, 0.05), 2.731724528609921, 1e-12);
  EXPECT_DOUBLE_EQ(TwoRotationsLogOdds(3, 2, 0.05),
                   TwoRotationsLogOdds(2, 3, 0.05));
  // One unflipped view (an object made from a turned detection) never
  // reaches odds 100, however many flips agree: each lowers the odds.
  EXPECT_LT(TwoRotationsLogOdds(1, 3, 0.05), std::log(100.0));
  EXPECT_LT(TwoRotationsLogOdds(1, 50, 0.05), TwoRotationsLogOdds(1, 3, 0.05));
  // A 2-fold object seen at random: half and half passes at 3 and 3.
  EXPECT_GE(TwoRotationsLogOdds(3, 3, 0.05), std::log(100.0));
}

// (n1 - n0) ln((1 - c) / c) >= ln(odds) and -TwoRotationsLogOdds >= ln(odds).
TEST(FlipsOutvoteTheRotation, NeedsTheFlipsToRejectASymmetryToo) {
  // One view and 18 flips: a symmetry has odds exp(1.897 - 18 * 0.354) =
  // exp(-4.48) > 1/100; 19 flips: exp(-4.83) < 1/100.
  EXPECT_FALSE(FlipsOutvoteTheRotation(1, 18, 0.05, 100.0));
  EXPECT_TRUE(FlipsOutvoteTheRotation(1, 19, 0.05, 100.0));
  // A symmetric object's two rotations recur: never.
  EXPECT_FALSE(FlipsOutvoteTheRotation(10, 12, 0.05, 100.0));
  EXPECT_FALSE(FlipsOutvoteTheRotation(30, 60, 0.05, 100.0));  // 4-fold
  // More views than flips: never.
  EXPECT_FALSE(FlipsOutvoteTheRotation(19, 1, 0.05, 100.0));
}

TEST(ClassFlipCounts, FlipsAsSymmetricComparesTheOrdersShare) {
  ClassFlipCounts counts;
  counts.keyframes = 40;
  counts.flip_keyframes_by_order = {{2, 12}, {4, 11}};
  EXPECT_TRUE(counts.FlipsAsSymmetric(2, 0.3));   // 12 >= 0.3 * 40
  EXPECT_FALSE(counts.FlipsAsSymmetric(4, 0.3));  // 11 < 12
  EXPECT_FALSE(counts.FlipsAsSymmetric(3, 0.0));  // no flip of order 3
}

// ---------------------------------------------------------------------------
// Association on hand-built objects.

std::unique_ptr<ObjectState> AsymmetricObject(int id,
                                              const std::string& class_name,
                                              const Rigid3d& T_wo,
                                              ObjectStatus status) {
  auto object = std::make_unique<ObjectState>();
  object->id = id;
  object->class_name = class_name;
  object->status = status;
  Eigen::Map<Eigen::Quaterniond>(object->q) = T_wo.q;
  Eigen::Map<Eigen::Vector3d>(object->t) = T_wo.t;
  return object;
}

TEST(HighestWeight, TheFirstOfTheHeaviestOfAllOrOfSome) {
  std::vector<PoseHypothesis> hyps(4);
  for (size_t j = 0; j < hyps.size(); ++j) hyps[j].weight = 1.0;
  hyps[1].weight = 3.0;
  hyps[3].weight = 3.0;
  EXPECT_EQ(HighestWeight(hyps), 1);
  EXPECT_EQ(HighestWeight(hyps, {0, 2, 3}), 3);
  EXPECT_EQ(HighestWeight(hyps, AllIndices(hyps.size())), 1);
  hyps.resize(1);
  EXPECT_EQ(HighestWeight(hyps), 0);
}

TEST(PositionGate, CombinesDetectionObjectAndPrediction) {
  BackendOptions options;
  options.gate_position = 0.5;
  options.gate_sigmas = 3.0;
  ObjectState object;
  AssociationScope scope;
  EXPECT_DOUBLE_EQ(PositionGate(object, scope, options), 0.5);  // unknown
  scope.sigma_t = 0.04;
  object.observations.resize(3);
  // 3 sqrt(0.04^2 (1 + 1/3)) = 0.12 / sqrt(0.75).
  EXPECT_NEAR(PositionGate(object, scope, options),
              3.0 * 0.04 * std::sqrt(4.0 / 3.0),
              1e-12);
  scope.prediction_variance = 0.01;
  EXPECT_NEAR(PositionGate(object, scope, options),
              3.0 * std::sqrt(0.0016 * 4.0 / 3.0 + 0.01),
              1e-12);
  scope.sigma_t = 1.0;  // capped by gate_position
  EXPECT_DOUBLE_EQ(PositionGate(object, scope, options), 0.5);
  options.gate_sigmas = 0.0;
  scope.sigma_t = 0.01;
  EXPECT_DOUBLE_EQ(PositionGate(object, scope, options), 0.5);
}

TEST(PositionGate, GrowsWithTheCamerasMotionSinceThePlaceWasSeen) {
  BackendOptions options;
  options.gate_position = 0.5;
  options.gate_sigmas = 3.0;
  ObjectState object;
  object.observations.resize(3);
  AssociationScope scope;
  scope.sigma_t = 0.04;
  scope.prediction_variance = 0.001;
  scope.place_variance = 0.004;  // the larger one counts
  scope.place_object = &object;
  EXPECT_NEAR(PositionGate(object, scope, options),
              3.0 * std::sqrt(0.0016 * 4.0 / 3.0 + 0.004),
              1e-12);
  scope.place_variance = 0.0005;
  EXPECT_NEAR(PositionGate(object, scope, options),
              3.0 * std::sqrt(0.0016 * 4.0 / 3.0 + 0.001),
              1e-12);
}

TEST(PlaceLastSeen, IsTheLatestKeyframeBeforeThisOneThatSawAnObjectNearby) {
  BackendOptions options;  // gate_position 0.5 m
  const Rigid3d pose(Eigen::Quaterniond::Identity(), {0, 0, 0});
  ObjectList objects;
  objects.push_back(
      AsymmetricObject(0, "chair", pose, ObjectStatus::kConfirmed));
  objects.push_back(AsymmetricObject(
      1, "table", Rigid3d(pose.q, {0.3, 0, 0}), ObjectStatus::kTentative));
  objects.push_back(AsymmetricObject(
      2, "chair", Rigid3d(pose.q, {2.0, 0, 0}), ObjectStatus::kConfirmed));
  objects[0]->last_keyframe = 2;
  objects[1]->last_keyframe = 4;  // the nearby table, any class
  objects[2]->last_keyframe = 8;  // too far from the detection
  const Eigen::Vector3d t_w(0.1, 0.0, 0.0);
  EXPECT_EQ(PlaceLastSeen(objects, 9, t_w, options), 4);
  // Detected in keyframe 9 already: not seen before it.
  objects[1]->last_keyframe = 9;
  EXPECT_EQ(PlaceLastSeen(objects, 9, t_w, options), 2);
  objects[1]->last_keyframe = 4;
  // A dropped object is no place; nothing seen near the detection: -1.
  objects[1]->status = ObjectStatus::kDropped;
  EXPECT_EQ(PlaceLastSeen(objects, 9, t_w, options), 2);
  objects[0]->last_keyframe = -1;
  EXPECT_EQ(PlaceLastSeen(objects, 9, t_w, options), -1);
}

TEST(PlaceGrowth, SumsTheMotionVariancesSinceThePlaceWasSeen) {
  std::vector<std::unique_ptr<KeyframeState>> keyframes;
  for (int k = 0; k < 10; ++k) {  // 1 mm^2 and 1e-4 rad^2 per step
    keyframes.push_back(std::make_unique<KeyframeState>());
    keyframes.back()->summed_motion_variance_t = 1e-6 * k;
    keyframes.back()->summed_motion_variance_r = 1e-4 * k;
  }
  // Seen at keyframe 4, now keyframe 9, 2 m away: 5 (1e-6 + 4 * 1e-4).
  EXPECT_NEAR(PlaceGrowth(keyframes, 4, 9, 2.0), 5 * (1e-6 + 4e-4), 1e-15);
  EXPECT_EQ(PlaceGrowth(keyframes, -1, 9, 2.0), 0.0);  // never seen
}

// Two detections of a keyframe 2 m from the camera, the object's noise 3
// cm: one step's gate 5 sqrt(0.03^2 (1 + 1/1) + 1e-4) = 0.218 m, the gate
// grown by 0.01 m^2 min(0.5, 0.543) = 0.5 m.
RevisitDetection Revisiting(const std::string& class_name,
                            const Eigen::Vector3d& t_w,
                            double place_variance) {
  static const std::string chair = "chair";
  static const std::string table = "table";
  RevisitDetection detection;
  detection.class_name = class_name == chair ? &chair : &table;
  detection.t_w = t_w;
  detection.distance = 2.0;
  detection.scope.sigma_t = 0.03;
  detection.scope.prediction_variance = 1e-4;
  detection.scope.place_variance = place_variance;
  return detection;
}

// The gates' variances and objects, for comparison.
std::vector<std::pair<double, int>> Gates(
    const ObjectList& objects,
    const std::vector<RevisitDetection>& detections,
    const BackendOptions& options) {
  std::vector<std::pair<double, int>> out;
  for (const RevisitGate& gate : RevisitGates(objects, detections, options)) {
    out.emplace_back(gate.variance, gate.object);
  }
  return out;
}

using Gate = std::pair<double, int>;

TEST(RevisitGates, AGrownGateNeedsAPlaceOfOneObjectOrAShiftTheOthersShare) {
  BackendOptions options;  // gate_position 0.5 m, gate_sigmas 5
  const Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  ObjectList objects;
  objects.push_back(AsymmetricObject(
      0, "chair", Rigid3d(q, {0, 0, 0}), ObjectStatus::kConfirmed));
  const Gate none(0.0, -1);
  // A place of one object, 0.3 m off: beyond one step's gate, within the
  // grown one, which applies to that object.
  EXPECT_EQ(Gates(objects, {Revisiting("chair", {0.3, 0, 0}, 0.01)}, options),
            (std::vector<Gate>{{0.01, 0}}));
  // Within one step's gate: no revisit; a growth smaller than one step's:
  // none.
  EXPECT_EQ(Gates(objects, {Revisiting("chair", {0.1, 0, 0}, 0.01)}, options),
            (std::vector<Gate>{none}));
  EXPECT_EQ(Gates(objects, {Revisiting("chair", {0.3, 0, 0}, 5e-5)}, options),
            (std::vector<Gate>{none}));
  // A table 1 m away (within the detections' 2 m): the chair needs the
  // table's detection moved by the same shift, and gives the table its.
  objects.push_back(AsymmetricObject(
      1, "table", Rigid3d(q, {1, 0, 0}), ObjectStatus::kConfirmed));
  EXPECT_EQ(Gates(objects,
                  {Revisiting("chair", {0.3, 0, 0}, 0.01),
                   Revisiting("table", {1.3, 0.05, 0}, 0.01)},
                  options),
            (std::vector<Gate>{{0.01, 0}, {0.01, 1}}));
  // The table's detection does not move with the chair's (0.67 m from the
  // table once moved): the chair's detection may have been carried near
  // this chair from elsewhere, and keeps one step's gate.
  EXPECT_EQ(Gates(objects,
                  {Revisiting("chair", {0.3, 0, 0}, 0.01),
                   Revisiting("table", {1.0, 0.6, 0}, 0.01)},
                  options),
            (std::vector<Gate>{none, none}));
  // Alone in the keyframe, with the table in the place: nothing shares it.
  EXPECT_EQ(Gates(objects, {Revisiting("chair", {0.3, 0, 0}, 0.01)}, options),
            (std::vector<Gate>{none}));
  // A second chair within one step's gate of the detection: no revisit,
  // whatever the grown gate would reach.
  objects.push_back(AsymmetricObject(
      2, "chair", Rigid3d(q, {0.4, 0.1, 0}), ObjectStatus::kTentative));
  EXPECT_EQ(Gates(objects,
                  {Revisiting("chair", {0.3, 0, 0}, 0.01),
                   Revisiting("table", {1.3, 0.05, 0}, 0.01)},
                  options)[0],
            none);
}

TEST(PositionGate, TheGrownGateIsThePlaceObjectsOnly) {
  BackendOptions options;
  options.gate_position = 0.5;
  options.gate_sigmas = 3.0;
  ObjectState object;
  ObjectState other;
  object.observations.resize(3);
  other.observations.resize(3);
  AssociationScope scope;
  scope.sigma_t = 0.04;
  scope.prediction_variance = 0.001;
  scope.place_variance = 0.004;
  scope.place_object = &object;
  EXPECT_NEAR(PositionGate(object, scope, options),
              3.0 * std::sqrt(0.0016 * 4.0 / 3.0 + 0.004),
              1e-12);
  EXPECT_NEAR(PositionGate(other, scope, options),
              3.0 * std::sqrt(0.0016 * 4.0 / 3.0 + 0.001),
              1e-12);
}

TEST(FindSixDofMatch, GatesPositionRotationClassAndStatus) {
  BackendOptions options;  // gate 0.5 m, 30 deg
  ObjectList objects;
  objects.push_back(
      AsymmetricObject(0,
                       "chair",
                       Rigid3d(Eigen::Quaterniond::Identity(), {0, 0, 0}),
                       ObjectStatus::kConfirmed));
  objects.push_back(
      AsymmetricObject(1,
                       "chair",
                       Rigid3d(Eigen::Quaterniond::Identity(), {0.3, 0, 0}),
                       ObjectStatus::kTentative));
  objects.push_back(
      AsymmetricObject(2,
                       "table",
                       Rigid3d(Eigen::Quaterniond::Identity(), {0.1, 0, 0}),
                       ObjectStatus::kConfirmed));
  AssociationScope confirmed;
  AssociationScope tentative;
  tentative.status = ObjectStatus::kTentative;
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  // 0.2 m from object 0, 0.1 m from tentative object 1.
  const Rigid3d near(Rot(z, 10 * kDeg), {0.2, 0, 0});
  EXPECT_EQ(FindSixDofMatch(objects, "chair", {near}, confirmed, options), 0);
  EXPECT_EQ(FindSixDofMatch(objects, "chair", {near}, tentative, options), 1);
  EXPECT_EQ(FindSixDofMatch(objects, "table", {near}, confirmed, options), 2);
  EXPECT_EQ(FindSixDofMatch(objects, "bed", {near}, confirmed, options), -1);
  // Rotation beyond 30 deg, position beyond 0.5 m.
  const Rigid3d turned(Rot(z, 40 * kDeg), {0, 0, 0});
  const Rigid3d far(Eigen::Quaterniond::Identity(), {0.6, 0, 0});
  EXPECT_EQ(FindSixDofMatch(objects, "chair", {turned}, confirmed, options),
            -1);
  EXPECT_EQ(FindSixDofMatch(objects, "chair", {far}, confirmed, options), -1);
  // Any candidate may match (MH).
  EXPECT_EQ(
      FindSixDofMatch(objects, "chair", {turned, near}, confirmed, options), 0);
  // The detection's noise tightens the position gate: 3 sigma.
  options.gate_sigmas = 3.0;
  confirmed.sigma_t = 0.05;  // n = 0 counts as 1: 3 * 0.05 * sqrt(2) = 0.21
  EXPECT_EQ(FindSixDofMatch(objects, "chair", {near}, confirmed, options), 0);
  confirmed.sigma_t = 0.04;  // 0.17 < 0.2
  EXPECT_EQ(FindSixDofMatch(objects, "chair", {near}, confirmed, options), -1);
}

CategorizedDetection AsymmetricDetection(const Rigid3d& T_co) {
  CategorizedDetection cat;
  cat.type = SymmetryType::kAsymmetric;
  cat.T_co_base = T_co;
  cat.t_co = T_co.t;
  cat.inliers = {0};
  return cat;
}

TEST(FindSymbaMatch, AFlipIsEvidenceNotAnUpgrade) {
  BackendOptions options;
  ObjectList objects;
  objects.push_back(
      AsymmetricObject(0,
                       "box",
                       Rigid3d(Eigen::Quaterniond::Identity(), {0, 0, 2}),
                       ObjectStatus::kConfirmed));
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  // A one-hypothesis asymmetric detection turned by `angle` about z, seen
  // from the identity camera.
  auto match_turned = [&](double angle, const ClassPrior* prior) {
    const Rigid3d T_co(Rot(z, angle), {0.05, 0, 2});
    return FindSymbaMatch(objects,
                          Rigid3d(),
                          AsymmetricDetection(T_co),
                          "box",
                          {{T_co, 1.0}},
                          prior,
                          {},
                          options);
  };
  // Nearly the same pose: a 6-DoF match.
  SymbaMatch match = match_turned(5 * kDeg, nullptr);
  EXPECT_EQ(match.object, 0);
  EXPECT_FALSE(match.flip);
  EXPECT_FALSE(match.upgrade);
  // Turned by 178 deg: a flip with that axis and angle.
  match = match_turned(178 * kDeg, nullptr);
  EXPECT_EQ(match.object, 0);
  EXPECT_TRUE(match.flip);
  EXPECT_FALSE(match.upgrade);
  EXPECT_NEAR(std::abs(match.a_o.dot(z)), 1.0, 1e-9);
  EXPECT_NEAR(match.flip_angle, 178 * kDeg, 1e-9);
  // An asymmetric class prior forbids it: no match at all.
  ClassPrior asymmetric;
  asymmetric.symmetry = SymmetryType::kAsymmetric;
  EXPECT_EQ(match_turned(178 * kDeg, &asymmetric).object, -1);
}

TEST(FindSymbaMatch, ASymmetricDetectionUpgradesAnAsymmetricObject) {
  BackendOptions options;
  ObjectList objects;
  objects.push_back(
      AsymmetricObject(0,
                       "table",
                       Rigid3d(Eigen::Quaterniond::Identity(), {0, 0, 2}),
                       ObjectStatus::kConfirmed));
  CategorizedDetection cat;
  cat.type = SymmetryType::kDiscrete;
  cat.axis_o = Eigen::Vector3d::UnitZ();
  cat.axis_c = Eigen::Vector3d::UnitZ();
  cat.t_co = Eigen::Vector3d(0, 0.1, 2);
  cat.T_co_base = Rigid3d(Eigen::Quaterniond::Identity(), cat.t_co);
  const SymbaMatch match = FindSymbaMatch(
      objects, Rigid3d(), cat, "table", {}, nullptr, {}, options);
  EXPECT_EQ(match.object, 0);
  EXPECT_TRUE(match.upgrade);
  EXPECT_TRUE(match.a_o.isApprox(Eigen::Vector3d::UnitZ()));
  // An axis 30 deg off (gate 20 deg) does not match.
  cat.axis_c = Rot(Eigen::Vector3d::UnitX(), 30 * kDeg) * cat.axis_o;
  EXPECT_EQ(
      FindSymbaMatch(objects, Rigid3d(), cat, "table", {}, nullptr, {}, options)
          .object,
      -1);
}

TEST(FindAngle, MatchesTheNearestAngleWithinTheGate) {
  ObjectState object;
  object.type = SymmetryType::kDiscrete;
  object.a_o = Eigen::Vector3d::UnitZ();
  object.anchor = SymmetryAnchor::FromObjectRotation(
      Eigen::Quaterniond::Identity(), object.a_o);
  Eigen::Map<Eigen::Vector3d>(object.a_w) = object.anchor.a_w0;
  object.thetas.push_back(std::make_unique<double>(0.0));
  object.thetas.push_back(std::make_unique<double>(kPi));
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  EXPECT_EQ(FindAngle(object, Rot(z, 10 * kDeg), 20 * kDeg), 0);
  EXPECT_EQ(FindAngle(object, Rot(z, 170 * kDeg), 20 * kDeg), 1);
  EXPECT_EQ(FindAngle(object, Rot(z, 90 * kDeg), 20 * kDeg), -1);
  EXPECT_NEAR(NewAngleTheta(object, Rot(z, 90 * kDeg)), 90 * kDeg, 1e-12);
}

// ---------------------------------------------------------------------------
// The persistent problem.

// r = x - target, one block of size 1.
struct Offset {
  explicit Offset(double target) : target(target) {}
  template <typename T>
  bool operator()(const T* x, T* r) const {
    r[0] = x[0] - T(target);
    return true;
  }
  double target;
};

FactorRecord OffsetFactor(double* block, double target) {
  FactorRecord record;
  record.cost.reset(
      new ceres::AutoDiffCostFunction<Offset, 1, 1>(new Offset(target)));
  record.blocks = {block};
  record.keyframe = 0;
  return record;
}

TEST(WindowProblem, HoldsExactlyTheActiveFactorsAndTheirBlocks) {
  double a = 0.0;
  double b = 0.0;
  WindowProblem problem;
  const int fa = problem.Add(OffsetFactor(&a, 1.0));
  const int fb = problem.Add(OffsetFactor(&b, 2.0));
  EXPECT_EQ(problem.size(), 2);
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 0);  // nothing until a sync

  const WindowProblem::SyncOptions plain;
  problem.Sync({fa}, plain);
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 1);
  EXPECT_TRUE(problem.HasBlock(&a));
  EXPECT_FALSE(problem.HasBlock(&b));

  problem.Sync({fb}, plain);  // a leaves with its block, b enters
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 1);
  EXPECT_FALSE(problem.HasBlock(&a));
  EXPECT_TRUE(problem.HasBlock(&b));

  problem.Sync({fa, fb, fb}, plain);  // a re-enters; duplicates once
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 2);
  ceres::Solver::Options options;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  problem.SetConstant(&b, true);
  problem.Solve(options, &summary);
  EXPECT_NEAR(a, 1.0, 1e-6);  // to the solver's tolerances
  EXPECT_EQ(b, 0.0);          // constant

  problem.Retire(fa);  // out for good, its cost function freed
  EXPECT_TRUE(problem.factor(fa).retired);
  EXPECT_EQ(problem.factor(fa).cost, nullptr);
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 1);
  problem.Sync({fa, fb}, plain);  // a retired factor never re-enters
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 1);
  EXPECT_NE(problem.factor(fb).residual, nullptr);

  problem.MarkMarginalized(fb);  // out of the window solves, not the batch
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 0);
  problem.Sync({fb}, plain);
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 0);
  EXPECT_FALSE(problem.HasBlock(&b));
  WindowProblem::SyncOptions batch;
  batch.with_marginalized = true;
  problem.Sync({fb}, batch);
  EXPECT_EQ(problem.ProblemSize().residual_blocks, 1);
  EXPECT_EQ(problem.in_problem(), std::vector<int>{fb});
}

// A step stated as (s_t, s_r) is tested by pairs whose change |d|^2, with
// the detections' variance c, makes g_i = sqrt(max(0, |d|^2 / 1.5382^2 -
// T^2 c) / s^2); a group's factor is the median g once it exceeds the
// tolerance (1.2 here), then while it exceeds 1, else 1; and only while
// another group's median g is at most 1 (it vouches for the detections).
TEST(MotionClaims, AGroupsFactorIsTheMedianOnceBeyondTheTolerance) {
  const double chi2 = kChi3Median * kChi3Median;
  const double s2 = 0.01;  // stated variance at the object, m^2
  // Pairs at g for the step stated as (s_t, s_r), the detections'
  // variance c with T^2 c = 2 s^2 (steps stated tighter than the
  // detections: s^2 / (T^2 c) = 0.5, a group that can vouch).
  const double c = 2.0 * s2 / 2.25;
  const auto add =
      [&](MotionClaims* claims, double s_t, double s_r, double g, int n) {
        for (int i = 0; i < n; ++i) {
          claims->Add(s_t, s_r, chi2 * (g * g + 2.0) * s2, c, s2);
        }
      };
  MotionClaims claims(/*window=*/10, /*min_samples=*/3, 1.2, 1.5);
  // Unknown groups and groups below min_samples: 1.
  EXPECT_EQ(claims.Factor(0.02, 0.04), 1.0);
  add(&claims, 0.02, 0.04, 1.0, 1);
  add(&claims, 0.02, 0.04, 3.0, 1);
  EXPECT_EQ(claims.Factor(0.02, 0.04), 1.0);
  add(&claims, 0.02, 0.04, 2.0, 1);  // median 2, but no other group
  EXPECT_EQ(claims.Factor(0.02, 0.04), 1.0);
  add(&claims, 0.01, 0.005, 0.5, 3);  // a group that vouches
  EXPECT_NEAR(claims.Factor(0.02, 0.04), 2.0, 1e-12);
  EXPECT_EQ(claims.Factor(0.01, 0.005), 1.0);
  // Sigmas in one quarter octave (rounded) are one group.
  EXPECT_NEAR(claims.Factor(0.0201, 0.0401), 2.0, 1e-12);
  // A third group beyond the tolerance: the second still vouches.
  add(&claims, 0.05, 0.1, 10.0, 3);
  EXPECT_NEAR(claims.Factor(0.05, 0.1), 10.0, 1e-12);
  EXPECT_NEAR(claims.Factor(0.02, 0.04), 2.0, 1e-12);
  // The vouching group's pairs turn (g = 1.5 > 1): nobody vouches now.
  add(&claims, 0.01, 0.005, 1.5, 10);
  EXPECT_EQ(claims.Factor(0.02, 0.04), 1.0);
  // Steps stated loosely (s^2 / (T^2 c) = 4 > 1) explain any detector:
  // their g of 0 vouches for nothing.
  MotionClaims loose(10, 3, 1.2, 1.5);
  add(&loose, 0.02, 0.04, 2.0, 3);
  for (int i = 0; i < 3; ++i) loose.Add(0.5, 0.5, 0.0, s2 / 9.0, s2);
  EXPECT_EQ(loose.Factor(0.02, 0.04), 1.0);
  // A vouching group again: the factor must pass the tolerance afresh
  // (1.1 does not; 2 does).
  MotionClaims again(3, 3, 1.2, 1.5);
  add(&again, 0.02, 0.04, 2.0, 3);
  add(&again, 0.01, 0.005, 0.5, 3);
  EXPECT_NEAR(again.Factor(0.02, 0.04), 2.0, 1e-12);
  add(&again, 0.01, 0.005, 1.5, 3);
  EXPECT_EQ(again.Factor(0.02, 0.04), 1.0);
  add(&again, 0.01, 0.005, 0.5, 3);
  add(&again, 0.02, 0.04, 1.1, 3);
  EXPECT_EQ(again.Factor(0.02, 0.04), 1.0);

  // The detections' variance, times T^2 = 2.25, is taken off first:
  // |d|^2 / chi2 = 0.03, c = 0.004: g = sqrt((0.03 - 0.009) / 0.01).
  MotionClaims noisy(10, 1, 1.2, 1.5);
  add(&noisy, 0.01, 0.005, 0.0, 1);
  noisy.Add(0.02, 0.04, chi2 * 0.03, 0.004, s2);
  EXPECT_NEAR(noisy.Factor(0.02, 0.04), std::sqrt(2.1), 1e-12);

  // Once applied, a factor stays while the median exceeds 1 (1.1 < 1.2)
  // and falls to 1 below it; a group never applied stays at 1 below the
  // tolerance.
  MotionClaims hysteresis(3, 3, 1.2, 1.5);
  add(&hysteresis, 0.01, 0.005, 0.5, 3);
  add(&hysteresis, 0.02, 0.04, 2.0, 3);
  EXPECT_NEAR(hysteresis.Factor(0.02, 0.04), 2.0, 1e-12);
  add(&hysteresis, 0.02, 0.04, 1.1, 3);
  EXPECT_NEAR(hysteresis.Factor(0.02, 0.04), 1.1, 1e-12);
  add(&hysteresis, 0.02, 0.04, 0.9, 3);
  EXPECT_EQ(hysteresis.Factor(0.02, 0.04), 1.0);
  add(&hysteresis, 0.05, 0.1, 1.1, 3);
  EXPECT_EQ(hysteresis.Factor(0.05, 0.1), 1.0);

  const std::vector<MotionNoiseReport::Group> report = claims.Report();
  ASSERT_EQ(report.size(), 3u);
  EXPECT_EQ(report[0].stated_sigma_t, 0.01);  // in the order of the sigmas
  EXPECT_EQ(report[0].pairs, 10);
  EXPECT_NEAR(*report[0].scale, 1.5, 1e-12);
  EXPECT_EQ(report[1].stated_sigma_r, 0.04);
  EXPECT_EQ(report[1].factor, 1.0);
  EXPECT_NEAR(report[2].factor, 10.0, 1e-12);  // as last applied
}

// The pairs test the step with the detections' known noise (variance_t):
// |d|^2, variance_t of both and the stated s_t^2 + d^2 s_r^2 of the step;
// a detection whose noise is not known tests nothing.
TEST(ClaimPairs, PairsWithKnownNoiseTestTheFrontEndsStep) {
  const double chi2 = kChi3Median * kChi3Median;
  DetectionNoiseEstimator noise(100, 1);
  MotionClaims motion(100, 1, 1.2, 1.0);
  ClaimPairs pairs(0.5, 0.5);
  ClaimedDetection a;  // weighed by its scatter: no claim, a known noise
  a.class_name = "table";
  a.p_w = Eigen::Vector3d(2.0, 0.0, 0.0);
  a.distance = 2.0;
  a.variance_t = 1e-4;
  pairs.Add(0, a, std::nullopt, &noise, &motion);
  ClaimedDetection b = a;
  b.p_w = Eigen::Vector3d(2.3, 0.0, 0.0);
  StepVariance step{4.0 * 0.01 * 0.01, 4.0 * 0.02 * 0.02, 0.01, 0.02};
  pairs.Add(1, b, step, &noise, &motion);
  EXPECT_EQ(noise.ClaimsReport("table").translation_samples, 0);
  const double stated = 0.01 * 0.01 + 4.0 * 0.02 * 0.02;
  ASSERT_EQ(motion.Report().size(), 1u);
  EXPECT_NEAR(*motion.Report().front().scale,
              std::sqrt((0.09 / chi2 - 2e-4) / stated),
              1e-12);
  ClaimedDetection unknown = b;
  unknown.variance_t = 0.0;
  unknown.p_w = Eigen::Vector3d(2.0, 0.0, 0.0);
  pairs.Add(2, unknown, step, &noise, &motion);
  EXPECT_EQ(motion.Report().front().pairs, 1);
}

// In a class with declared and undeclared detections each test pairs
// with its own kind: the claim with the nearest declared detection, the
// step with the nearest whose noise is known; a previous detection whose
// noise is not known tests nothing.
TEST(ClaimPairs, EachTestPairsWithItsOwnKind) {
  const double chi2 = kChi3Median * kChi3Median;
  DetectionNoiseEstimator noise(100, 1);
  MotionClaims motion(100, 1, 1.2, 1.0);
  ClaimPairs pairs(0.5, 0.5);
  ClaimedDetection scatter;  // 0.1 m from the later one, noise known
  scatter.class_name = "box";
  scatter.p_w = Eigen::Vector3d(1.1, 0.0, 0.0);
  scatter.distance = 1.0;
  scatter.variance_t = 1e-4;
  ClaimedDetection declared = scatter;  // 0.2 m from it, declared
  declared.p_w = Eigen::Vector3d(1.2, 0.0, 0.0);
  declared.sigma_t = 0.01;
  declared.sigma_r = 0.02;
  ClaimedDetection unknown = scatter;  // nearest of all, noise unknown
  unknown.p_w = Eigen::Vector3d(1.01, 0.0, 0.0);
  unknown.variance_t = 0.0;
  pairs.Add(0, scatter, std::nullopt, &noise, &motion);
  pairs.Add(0, declared, std::nullopt, &noise, &motion);
  pairs.Add(0, unknown, std::nullopt, &noise, &motion);
  ClaimedDetection later = declared;
  later.p_w = Eigen::Vector3d(1.0, 0.0, 0.0);
  const StepVariance step{1e-4, 1e-4, 0.01, 0.01};
  pairs.Add(1, later, step, &noise, &motion);
  const ClassNoiseEstimate::Claims claims = noise.ClaimsReport("box");
  ASSERT_EQ(claims.translation_samples, 1);
  // |d| = 0.2 m to the declared one: f^2 c + s = 0.04 / chi2.
  EXPECT_NEAR(*claims.scale_t,
              std::sqrt((0.04 / chi2 - 2e-4) / (2.0 * 0.01 * 0.01)),
              1e-9);
  ASSERT_EQ(motion.Report().size(), 1u);
  // |d| = 0.1 m to the scatter one: g^2 s^2 = 0.01 / chi2 - c.
  EXPECT_NEAR(*motion.Report().front().scale,
              std::sqrt((0.01 / chi2 - 2e-4) / 2e-4),
              1e-9);
}

}  // namespace
}  // namespace symba::internal
