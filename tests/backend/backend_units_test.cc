// Unit tests of the backend's internal units (src/backend/*.h): the noise
// estimator, the upgrade evidence, the association gates on hand-built
// object sets and the persistent window problem. Every expected value is
// derived in the comment next to it.
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "backend/association.h"
#include "backend/detection_noise.h"
#include "backend/upgrade_evidence.h"
#include "backend/window_problem.h"
#include "symba/geometry/angle.h"

namespace symba::internal {
namespace {

constexpr double kDeg = kPi / 180.0;

Eigen::Quaterniond Rot(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// ---------------------------------------------------------------------------
// Detection noise.

TEST(LagBinIndex, BinsLagsByPowersOfTwo) {
  EXPECT_EQ(LagBinIndex(0), -1);
  EXPECT_EQ(LagBinIndex(1), 0);
  EXPECT_EQ(LagBinIndex(2), 1);
  EXPECT_EQ(LagBinIndex(3), 1);
  EXPECT_EQ(LagBinIndex(4), 2);
  EXPECT_EQ(LagBinIndex(255), 7);
  EXPECT_EQ(LagBinIndex(256), 8);
  EXPECT_EQ(LagBinIndex(511), 8);
  EXPECT_EQ(LagBinIndex(512), -1);
}

TEST(LagBin, IsTheMedianOverTheChiSquareMedianAndKeepsTheLastWindow) {
  LagBin bin(3);
  for (double v : {1.0, 1.0, 1.0, 5.0, 9.0, 6.0}) bin.Add({2, v});
  const LagBinSummary summary = bin.Summary();
  EXPECT_EQ(summary.count, 3);
  // The last three: 5, 9, 6; median 6; the 9 does not move it.
  EXPECT_DOUBLE_EQ(summary.variance, 6.0 / kChiSquare3Median);
  EXPECT_DOUBLE_EQ(summary.lag, 2.0);
}

// The level and lag bins of the exact model: level w + b, lag L
// 2 w + 2 b (1 - rho^L).
std::vector<LagBinSummary> ExactBins(double w, double b, double rho) {
  std::vector<LagBinSummary> bins = {{0.0, w + b, kMinBinSamples}};
  for (int i = 0; i < kLagBins; ++i) {
    const double lag = 1 << i;
    bins.push_back(
        {lag, 2 * w + 2 * b * (1 - std::pow(rho, lag)), kMinBinSamples});
  }
  return bins;
}

TEST(FitVariogram, TellsWhiteNoiseFromPersistence) {
  // White noise only.
  std::optional<VariogramFit> fit = FitVariogram(ExactBins(1e-4, 0, 0));
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->white, 1e-4, 1e-10);
  EXPECT_NEAR(fit->persistent, 0.0, 1e-10);
  EXPECT_NEAR(fit->EffectiveVariance(), 1e-4, 1e-10);
  // A persistent error of 5 cm (rho 0.95, on the grid) over 5 mm of white
  // noise.
  fit = FitVariogram(ExactBins(2.5e-5, 2.5e-3, 0.95));
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->white, 2.5e-5, 1e-9);
  EXPECT_NEAR(fit->persistent, 2.5e-3, 1e-8);
  EXPECT_DOUBLE_EQ(fit->rho, 0.95);
  // Each detection informs like (1 - rho) / (1 + rho) independent ones.
  EXPECT_NEAR(fit->EffectiveVariance(), 2.5e-5 + 2.5e-3 * 39.0, 1e-7);
  EXPECT_NEAR(fit->Inflation(), std::sqrt(39.0), 1e-12);
  EXPECT_NEAR(fit->ScatterVariance(), 2.525e-3, 1e-8);
}

TEST(FitVariogram, NeedsTheLevelAndALagBinWithEnoughSamples) {
  std::vector<LagBinSummary> bins = ExactBins(1e-4, 0, 0);
  for (LagBinSummary& bin : bins) bin.count = kMinBinSamples - 1;
  EXPECT_FALSE(FitVariogram(bins));
  bins[1].count = kMinBinSamples;  // lag 1 without the level
  bins[2].count = kMinBinSamples;
  EXPECT_FALSE(FitVariogram(bins));
  bins[0].count = kMinBinSamples;  // the level
  EXPECT_TRUE(FitVariogram(bins));
}

// Samples of a detector's error e_k = white + AR(1) along a track of
// `count` keyframes: the level |e_k|^2 and every lag 2^i back.
void AddTrack(DetectionNoiseEstimator* noise,
              const std::string& class_name,
              double white,
              double persistent,
              double rho,
              int count,
              unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto gaussian = [&](double sigma) {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v[i] = sigma * normal(random);
    return v;
  };
  const double innovation = persistent * std::sqrt(1 - rho * rho);
  Eigen::Vector3d ar = gaussian(persistent);
  std::vector<Eigen::Vector3d> errors;
  for (int k = 0; k < count; ++k) {
    ar = rho * ar + gaussian(innovation);
    errors.push_back(ar + gaussian(white));
    noise->AddTranslation(class_name, {0, errors[k].squaredNorm()});
    for (int bin = 0; bin < kLagBins && (1 << bin) <= k; ++bin) {
      const int lag = 1 << bin;
      noise->AddTranslation(class_name,
                            {lag, (errors[k] - errors[k - lag]).squaredNorm()});
    }
  }
}

TEST(DetectionNoiseEstimator, EstimatesAKnownWhiteNoiseWithin15Percent) {
  DetectionNoiseEstimator noise(500, 20);
  AddTrack(&noise, "chair", 0.03, 0.0, 0.0, 2000, 7);  // 3 cm per axis
  noise.Update("chair");
  const ClassNoise estimate = noise.Estimate("chair");
  ASSERT_TRUE(estimate.sigma_t);
  EXPECT_NEAR(*estimate.sigma_t, 0.03, 0.15 * 0.03);
  EXPECT_NEAR(*estimate.scatter_t, 0.03, 0.15 * 0.03);
  EXPECT_EQ(estimate.samples_t, 2000);
  EXPECT_FALSE(estimate.sigma_r);
  EXPECT_FALSE(noise.Estimate("table").sigma_t);
  EXPECT_EQ(noise.Classes(), std::vector<std::string>{"chair"});
}

TEST(DetectionNoiseEstimator, GetsAKnownAR1ErrorsInflation) {
  // 5 mm white, 5 cm persistent with rho 0.9 per keyframe.
  DetectionNoiseEstimator noise(500, 20);
  AddTrack(&noise, "box", 0.005, 0.05, 0.9, 3000, 11);
  noise.Update("box");
  const ClassNoise estimate = noise.Estimate("box");
  ASSERT_TRUE(estimate.translation);
  EXPECT_NEAR(estimate.translation->rho, 0.9, 0.05);
  // sigma^2 = w + b (1 + rho) / (1 - rho) = 0.005^2 + 0.05^2 19: 0.218 m.
  const double expected = std::sqrt(0.005 * 0.005 + 0.05 * 0.05 * 19.0);
  EXPECT_NEAR(*estimate.sigma_t, expected, 0.2 * expected);
  EXPECT_NEAR(*estimate.scatter_t, 0.05, 0.15 * 0.05);
}

TEST(DetectionNoiseEstimator, WaitsForEnoughLevelsAndNeverGoesBelowTheFloor) {
  DetectionNoiseEstimator noise(500, 20);
  for (int i = 0; i < 19; ++i) {
    noise.AddTranslation("box", {0, 0.0});
    noise.AddTranslation("box", {1, 0.0});
  }
  noise.Update("box");
  EXPECT_FALSE(noise.Estimate("box").sigma_t);
  noise.AddTranslation("box", {0, 0.0});
  noise.Update("box");
  // A detector that agrees with the map to the last bit.
  ASSERT_TRUE(noise.Estimate("box").sigma_t);
  EXPECT_DOUBLE_EQ(*noise.Estimate("box").sigma_t, kMinSigmaT);
  // Lags past the last bin are not kept.
  noise.AddRotation("box", {512, 1.0});
  noise.Update("box");
  EXPECT_FALSE(noise.Estimate("box").sigma_r);
}

// `count` whitened odometry residuals: N(0, scale) per value plus `drift`
// on the first value of every one.
OdometryNoiseEstimator OdometryOf(double scale, double drift, int count) {
  OdometryNoiseEstimator odometry(500, 20);
  std::mt19937 random(5);
  std::normal_distribution<double> normal(0.0, std::sqrt(scale));
  for (int i = 0; i < count; ++i) {
    Eigen::Matrix<double, 6, 1> r;
    for (int j = 0; j < 6; ++j) r[j] = normal(random);
    r[0] += drift;
    odometry.Add(r, true);
  }
  odometry.Update();
  return odometry;
}

TEST(OdometryNoiseEstimator, FindsTheFactorOnTheStatedVariance) {
  // As stated: s near 1 at every run length (the largest of seven
  // estimates, each within a few percent).
  OdometryNoiseEstimator odometry = OdometryOf(1.0, 0.0, 500);
  ASSERT_TRUE(odometry.Scale());
  EXPECT_NEAR(*odometry.Scale(), 1.0, 0.3);
  EXPECT_EQ(odometry.samples(), 500);
  // Four times the stated variance.
  odometry = OdometryOf(4.0, 0.0, 500);
  EXPECT_NEAR(*odometry.Scale(), 4.0, 1.2);
  // A front end far better than it says: the factor's floor.
  odometry = OdometryOf(1e-6, 0.0, 500);
  EXPECT_DOUBLE_EQ(*odometry.Scale(), kMinOdometryScale);
  // A drift of half a sigma per step: small per step, but 64 steps add up
  // to 32 sigma: s about (32^2 + 64 5.35) / (64 5.35) = 4.
  odometry = OdometryOf(1.0, 0.5, 500);
  EXPECT_GT(*odometry.Scale(), 3.0);
  // Too few residuals for any run length.
  EXPECT_FALSE(OdometryOf(1.0, 0.0, 19).Scale());
}

TEST(OdometryNoiseEstimator, RunsDoNotCrossARestart) {
  OdometryNoiseEstimator odometry(500, 20);
  Eigen::Matrix<double, 6, 1> drift = Eigen::Matrix<double, 6, 1>::Zero();
  drift[0] = 1.0;
  // 40 runs of two steps: sums of one and two steps only (each 2 sigma
  // at most); no longer run exists.
  for (int i = 0; i < 80; ++i) odometry.Add(drift, i % 2 == 1);
  odometry.Update();
  ASSERT_TRUE(odometry.Scale());
  // Single steps |r|^2 = 1, pairs 4 / 2 = 2: s = 2 / median chi-square(6).
  EXPECT_NEAR(*odometry.Scale(), 2.0 / kChiSquare6Median, 1e-12);
}

TEST(EffectiveSigma, ClaimsAreAPriorThatContradictingDataOverrule) {
  // A claim stands while the estimate is within the ratio of it.
  EXPECT_DOUBLE_EQ(EffectiveSigma(0.03, true, 0.05, 3.0), 0.03);
  EXPECT_DOUBLE_EQ(EffectiveSigma(0.03, true, std::nullopt, 3.0), 0.03);
  // A detector that claims 1 cm and is off by 10 cm.
  EXPECT_DOUBLE_EQ(EffectiveSigma(0.01, true, 0.1, 3.0), 0.1);
  // Without a claim: the estimate, and the initial noise before one.
  EXPECT_DOUBLE_EQ(EffectiveSigma(2.0, false, 0.05, 3.0), 0.05);
  EXPECT_DOUBLE_EQ(EffectiveSigma(2.0, false, std::nullopt, 3.0), 2.0);
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
  EXPECT_EQ(problem.NumResidualBlocks(), 0);  // nothing until a sync

  const WindowProblem::SyncOptions plain;
  problem.Sync({fa}, plain);
  EXPECT_EQ(problem.NumResidualBlocks(), 1);
  EXPECT_TRUE(problem.HasBlock(&a));
  EXPECT_FALSE(problem.HasBlock(&b));

  problem.Sync({fb}, plain);  // a leaves with its block, b enters
  EXPECT_EQ(problem.NumResidualBlocks(), 1);
  EXPECT_FALSE(problem.HasBlock(&a));
  EXPECT_TRUE(problem.HasBlock(&b));

  problem.Sync({fa, fb, fb}, plain);  // a re-enters; duplicates once
  EXPECT_EQ(problem.NumResidualBlocks(), 2);
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
  EXPECT_EQ(problem.NumResidualBlocks(), 1);
  problem.Sync({fa, fb}, plain);  // a retired factor never re-enters
  EXPECT_EQ(problem.NumResidualBlocks(), 1);
  EXPECT_NE(problem.factor(fb).residual, nullptr);

  problem.MarkMarginalized(fb);  // out of the window solves, not the batch
  EXPECT_EQ(problem.NumResidualBlocks(), 0);
  problem.Sync({fb}, plain);
  EXPECT_EQ(problem.NumResidualBlocks(), 0);
  EXPECT_FALSE(problem.HasBlock(&b));
  WindowProblem::SyncOptions batch;
  batch.with_marginalized = true;
  problem.Sync({fb}, batch);
  EXPECT_EQ(problem.NumResidualBlocks(), 1);
  EXPECT_EQ(problem.in_problem(), std::vector<int>{fb});
}

}  // namespace
}  // namespace symba::internal
