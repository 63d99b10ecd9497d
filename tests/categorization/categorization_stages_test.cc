// The categorization's stages (src/categorization/*.h) on small inputs whose
// results are known exactly; categorize_test.cc tests the whole.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "categorization/asymmetric_result.h"
#include "categorization/categorize_with_valid_options.h"
#include "categorization/discrete_result.h"
#include "categorization/hypothesis_set.h"
#include "categorization/reference_choice.h"
#include "categorization/signed_twists.h"
#include "categorization/symmetry_axis.h"
#include "categorization/symmetry_decision.h"
#include "categorization/twist_clusters.h"
#include "symba/geometry/angle.h"
#include "test_support/hypothesis_generator.h"
#include "test_support/random.h"

namespace symba {
namespace categorization {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr int kNoise = CircularDbscanResult::kNoiseLabel;

PoseHypothesis AboutZ(double angle,
                      const Eigen::Vector3d& t = Eigen::Vector3d::Zero(),
                      double weight = 1.0) {
  PoseHypothesis h;
  h.T_co = Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ())),
      t);
  h.weight = weight;
  return h;
}

CircularCluster Arc(double start, double extent, int size) {
  CircularCluster c;
  c.start = start;
  c.extent = extent;
  c.size = size;
  return c;
}

TEST(TranslationGate, DropsWhatIsFarFromTheMedian) {
  // Medians per axis: x 0.1, y 0, z 1.
  const std::vector<PoseHypothesis> h = {AboutZ(0.0, {0.0, 0.0, 1.0}),
                                         AboutZ(0.0, {0.1, 0.0, 1.0}),
                                         AboutZ(0.0, {0.2, 0.0, 1.0}),
                                         AboutZ(0.0, {0.1, 0.5, 1.0}),
                                         AboutZ(0.0, {0.1, 0.0, 1.3})};
  EXPECT_EQ(GateTranslations(h, 0.2), std::vector<char>({1, 1, 1, 0, 0}));
  EXPECT_EQ(GateTranslations(h, 0.05), std::vector<char>({0, 1, 0, 0, 0}));
  EXPECT_EQ(GateTranslations(h, std::numeric_limits<double>::infinity()),
            std::vector<char>(5, 1));
}

TEST(TranslationGate, KeepsEverythingRatherThanNothing) {
  // The coordinate-wise median (1, 1, 0) is none of the hypotheses: 1, 1
  // and sqrt(2) from it.
  const std::vector<PoseHypothesis> h = {AboutZ(0.0, {0.0, 1.0, 0.0}),
                                         AboutZ(0.0, {1.0, 0.0, 0.0}),
                                         AboutZ(0.0, {2.0, 2.0, 0.0})};
  EXPECT_EQ(GateTranslations(h, 1.0), std::vector<char>({1, 1, 0}));
  EXPECT_EQ(GateTranslations(h, 0.5), std::vector<char>({1, 1, 1}));
}

TEST(MeanTranslation, WeighsTheMembers) {
  const HypothesisSet set =
      MakeHypothesisSet({AboutZ(0.0, {1.0, 0.0, 0.0}, 1.0),
                         AboutZ(0.0, {4.0, 0.0, 0.0}, 2.0),
                         AboutZ(0.0, {9.0, 0.0, 0.0}, 1.0)},
                        0.2);
  EXPECT_EQ(MeanTranslation(set, {0, 1}), Eigen::Vector3d(3.0, 0.0, 0.0));
  EXPECT_EQ(MeanTranslation(set, {}), Eigen::Vector3d(1.0, 0.0, 0.0));
}

TEST(ReferenceChoice, HighestWeightWithSupport) {
  // 0, 10 and 20 degrees support one another within 30 degrees; 100 degrees
  // has only itself, and the highest weight.
  const HypothesisSet set =
      MakeHypothesisSet({AboutZ(0.0, Eigen::Vector3d::Zero(), 1.0),
                         AboutZ(10 * kDeg, Eigen::Vector3d::Zero(), 2.0),
                         AboutZ(20 * kDeg, Eigen::Vector3d::Zero(), 1.0),
                         AboutZ(100 * kDeg, Eigen::Vector3d::Zero(), 5.0)},
                        0.2);
  EXPECT_EQ(RotationSupport(set, 30 * kDeg), std::vector<int>({3, 3, 3, 1}));
  EXPECT_EQ(ChooseReference(set, 30 * kDeg, 3), 1);
  // Nobody has 4 neighbours: the highest weight of all.
  EXPECT_EQ(ChooseReference(set, 30 * kDeg, 4), 3);
}

