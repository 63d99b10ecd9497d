#include "symba/categorization/categorize.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "test_support/hypothesis_generator.h"
#include "test_support/random.h"

namespace symba {
namespace {

using testing::GeneratedDetection;
using testing::HypothesisSetSpec;
using testing::kDegree;
using testing::TestRandom;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Angle between two axes up to sign, degrees.
double AxisErrorDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return std::acos(c) / kDegree;
}

double RotationErrorDeg(const Eigen::Quaterniond& a,
                        const Eigen::Quaterniond& b) {
  return LogSO3(Eigen::Quaterniond(a.conjugate() * b)).norm() / kDegree;
}

Eigen::Quaterniond Rot(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

PoseHypothesis Hyp(const Eigen::Quaterniond& q,
                   const Eigen::Vector3d& t = Eigen::Vector3d(0, 0, 2),
                   double weight = 1.0) {
  PoseHypothesis h;
  h.T_co = Rigid3d(q, t);
  h.weight = weight;
  return h;
}

// Every number in the result is finite and the structure is consistent.
void ExpectWellFormed(const std::vector<PoseHypothesis>& hypotheses,
                      const CategorizedDetection& out) {
  const int n = static_cast<int>(hypotheses.size());
  EXPECT_TRUE(out.T_co_base.q.coeffs().allFinite());
  EXPECT_NEAR(out.T_co_base.q.norm(), 1.0, 1e-9);
  EXPECT_TRUE(out.t_co.allFinite());
  EXPECT_TRUE(out.axis_o.allFinite());
  EXPECT_TRUE(out.axis_c.allFinite());
  EXPECT_EQ(out.T_co_base.t, out.t_co);
  EXPECT_GE(out.reference, 0);
  EXPECT_LT(out.reference, n);
  EXPECT_FALSE(out.inliers.empty());
  EXPECT_TRUE(std::is_sorted(out.inliers.begin(), out.inliers.end()));
  EXPECT_EQ(static_cast<int>(out.twist.size()), n);
  for (double t : out.twist) EXPECT_TRUE(std::isfinite(t));
  if (out.type == SymmetryType::kAsymmetric) {
    EXPECT_EQ(out.axis_o, Eigen::Vector3d::Zero());
    EXPECT_TRUE(out.clusters.empty());
    return;
  }
  EXPECT_NEAR(out.axis_o.norm(), 1.0, 1e-9);
  EXPECT_NEAR(out.axis_c.norm(), 1.0, 1e-9);
  // axis_c = R_base axis_o exactly.
  EXPECT_LT((out.T_co_base.q * out.axis_o - out.axis_c).norm(), 1e-9);
  if (out.type == SymmetryType::kContinuous) {
    EXPECT_TRUE(out.clusters.empty());
    return;
  }
  // One mode read with a discrete prior's type is one cluster.
  ASSERT_GE(out.clusters.size(), out.diagnostics.prior_type_used ? 1u : 2u);
  EXPECT_EQ(out.clusters[0].theta, 0.0);
  std::vector<int> members;
  for (const AngleCluster& c : out.clusters) {
    EXPECT_TRUE(std::isfinite(c.theta));
    EXPECT_GT(c.theta, -kPi);
    EXPECT_LE(c.theta, kPi);
    EXPECT_TRUE(std::isfinite(c.spread));
    EXPECT_GT(c.weight, 0.0);
    EXPECT_TRUE(std::is_sorted(c.members.begin(), c.members.end()));
    members.insert(members.end(), c.members.begin(), c.members.end());
  }
  std::sort(members.begin(), members.end());
  EXPECT_EQ(members, out.inliers);
  EXPECT_NE(std::find(out.clusters[0].members.begin(),
                      out.clusters[0].members.end(),
                      out.reference),
            out.clusters[0].members.end());
}

// ---------------------------------------------------------------------------
// Errors reported to the caller.

TEST(CategorizeTest, RejectsEmptyDetection) {
  CategorizedDetection out;
  const Status status = Categorize({}, CategorizationOptions(), nullptr, &out);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("no hypotheses"), std::string::npos);
}

TEST(CategorizeTest, RejectsNonFiniteInputNamingTheHypothesis) {
  std::vector<PoseHypothesis> hypotheses(5, Hyp(Rot({0, 0, 1}, 0.3)));
  CategorizedDetection out;
  struct Case {
    std::vector<PoseHypothesis> input;
    std::string expected;
  };
  std::vector<Case> cases;
  {
    auto h = hypotheses;
    h[3].T_co.q.x() = kNaN;
    cases.push_back({h, "hypothesis 3: rotation is not finite"});
  }
  {
    auto h = hypotheses;
    h[1].T_co.t.z() = kInf;
    cases.push_back({h, "hypothesis 1: translation is not finite"});
  }
  {
    auto h = hypotheses;
    h[4].T_co.q.coeffs() *= 2.0;
    cases.push_back({h, "hypothesis 4: quaternion norm"});
  }
  {
    auto h = hypotheses;
    h[2].T_co.q.coeffs().setZero();
    cases.push_back({h, "hypothesis 2: quaternion norm"});
  }
  {
    auto h = hypotheses;
    h[0].weight = 0.0;
    cases.push_back({h, "hypothesis 0: weight"});
  }
  {
    auto h = hypotheses;
    h[2].weight = -1.0;
    cases.push_back({h, "hypothesis 2: weight"});
  }
  {
    auto h = hypotheses;
    h[3].weight = kNaN;
    cases.push_back({h, "hypothesis 3: weight"});
  }
  {
    auto h = hypotheses;
    h[3].weight = kInf;
    cases.push_back({h, "hypothesis 3: weight"});
  }
  for (const Case& c : cases) {
    const Status status =
        Categorize(c.input, CategorizationOptions(), nullptr, &out);
    ASSERT_FALSE(status.ok()) << c.expected;
    EXPECT_NE(status.message().find(c.expected), std::string::npos)
        << status.message();
    EXPECT_TRUE(out.inliers.empty());
  }
}

TEST(CategorizeTest, RejectsInvalidOptionsAndPriors) {
  const std::vector<PoseHypothesis> hypotheses(3, Hyp(Rot({0, 0, 1}, 0.3)));
  CategorizedDetection out;
  CategorizationOptions options;
  options.cluster_eps = 0.0;
  Status status = Categorize(hypotheses, options, nullptr, &out);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("cluster_eps"), std::string::npos);
  options = CategorizationOptions();
  options.min_points = 0;
  EXPECT_FALSE(Categorize(hypotheses, options, nullptr, &out).ok());
  options = CategorizationOptions();
  options.max_noise_fraction = kNaN;
  EXPECT_FALSE(Categorize(hypotheses, options, nullptr, &out).ok());
  options = CategorizationOptions();
  options.translation_gate = -1.0;
  EXPECT_FALSE(Categorize(hypotheses, options, nullptr, &out).ok());
  options = CategorizationOptions();
  options.swing_tolerance = kPi;
  EXPECT_FALSE(Categorize(hypotheses, options, nullptr, &out).ok());
  options = CategorizationOptions();
  options.min_empty_fraction = 1.5;
  EXPECT_FALSE(Categorize(hypotheses, options, nullptr, &out).ok());
  EXPECT_TRUE(CategorizationOptions().Validate().ok());

  ClassPrior prior;
  prior.axis_o = Eigen::Vector3d(kNaN, 0, 1);
  EXPECT_FALSE(
      Categorize(hypotheses, CategorizationOptions(), &prior, &out).ok());
  prior = ClassPrior();
  prior.order = 1;
  EXPECT_FALSE(
      Categorize(hypotheses, CategorizationOptions(), &prior, &out).ok());
}

// ---------------------------------------------------------------------------
// Degenerate input: defined answers.

TEST(CategorizeTest, SingleHypothesisIsAsymmetric) {
  const std::vector<PoseHypothesis> hypotheses = {
      Hyp(Rot({1, 2, 3}, 2.0), Eigen::Vector3d(0.5, -0.2, 3.0))};
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
  EXPECT_EQ(out.reference, 0);
  EXPECT_EQ(out.inliers, std::vector<int>{0});
  EXPECT_LT(RotationErrorDeg(out.T_co_base.q, hypotheses[0].T_co.q), 1e-6);
  EXPECT_LT((out.t_co - hypotheses[0].T_co.t).norm(), 1e-12);
  ExpectWellFormed(hypotheses, out);
}

TEST(CategorizeTest, TwoHypothesesAreAsymmetric) {
  CategorizedDetection out;
  // Close together: both are inliers.
  std::vector<PoseHypothesis> hypotheses = {Hyp(Rot({0, 1, 0}, 0.5)),
                                            Hyp(Rot({0, 1, 0}, 0.55))};
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
  EXPECT_EQ(out.inliers, (std::vector<int>{0, 1}));
  ExpectWellFormed(hypotheses, out);
  // A half-turn apart: too little evidence for a symmetry; the reference
  // (the heavier one) is kept.
  hypotheses = {Hyp(Rot({0, 1, 0}, 0.5)),
                Hyp(Rot({0, 1, 0}, 0.5 + kPi), Eigen::Vector3d(0, 0, 2), 2.0)};
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
  EXPECT_EQ(out.reference, 1);
  EXPECT_EQ(out.inliers, std::vector<int>{1});
  ExpectWellFormed(hypotheses, out);
}