TEST(SymmetryAxis, RelativeRotationsAndVotes) {
  // Modes at 0 and 180 degrees about z, and a near one at 5 degrees.
  const HypothesisSet set =
      MakeHypothesisSet({AboutZ(0.0),
                         AboutZ(kPi, Eigen::Vector3d::Zero(), 2.0),
                         AboutZ(kPi, Eigen::Vector3d::Zero(), 1.0),
                         AboutZ(5 * kDeg)},
                        0.2);
  const RelativeRotations rotations = RelativeRotationsTo(set, 0, 30 * kDeg);
  EXPECT_EQ(rotations.far, std::vector<int>({1, 2}));
  EXPECT_NEAR(rotations.theta[1], kPi, 1e-15);
  EXPECT_NEAR(rotations.theta[3], 5 * kDeg, 1e-15);
  EXPECT_EQ(rotations.dir[3], Eigen::Vector3d::Zero());
  const AxisVote vote =
      VoteAxis(rotations, set.w, 20 * kDeg, /*prior_axis=*/std::nullopt);
  EXPECT_EQ(vote.support, 2);
  EXPECT_EQ(vote.support_weight, 3.0);
  EXPECT_NEAR(std::abs(vote.guess.z()), 1.0, 1e-15);
  // A prior axis along x agrees with nobody.
  const AxisVote prior_vote =
      VoteAxis(rotations, set.w, 20 * kDeg, Eigen::Vector3d::UnitX().eval());
  EXPECT_EQ(prior_vote.support, 0);
  EXPECT_EQ(prior_vote.guess, Eigen::Vector3d::UnitX());
}