TEST(CategorizeTest, IdenticalHypothesesAreAsymmetric) {
  const std::vector<PoseHypothesis> hypotheses(
      30, Hyp(Rot({-1, 0.5, 2}, 1.2), Eigen::Vector3d(1, 2, 3)));
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
  EXPECT_EQ(out.reference, 0);
  EXPECT_EQ(out.inliers.size(), 30u);
  EXPECT_LT(RotationErrorDeg(out.T_co_base.q, hypotheses[0].T_co.q), 1e-6);
  EXPECT_LT((out.t_co - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
  ExpectWellFormed(hypotheses, out);
}

// Noise-free half-turn symmetry about each coordinate axis (the poles of any
// spherical parametrisation) and about oblique axes; the twist is exactly pi.
TEST(CategorizeTest, ExactHalfTurnAtPolesIsDiscreteWithAngleZeroAndPi) {
  const Eigen::Quaterniond q_co = Rot({0.3, -0.4, 0.5}, 0.7);
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0, 0, 1),
                                      Eigen::Vector3d(0, 0, -1),
                                      Eigen::Vector3d(1, 0, 0),
                                      Eigen::Vector3d(0, 1, 0),
                                      Eigen::Vector3d(1, 1, 1).normalized()}) {
    std::vector<PoseHypothesis> hypotheses;
    for (int j = 0; j < 10; ++j) {
      hypotheses.push_back(Hyp(j % 2 == 0 ? q_co : q_co * Rot(axis, kPi)));
    }
    CategorizedDetection out;
    ASSERT_TRUE(
        Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
    ASSERT_EQ(out.type, SymmetryType::kDiscrete) << axis.transpose();
    ExpectWellFormed(hypotheses, out);
    EXPECT_LT(AxisErrorDeg(out.axis_o, axis), 1e-6);
    EXPECT_LT(AxisErrorDeg(out.axis_c, q_co * axis), 1e-6);
    ASSERT_EQ(out.clusters.size(), 2u);
    EXPECT_NEAR(std::abs(out.clusters[1].theta), kPi, 1e-9);
    EXPECT_EQ(out.clusters[0].members, (std::vector<int>{0, 2, 4, 6, 8}));
    EXPECT_EQ(out.clusters[1].members, (std::vector<int>{1, 3, 5, 7, 9}));
    EXPECT_LT(RotationErrorDeg(out.T_co_base.q, q_co), 1e-6);
  }
}

TEST(CategorizeTest, ExactContinuousAboutPoleAxis) {
  const Eigen::Quaterniond q_co = Rot({1, 0, 0}, kPi);  // itself a half-turn
  std::vector<PoseHypothesis> hypotheses;
  for (int j = 0; j < 30; ++j) {
    hypotheses.push_back(Hyp(q_co * Rot({0, 0, 1}, -kPi + j * kTwoPi / 30)));
  }
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kContinuous);
  ExpectWellFormed(hypotheses, out);
  EXPECT_LT(AxisErrorDeg(out.axis_o, {0, 0, 1}), 1e-6);
  EXPECT_LT(AxisErrorDeg(out.axis_c, q_co * Eigen::Vector3d(0, 0, 1)), 1e-6);
  EXPECT_EQ(out.inliers.size(), 30u);
}

// Signed angles: a square table seen with modes 0 and +90 degrees differs
// from one seen with 0 and -90 (the unsigned |log| would fold them).
TEST(CategorizeTest, SignedAnglesSeparatePlusAndMinusNinety) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, -1, 0.4).normalized();
  const Eigen::Quaterniond q_co = Rot({1, 1, 0}, 0.4);
  for (double sign : {1.0, -1.0}) {
    std::vector<PoseHypothesis> hypotheses;
    for (int j = 0; j < 12; ++j) {
      hypotheses.push_back(
          Hyp(j < 6 ? q_co : q_co * Rot(axis, sign * kPi / 2)));
    }
    CategorizedDetection out;
    ASSERT_TRUE(
        Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
    ASSERT_EQ(out.type, SymmetryType::kDiscrete);
    ASSERT_EQ(out.clusters.size(), 2u);
    const double axis_sign = out.axis_o.dot(axis) > 0 ? 1.0 : -1.0;
    EXPECT_NEAR(axis_sign * out.clusters[1].theta, sign * kPi / 2, 1e-9);
    // The convention: R_j = R_base Rot(axis_o, theta) for the members.
    for (const AngleCluster& c : out.clusters) {
      for (int j : c.members) {
        EXPECT_LT(RotationErrorDeg(out.T_co_base.q * Rot(out.axis_o, c.theta),
                                   hypotheses[j].T_co.q),
                  1e-6);
      }
    }
  }
}

// Hypotheses R_co * Rot(axis, angle_k) for the given angles (degrees).
std::vector<PoseHypothesis> AtAngles(const Eigen::Quaterniond& q_co,
                                     const Eigen::Vector3d& axis,
                                     const std::vector<double>& degrees) {
  std::vector<PoseHypothesis> hypotheses;
  for (double d : degrees)
    hypotheses.push_back(Hyp(q_co * Rot(axis, d * kDegree)));
  return hypotheses;
}

// Twists too sparse for any DBSCAN core point, around one axis: continuous.
TEST(CategorizeTest, SparseTwistsWithoutClustersAreContinuous) {
  const Eigen::Vector3d axis(0, 1, 0);
  const auto hypotheses =
      AtAngles(Rot({1, 0, 0}, 0.3),
               axis,
               {0, 35, 62, 101, 140, 171, 205, 238, 281, 317});
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kContinuous);
  EXPECT_EQ(out.diagnostics.num_raw_clusters, 0);
  EXPECT_EQ(out.inliers.size(), 10u);
  EXPECT_LT(AxisErrorDeg(out.axis_o, axis), 1e-6);
  ExpectWellFormed(hypotheses, out);
}

// A mode with a gap above cluster_eps inside it is split by DBSCAN and
// merged back; the mode's angle is the mean of all its members.
TEST(CategorizeTest, SplitModeIsMergedBack) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -1, 2).normalized();
  const auto hypotheses = AtAngles(
      Rot({0, 0, 1}, 2.0), axis, {0, 0, 0, 180, 180, 180, 194, 194, 194});
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  ASSERT_EQ(out.type, SymmetryType::kDiscrete);
  EXPECT_EQ(out.diagnostics.num_raw_clusters, 3);
  ASSERT_EQ(out.clusters.size(), 2u);
  EXPECT_EQ(out.clusters[1].members, (std::vector<int>{3, 4, 5, 6, 7, 8}));
  const double sign = out.axis_o.dot(axis) > 0 ? 1.0 : -1.0;
  EXPECT_NEAR(
      WrapToPi(sign * out.clusters[1].theta - 187 * kDegree), 0.0, 1e-9);
  EXPECT_NEAR(out.clusters[1].spread, 7 * kDegree, 1e-9);
  ExpectWellFormed(hypotheses, out);

  CategorizationOptions no_merge;
  no_merge.merge_close_clusters = false;
  ASSERT_TRUE(Categorize(hypotheses, no_merge, nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kContinuous);  // clusters 14 deg apart
}

// A discrete detection's mode with fewer than min_points members is found
// by the rescue pass.
TEST(CategorizeTest, SmallModeOfDiscreteDetectionIsRescued) {
  const Eigen::Vector3d axis(0, 0, 1);
  std::vector<double> angles(8, 0.0);
  angles.insert(angles.end(), 8, 120.0);
  angles.insert(angles.end(), {-120.0, -118.0});
  const auto hypotheses = AtAngles(Rot({1, 1, 1}, 1.0), axis, angles);
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(hypotheses, CategorizationOptions(), nullptr, &out).ok());
  ASSERT_EQ(out.type, SymmetryType::kDiscrete);
  ASSERT_EQ(out.clusters.size(), 3u);
  EXPECT_EQ(out.clusters[2].members, (std::vector<int>{16, 17}));
  EXPECT_EQ(out.inliers.size(), 18u);
  ExpectWellFormed(hypotheses, out);

  CategorizationOptions no_rescue;
  no_rescue.rescue_min_points = 0;
  ASSERT_TRUE(Categorize(hypotheses, no_rescue, nullptr, &out).ok());
  ASSERT_EQ(out.type, SymmetryType::kDiscrete);
  EXPECT_EQ(out.clusters.size(), 2u);
  EXPECT_EQ(out.inliers.size(), 16u);
}

// ---------------------------------------------------------------------------
// Decisions and tolerances on generated detections (fixed seeds).