TEST(SymmetryAxis, FitOfAFourFoldSetIsItsAxis) {
  // B = sum_k Rot(z, k pi / 2) = diag(0, 0, 4): the only direction every
  // hypothesis maps to the same camera direction is z.
  const HypothesisSet set = MakeHypothesisSet(
      {AboutZ(0.0), AboutZ(kPi / 2), AboutZ(kPi), AboutZ(-kPi / 2)}, 0.2);
  Eigen::Vector3d axis_o, axis_c;
  ASSERT_TRUE(FitAxis(set,
                      {1, 1, 1, 1},
                      Eigen::Vector3d(0.1, 0.0, 1.0).normalized(),
                      &axis_o,
                      &axis_c));
  EXPECT_NEAR((axis_o - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-15);
  EXPECT_NEAR((axis_c - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-15);
  // The identity and a half-turn about z: B = diag(0, 0, 2) maps no
  // direction of the xy plane anywhere.
  const HypothesisSet half_turns =
      MakeHypothesisSet({AboutZ(0.0), AboutZ(kPi)}, 0.2);
  EXPECT_FALSE(
      FitAxis(half_turns, {1, 1}, Eigen::Vector3d::UnitY(), &axis_o, &axis_c));
}

TEST(SignedTwists, AreTheAnglesAboutTheAxis) {
  const HypothesisSet set = MakeHypothesisSet(
      {AboutZ(0.5), AboutZ(0.5 + kPi / 2), AboutZ(0.5 - 2.0)}, 0.2);
  const SignedTwists twists = TwistsAboutAxis(
      set, 0, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ(), {1, 0, 1});
  EXPECT_NEAR(twists.psi[0], 0.0, 1e-15);
  EXPECT_NEAR(twists.psi[1], kPi / 2, 1e-15);
  EXPECT_NEAR(twists.psi[2], -2.0, 1e-15);
  EXPECT_EQ(twists.inlier_owner, std::vector<int>({0, 2}));
  EXPECT_EQ(twists.inlier_psi,
            std::vector<double>({twists.psi[0], twists.psi[2]}));
}

TEST(TwistClusters, MergesTheClosestCompactPair) {
  CategorizationOptions options;  // separation 20 deg, extent 45 deg
  CircularDbscanResult clusters;
  clusters.clusters = {Arc(0.0, 10 * kDeg, 2),
                       Arc(25 * kDeg, 10 * kDeg, 2),
                       Arc(kPi / 2, 5 * kDeg, 1)};
  clusters.labels = {0, 0, 1, 1, 2, kNoise};
  clusters.num_noise = 1;
  MergeCloseClusters(options, &clusters);
  ASSERT_EQ(clusters.clusters.size(), 2u);
  EXPECT_EQ(clusters.clusters[0].start, 0.0);
  EXPECT_DOUBLE_EQ(clusters.clusters[0].extent, 35 * kDeg);
  EXPECT_EQ(clusters.clusters[0].size, 4);
  EXPECT_EQ(clusters.labels, std::vector<int>({0, 0, 0, 0, 1, kNoise}));
  // A union wider than max_cluster_extent stays apart.
  options.max_cluster_extent = 30 * kDeg;
  CircularDbscanResult wide;
  wide.clusters = {Arc(0.0, 10 * kDeg, 2), Arc(25 * kDeg, 10 * kDeg, 2)};
  wide.labels = {0, 0, 1, 1};
  MergeCloseClusters(options, &wide);
  EXPECT_EQ(wide.clusters.size(), 2u);
}

TEST(TwistClusters, RescuesASmallModeFarFromTheOthers) {
  CategorizationOptions options;  // rescue_min_points 2
  // Two clusters near 0 and pi/2; noise: a pair near pi, one point at 30
  // degrees (too close to the cluster at 0 to be a mode).
  const std::vector<double> twists = {
      0.0, 0.05, kPi / 2, kPi / 2 + 0.05, kPi - 0.02, -kPi + 0.02, 30 * kDeg};
  CircularDbscanResult clusters = ClusterTwists(twists, options);
  ASSERT_EQ(clusters.clusters.size(), 0u);  // min_points 3: all noise
  clusters.clusters = {Arc(0.0, 0.05, 2), Arc(kPi / 2, 0.05, 2)};
  clusters.labels = {0, 0, 1, 1, kNoise, kNoise, kNoise};
  clusters.num_noise = 3;
  RescueSmallModes(twists, options, &clusters);
  ASSERT_EQ(clusters.clusters.size(), 3u);
  EXPECT_EQ(clusters.clusters[2].size, 2);
  EXPECT_EQ(clusters.labels, std::vector<int>({0, 0, 1, 1, 2, 2, kNoise}));
  EXPECT_EQ(clusters.num_noise, 1);
}

TEST(SymmetryDecision, ShapeGapsAndEmptyFraction) {
  CategorizationOptions options;
  CircularDbscanResult clusters;
  clusters.clusters = {Arc(-0.1, 0.2, 3), Arc(kPi - 0.1, 0.2, 3)};
  const ClusterShape shape = MeasureClusters(options, clusters);
  EXPECT_EQ(shape.max_extent, 0.2);
  EXPECT_TRUE(shape.all_compact);
  EXPECT_NEAR(shape.min_separation, kPi - 0.2, 1e-15);
  EXPECT_TRUE(shape.separated);
  // Twists at 0, 0.1, pi: gaps 0.1, pi - 0.1, pi; the last two are wide.
  const std::vector<double> twists = {kPi, 0.0, 0.1};
  EXPECT_NEAR(EmptyFraction(twists, {1, 2, 0}, 20 * kDeg),
              (2 * kPi - 0.1) / kTwoPi,
              1e-15);
  EXPECT_EQ(EmptyFraction({1.0}, {0}, 20 * kDeg), 1.0);
}

TEST(SymmetryDecision, TypeFromTheEvidence) {
  const CategorizationOptions options;
  ClusterEvidence evidence;
  evidence.num_clusters = 1;
  evidence.num_twists = 10;
  evidence.num_noise = 2;  // 0.2 * 10: still few
  EXPECT_EQ(DecideSymmetryType(evidence, options), SymmetryType::kAsymmetric);
  evidence.num_noise = 3;
  EXPECT_EQ(DecideSymmetryType(evidence, options), SymmetryType::kContinuous);
  evidence.num_noise = 0;
  evidence.num_clusters = 2;
  evidence.shape.separated = true;
  evidence.empty_fraction = 0.7;
  EXPECT_EQ(DecideSymmetryType(evidence, options), SymmetryType::kDiscrete);
  evidence.empty_fraction = 0.69;
  EXPECT_EQ(DecideSymmetryType(evidence, options), SymmetryType::kContinuous);
}

TEST(SymmetryDecision, NextReferenceIsTheHeaviestOfTheLargestCluster) {
  SignedTwists twists;
  twists.inlier_owner = {0, 2, 3, 5, 6};
  CircularDbscanResult clusters;
  clusters.clusters = {Arc(0.0, 0.1, 2), Arc(1.0, 0.1, 3)};
  clusters.labels = {0, 1, 1, 0, 1};
  const std::vector<double> weights = {9, 1, 2, 3, 1, 9, 3};
  EXPECT_EQ(LabelOf(twists, clusters, 5), 0);
  EXPECT_EQ(LabelOf(twists, clusters, 1), kNoise);
  // Cluster 1 holds 2, 3 and 6; 3 and 6 weigh 3: the lower index.
  EXPECT_EQ(NextReference(twists, clusters, weights), 3);
}

TEST(DiscreteResult, ArcMeanAcrossTheSeam) {
  // One cluster starting at 3.0 rad: members at 3.0 and -3.0 (= 3.0 +
  // (2 pi - 6)); weights 1 and 3.
  const HypothesisSet set =
      MakeHypothesisSet({AboutZ(3.0, Eigen::Vector3d::Zero(), 1.0),
                         AboutZ(-3.0, Eigen::Vector3d::Zero(), 3.0),
                         AboutZ(1.0)},
                        0.2);
  Pass pass;
  pass.twists.psi = {3.0, -3.0, 1.0};
  pass.twists.inlier_owner = {0, 1, 2};
  pass.clusters.clusters = {Arc(3.0, kTwoPi - 6.0, 2)};
  pass.clusters.labels = {0, 0, kNoise};
  const ModeAngles modes = MeanModeAngles(set, pass);
  EXPECT_EQ(modes.label, std::vector<int>({0, 0, kNoise}));
  EXPECT_EQ(modes.weight, std::vector<double>({4.0}));
  EXPECT_NEAR(modes.mean[0], WrapToPi(3.0 + 0.75 * (kTwoPi - 6.0)), 1e-15);
}

TEST(DiscreteResult, SnapsToTheOrderAndReestimatesTheOffset) {
  // Order 4, clusters at 0 and 1.6 rad (near pi / 2); members' twists
  // relative to R_ref 0.02, -0.02 (cluster 0) and 1.6 (cluster 1).
  const std::vector<int> label = {0, 0, 1, kNoise};
  const std::vector<double> psi = {0.02, -0.02, 1.6, 2.5};
  const std::vector<double> weights = {1.0, 1.0, 2.0, 7.0};
  double offset = 0.0;
  std::vector<double> theta = {0.0, 1.6};
  ASSERT_TRUE(SnapToOrder(4, 15 * kDeg, label, psi, weights, &offset, &theta));
  EXPECT_EQ(theta, std::vector<double>({0.0, kPi / 2}));
  EXPECT_EQ(offset, (0.02 - 0.02 + 2.0 * (1.6 - kPi / 2)) / 4.0);
  // Not within the snap angle, or two clusters on one multiple: unchanged.
  offset = 0.1;
  theta = {0.0, 1.0};
  EXPECT_FALSE(SnapToOrder(4, 15 * kDeg, label, psi, weights, &offset, &theta));
  EXPECT_EQ(offset, 0.1);
  EXPECT_EQ(theta, std::vector<double>({0.0, 1.0}));
  theta = {0.0, kTwoPi - 0.05};
  EXPECT_FALSE(SnapToOrder(4, 15 * kDeg, label, psi, weights, &offset, &theta));
}

TEST(AsymmetricResult, MeanRotationOfTheNearOnes) {
  // 8 and -8 degrees about z average to 0; 90 degrees is too far.
  const HypothesisSet set =
      MakeHypothesisSet({AboutZ(8 * kDeg),
                         AboutZ(-8 * kDeg),
                         AboutZ(90 * kDeg, Eigen::Vector3d::Zero(), 5.0)},
                        0.2);
  const Eigen::Quaterniond mean = MeanRotationNear(set, set.q[0], 20 * kDeg);
  EXPECT_NEAR(RotationAngle(mean), 0.0, 1e-15);
  CategorizedDetection out;
  AssembleAsymmetric(set, 20 * kDeg, 0, &out);
  EXPECT_EQ(out.inliers, std::vector<int>({0, 1}));
  EXPECT_EQ(out.twist, std::vector<double>(3, 0.0));
}

// The backend's entry gives Categorize()'s results.
TEST(CategorizeWithValidOptions, SameAsCategorize) {
  testing::TestRandom random(7);
  const SymmetryType types[] = {SymmetryType::kAsymmetric,
                                SymmetryType::kDiscrete,
                                SymmetryType::kContinuous};
  testing::HypothesisSetSpec spec;
  for (int i = 0; i < 30; ++i) {
    spec.type = types[i % 3];
    const testing::GeneratedDetection d =
        testing::GenerateDetection(spec, &random);
    CategorizedDetection a, b;
    ASSERT_TRUE(
        Categorize(d.hypotheses, CategorizationOptions(), nullptr, &a).ok());
    ASSERT_TRUE(CategorizeWithValidOptions(
                    d.hypotheses, CategorizationOptions(), nullptr, &b)
                    .ok());
    EXPECT_EQ(a.type, b.type);
    EXPECT_EQ(a.inliers, b.inliers);
    EXPECT_EQ(a.twist, b.twist);
    EXPECT_EQ(a.T_co_base.q.coeffs(), b.T_co_base.q.coeffs());
  }
  // It still checks the hypotheses.
  CategorizedDetection out;
  EXPECT_FALSE(
      CategorizeWithValidOptions({}, CategorizationOptions(), nullptr, &out)
          .ok());
}

}  // namespace
}  // namespace categorization
}  // namespace symba