struct CellResult {
  int count = 0;
  int correct = 0;
  std::vector<double> axis_error;   // deg, camera frame
  std::vector<double> angle_error;  // deg
  int modes_checked = 0;
  int all_modes_found = 0;
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

CellResult RunCell(const HypothesisSetSpec& spec,
                   int detections,
                   unsigned seed,
                   const ClassPrior* prior = nullptr,
                   bool prior_axis_from_truth = false) {
  TestRandom random(seed);
  CellResult result;
  CategorizedDetection out;
  for (int i = 0; i < detections; ++i) {
    const GeneratedDetection d = GenerateDetection(spec, &random);
    ClassPrior local;
    if (prior != nullptr) {
      local = *prior;
      if (prior_axis_from_truth) local.axis_o = d.axis_o;
    }
    const Status status = Categorize(d.hypotheses,
                                     CategorizationOptions(),
                                     prior != nullptr ? &local : nullptr,
                                     &out);
    EXPECT_TRUE(status.ok()) << status.message();
    ExpectWellFormed(d.hypotheses, out);
    ++result.count;
    if (out.type != d.expected_type) continue;
    ++result.correct;
    if (out.type == SymmetryType::kAsymmetric) {
      // The base pose is the truth within the noise.
      EXPECT_LT(
          RotationErrorDeg(out.T_co_base.q,
                           d.T_co_true.q * Rot(d.axis_o, d.phi[out.reference])),
          5 * spec.rotation_sigma / kDegree);
      continue;
    }
    result.axis_error.push_back(AxisErrorDeg(out.axis_c, d.axis_c));
    if (out.type != SymmetryType::kDiscrete) continue;
    const double sign = out.axis_o.dot(d.axis_o) < 0 ? -1.0 : 1.0;
    std::vector<int> found;
    for (const AngleCluster& c : out.clusters) {
      int mode = -1;
      for (int j : c.members) mode = std::max(mode, d.mode[j]);
      found.push_back(mode);
    }
    for (size_t k = 1; k < out.clusters.size(); ++k) {
      const double truth = kTwoPi * (found[k] - found[0]) / spec.order;
      result.angle_error.push_back(
          std::abs(WrapToPi(sign * out.clusters[k].theta - truth)) / kDegree);
    }
    std::sort(found.begin(), found.end());
    std::vector<int> visible = d.visible_modes;
    std::sort(visible.begin(), visible.end());
    ++result.modes_checked;
    result.all_modes_found += found == visible;
  }
  return result;
}

HypothesisSetSpec Spec(SymmetryType type,
                       int order,
                       std::vector<int> visible,
                       double noise_deg,
                       double outliers) {
  HypothesisSetSpec spec;
  spec.type = type;
  spec.order = order;
  spec.visible_modes = std::move(visible);
  spec.rotation_sigma = noise_deg * kDegree;
  spec.outlier_fraction = outliers;
  return spec;
}

// The target cell: 5 degrees of noise, 10 % outliers, N = 30.
TEST(CategorizeTest, TargetCellDecisionsAndTolerances) {
  struct Case {
    const char* name;
    HypothesisSetSpec spec;
  };
  const std::vector<Case> cases = {
      {"asymmetric", Spec(SymmetryType::kAsymmetric, 1, {}, 5, 0.1)},
      {"continuous", Spec(SymmetryType::kContinuous, 1, {}, 5, 0.1)},
      {"C2", Spec(SymmetryType::kDiscrete, 2, {}, 5, 0.1)},
      {"C3", Spec(SymmetryType::kDiscrete, 3, {}, 5, 0.1)},
      {"C4", Spec(SymmetryType::kDiscrete, 4, {}, 5, 0.1)},
      {"C6", Spec(SymmetryType::kDiscrete, 6, {}, 5, 0.1)},
      {"C4 {0,1}", Spec(SymmetryType::kDiscrete, 4, {0, 1}, 5, 0.1)},
      {"C6 {0,1,2}", Spec(SymmetryType::kDiscrete, 6, {0, 1, 2}, 5, 0.1)},
      {"C4 {0}", Spec(SymmetryType::kDiscrete, 4, {0}, 5, 0.1)},
  };
  unsigned seed = 100;
  for (const Case& c : cases) {
    const CellResult r = RunCell(c.spec, 150, seed++);
    EXPECT_GE(r.correct, 0.98 * r.count) << c.name;
    if (!r.axis_error.empty()) {
      EXPECT_LT(Median(r.axis_error), 2.0) << c.name;
    }
    if (!r.angle_error.empty()) {
      EXPECT_LT(Median(r.angle_error), 3.0) << c.name;
    }
    if (r.modes_checked > 0) {
      EXPECT_GE(r.all_modes_found, 0.97 * r.modes_checked) << c.name;
    }
  }
}

// Two adjacent 6-fold modes pin the axis only through one 60-degree
// relative rotation. At 5 degrees RMS rotation angle (5 / sqrt(3) per axis,
// the benchmark's default reading) the target holds; at 5 degrees per axis
// the median is at the information limit, 1.18 * 5 * sqrt(2 / 13.5) = 2.26
// degrees, and within 10 % of it (docs/categorization.md).
TEST(CategorizeTest, TwoAdjacentSixFoldModesReachTheTargetAndTheLimit) {
  const HypothesisSetSpec rms_angle =
      Spec(SymmetryType::kDiscrete, 6, {0, 1}, 5.0 / std::sqrt(3.0), 0.1);
  const CellResult r = RunCell(rms_angle, 200, 7);
  EXPECT_GE(r.correct, 0.98 * r.count);
  EXPECT_LT(Median(r.axis_error), 2.0);
  EXPECT_LT(Median(r.angle_error), 3.0);
  EXPECT_GE(r.all_modes_found, 0.97 * r.modes_checked);

  const HypothesisSetSpec per_axis =
      Spec(SymmetryType::kDiscrete, 6, {0, 1}, 5.0, 0.1);
  const double limit = 1.1774 * 5.0 * std::sqrt(2.0 / 13.5);
  const double median = Median(RunCell(per_axis, 200, 8).axis_error);
  EXPECT_GT(median, 0.85 * limit);
  EXPECT_LT(median, 1.10 * limit);
}

TEST(CategorizeTest, LowNoiseCellsAreExact) {
  unsigned seed = 200;
  for (double outliers : {0.0, 0.2}) {
    for (const HypothesisSetSpec& spec :
         {Spec(SymmetryType::kAsymmetric, 1, {}, 2, outliers),
          Spec(SymmetryType::kContinuous, 1, {}, 2, outliers),
          Spec(SymmetryType::kDiscrete, 3, {}, 2, outliers),
          Spec(SymmetryType::kDiscrete, 6, {0, 1}, 2, outliers),
          Spec(SymmetryType::kDiscrete, 2, {0}, 2, outliers)}) {
      const CellResult r = RunCell(spec, 60, seed++);
      EXPECT_GE(r.correct, 0.98 * r.count);
      if (!r.axis_error.empty()) {
        EXPECT_LT(Median(r.axis_error), 1.5);
      }
      if (!r.angle_error.empty()) {
        EXPECT_LT(Median(r.angle_error), 1.5);
      }
    }
  }
}

// A 4-fold object seen with two of its modes is discrete with two angles;
// with one mode it is asymmetric.
TEST(CategorizeTest, SubsetViewsOfFourFoldObject) {
  TestRandom random(17);
  for (int trial = 0; trial < 20; ++trial) {
    const GeneratedDetection d = GenerateDetection(
        Spec(SymmetryType::kDiscrete, 4, {0, 3}, 5, 0.1), &random);
    CategorizedDetection out;
    ASSERT_TRUE(
        Categorize(d.hypotheses, CategorizationOptions(), nullptr, &out).ok());
    ASSERT_EQ(out.type, SymmetryType::kDiscrete);
    ASSERT_EQ(out.clusters.size(), 2u);
    const double sign = out.axis_o.dot(d.axis_o) < 0 ? -1.0 : 1.0;
    const int ref_mode = d.mode[out.reference];
    const double truth = ref_mode == 0 ? -kPi / 2 : kPi / 2;
    EXPECT_NEAR(sign * out.clusters[1].theta, truth, 8 * kDegree);
    // No outlier among the survivors, every inlier kept.
    for (int j : out.inliers) EXPECT_GE(d.mode[j], 0);
  }
  for (int trial = 0; trial < 20; ++trial) {
    const GeneratedDetection d = GenerateDetection(
        Spec(SymmetryType::kDiscrete, 4, {2}, 5, 0.1), &random);
    CategorizedDetection out;
    ASSERT_TRUE(
        Categorize(d.hypotheses, CategorizationOptions(), nullptr, &out).ok());
    EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
    EXPECT_EQ(out.inliers.size(), 27u);
  }
}

// The heaviest hypothesis is an outlier: it is not used as the reference.
TEST(CategorizeTest, OutlierWithTheHighestWeightIsNotTheReference) {
  TestRandom random(23);
  for (SymmetryType type : {SymmetryType::kAsymmetric,
                            SymmetryType::kDiscrete,
                            SymmetryType::kContinuous}) {
    for (int trial = 0; trial < 10; ++trial) {
      GeneratedDetection d =
          GenerateDetection(Spec(type, 3, {}, 5, 0.2), &random);
      int outlier = 0;
      while (d.mode[outlier] >= 0) ++outlier;
      d.hypotheses[outlier].weight = 5.0;
      CategorizedDetection out;
      ASSERT_TRUE(
          Categorize(d.hypotheses, CategorizationOptions(), nullptr, &out)
              .ok());
      EXPECT_EQ(out.type, type);
      EXPECT_GE(d.mode[out.reference], 0);
      EXPECT_TRUE(std::find(out.inliers.begin(), out.inliers.end(), outlier) ==
                  out.inliers.end());
    }
  }
}

TEST(CategorizeTest, ReferenceIsTheHeaviestInlier) {
  TestRandom random(29);
  GeneratedDetection d =
      GenerateDetection(Spec(SymmetryType::kDiscrete, 2, {}, 2, 0.0), &random);
  d.hypotheses[7].weight = 3.0;
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(d.hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.reference, 7);
  EXPECT_EQ(out.type, SymmetryType::kDiscrete);
}

// Translation outliers are dropped before anything else.
TEST(CategorizeTest, TranslationOutliersAreGated) {
  TestRandom random(31);
  GeneratedDetection d = GenerateDetection(
      Spec(SymmetryType::kAsymmetric, 1, {}, 2, 0.0), &random);
  d.hypotheses[4].T_co.t += Eigen::Vector3d(0, 0, 1.0);
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(d.hypotheses, CategorizationOptions(), nullptr, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
  EXPECT_TRUE(std::find(out.inliers.begin(), out.inliers.end(), 4) ==
              out.inliers.end());
  EXPECT_LT((out.t_co - d.T_co_true.t).norm(), 0.03);
}

// A class prior refines: its axis is used, its order snaps the angles.
TEST(CategorizeTest, ClassPriorSnapsAnglesToTheOrder) {
  ClassPrior prior;
  prior.symmetry = SymmetryType::kDiscrete;
  prior.order = 4;
  const HypothesisSetSpec spec = Spec(SymmetryType::kDiscrete, 4, {}, 5, 0.1);
  TestRandom random(37);
  int snapped = 0;
  for (int trial = 0; trial < 50; ++trial) {
    GeneratedDetection d = GenerateDetection(spec, &random);
    ClassPrior with_axis = prior;
    with_axis.axis_o = -d.axis_o * 3.0;  // any length, any sign
    CategorizedDetection out;
    ASSERT_TRUE(
        Categorize(d.hypotheses, CategorizationOptions(), &with_axis, &out)
            .ok());
    ASSERT_EQ(out.type, SymmetryType::kDiscrete);
    ExpectWellFormed(d.hypotheses, out);
    EXPECT_TRUE(out.diagnostics.prior_axis_used);
    EXPECT_LT(AxisErrorDeg(out.axis_o, d.axis_o), 1e-9);
    if (!out.diagnostics.prior_order_snapped) continue;
    ++snapped;
    for (const AngleCluster& c : out.clusters) {
      const double steps = c.theta / (kPi / 2);
      EXPECT_NEAR(steps, std::round(steps), 1e-12);
    }
  }
  EXPECT_GE(snapped, 48);
}

TEST(CategorizeTest, ClassPriorAxisImprovesTheCameraAxis) {
  ClassPrior prior;
  prior.symmetry = SymmetryType::kContinuous;
  const CellResult with = RunCell(
      Spec(SymmetryType::kContinuous, 1, {}, 5, 0.1), 100, 41, &prior, true);
  const CellResult without =
      RunCell(Spec(SymmetryType::kContinuous, 1, {}, 5, 0.1), 100, 41);
  EXPECT_GE(with.correct, 98);
  EXPECT_LE(Median(with.axis_error), Median(without.axis_error) + 0.1);
}

// One mode of a class with a symmetric prior takes the prior's type: one
// pose (a single-hypothesis detector) and a noisy one-mode set, any axis.
TEST(CategorizeTest, OneModeTakesTheTypeOfASymmetricPrior) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
  const Eigen::Quaterniond q = Rot(Eigen::Vector3d(0.3, 1, -0.2), 0.8);
  const Eigen::Vector3d t(0.1, -0.2, 2.5);
  for (SymmetryType type :
       {SymmetryType::kDiscrete, SymmetryType::kContinuous}) {
    ClassPrior prior;
    prior.symmetry = type;
    prior.order = type == SymmetryType::kDiscrete ? 3 : 0;
    prior.axis_o = -2.0 * axis;  // any length, any sign
    CategorizedDetection out;
    const std::vector<PoseHypothesis> one = {Hyp(q, t, 0.7)};
    ASSERT_TRUE(Categorize(one, CategorizationOptions(), &prior, &out).ok());
    ExpectWellFormed(one, out);
    EXPECT_EQ(out.type, type);
    EXPECT_TRUE(out.diagnostics.prior_type_used);
    EXPECT_TRUE(out.diagnostics.prior_axis_used);
    EXPECT_LT(RotationErrorDeg(out.T_co_base.q, q), 1e-9);
    EXPECT_LT((out.t_co - t).norm(), 1e-12);
    // The prior's axis, unit, with the prior's sign.
    EXPECT_LT((out.axis_o + axis).norm(), 1e-12);
    EXPECT_LT((out.axis_c + q * axis).norm(), 1e-12);
    EXPECT_EQ(out.inliers, std::vector<int>{0});
    EXPECT_NEAR(out.twist[0], 0.0, 1e-12);
    if (type == SymmetryType::kDiscrete) {
      ASSERT_EQ(out.clusters.size(), 1u);
      EXPECT_EQ(out.clusters[0].theta, 0.0);
      EXPECT_EQ(out.clusters[0].members, std::vector<int>{0});
      EXPECT_DOUBLE_EQ(out.clusters[0].weight, 0.7);
      EXPECT_NEAR(out.clusters[0].spread, 0.0, 1e-12);
    } else {
      EXPECT_TRUE(out.clusters.empty());
    }
  }
}

TEST(CategorizeTest, OneNoisyModeTakesThePriorTypeAndKeepsItsTwists) {
  ClassPrior prior;
  prior.symmetry = SymmetryType::kDiscrete;
  prior.order = 2;
  const HypothesisSetSpec spec = Spec(SymmetryType::kDiscrete, 2, {0}, 5, 0.1);
  TestRandom random(53);
  for (int trial = 0; trial < 20; ++trial) {
    GeneratedDetection d = GenerateDetection(spec, &random);
    prior.axis_o = d.axis_o;
    CategorizedDetection out;
    ASSERT_TRUE(
        Categorize(d.hypotheses, CategorizationOptions(), &prior, &out).ok());
    ASSERT_EQ(out.type, SymmetryType::kDiscrete);
    ExpectWellFormed(d.hypotheses, out);
    ASSERT_EQ(out.clusters.size(), 1u);
    EXPECT_EQ(out.clusters[0].members, out.inliers);
    EXPECT_LT(AxisErrorDeg(out.axis_c, d.T_co_true.q * d.axis_o), 5.0);
    // Each inlier's twist reproduces its rotation about the axis up to the
    // swing: R_j ~= R_base Rot(a_o, twist_j) within the noise.
    for (int j : out.inliers) {
      const Eigen::Quaterniond rebuilt =
          out.T_co_base.q * Rot(out.axis_o, out.twist[j]);
      EXPECT_LT(RotationErrorDeg(rebuilt, d.hypotheses[j].T_co.q), 25.0);
    }
  }
}

TEST(CategorizeTest, OneModeStaysAsymmetricWithoutAUsablePrior) {
  const std::vector<PoseHypothesis> one = {Hyp(Rot({0, 0, 1}, 0.4))};
  ClassPrior no_axis;
  no_axis.symmetry = SymmetryType::kContinuous;
  ClassPrior asymmetric;
  ClassPrior with_axis = no_axis;
  with_axis.axis_o = Eigen::Vector3d::UnitZ();
  CategorizationOptions off;
  off.read_one_mode_with_prior = false;
  CategorizedDetection out;
  const std::vector<const ClassPrior*> priors = {
      nullptr, &no_axis, &asymmetric};
  for (const ClassPrior* prior : priors) {
    ASSERT_TRUE(Categorize(one, CategorizationOptions(), prior, &out).ok());
    EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
    EXPECT_FALSE(out.diagnostics.prior_type_used);
  }
  ASSERT_TRUE(Categorize(one, off, &with_axis, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kAsymmetric);
  EXPECT_FALSE(out.diagnostics.prior_type_used);
  EXPECT_TRUE(out.axis_o.isZero());
}

// Hypotheses that show two modes keep their own type under any prior.
TEST(CategorizeTest, TwoModesKeepTheirTypeUnderAContinuousPrior) {
  const HypothesisSetSpec spec = Spec(SymmetryType::kDiscrete, 2, {}, 3, 0.0);
  TestRandom random(59);
  GeneratedDetection d = GenerateDetection(spec, &random);
  ClassPrior prior;
  prior.symmetry = SymmetryType::kContinuous;
  prior.axis_o = d.axis_o;
  CategorizedDetection out;
  ASSERT_TRUE(
      Categorize(d.hypotheses, CategorizationOptions(), &prior, &out).ok());
  EXPECT_EQ(out.type, SymmetryType::kDiscrete);
  EXPECT_FALSE(out.diagnostics.prior_type_used);
}

// ---------------------------------------------------------------------------
// The generator itself.

TEST(HypothesisGeneratorTest, MakesWhatTheSpecSays) {
  TestRandom random(3);
  const HypothesisSetSpec spec =
      Spec(SymmetryType::kDiscrete, 6, {1, 4}, 2, 0.2);
  const GeneratedDetection d = GenerateDetection(spec, &random);
  ASSERT_EQ(d.hypotheses.size(), 30u);
  EXPECT_EQ(std::count(d.mode.begin(), d.mode.end(), -1), 6);
  EXPECT_EQ(std::count(d.mode.begin(), d.mode.end(), 1), 12);
  EXPECT_EQ(std::count(d.mode.begin(), d.mode.end(), 4), 12);
  EXPECT_NEAR(d.axis_o.norm(), 1.0, 1e-12);
  EXPECT_LT((d.T_co_true.q * d.axis_o - d.axis_c).norm(), 1e-12);
  for (int j = 0; j < 30; ++j) {
    if (d.mode[j] < 0) continue;
    const Eigen::Quaterniond mode_pose =
        d.T_co_true.q * Rot(d.axis_o, kTwoPi * d.mode[j] / 6);
    EXPECT_LT(RotationErrorDeg(mode_pose, d.hypotheses[j].T_co.q), 15.0);
    EXPECT_LT((d.hypotheses[j].T_co.t - d.T_co_true.t).norm(), 0.2);
  }
  // One visible mode reads as asymmetric.
  EXPECT_EQ(
      GenerateDetection(Spec(SymmetryType::kDiscrete, 4, {0}, 2, 0.0), &random)
          .expected_type,
      SymmetryType::kAsymmetric);
}

}  // namespace
}  // namespace symba
