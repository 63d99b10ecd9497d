// MeasureHypothesisScatter: the spread of a detection's hypotheses about
// their own modes recovers the noise they were drawn with, for every
// symmetry type, with outliers among them.
#include "symba/categorization/hypothesis_scatter.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/categorization/categorize.h"
#include "test_support/hypothesis_generator.h"
#include "test_support/random.h"

namespace symba {
namespace {

using testing::GeneratedDetection;
using testing::HypothesisSetSpec;
using testing::kDegree;
using testing::TestRandom;

struct ScatterCase {
  std::string name;
  HypothesisSetSpec spec;
};

// The mean scatter over 40 detections of 30 hypotheses (10 % outliers)
// drawn with s_t = 0.03 m and s_r = 3 deg per axis is within 15 % of both.
class HypothesisScatterTest : public ::testing::TestWithParam<ScatterCase> {};

TEST_P(HypothesisScatterTest, RecoversTheNoiseTheHypothesesWereDrawnWith) {
  HypothesisSetSpec spec = GetParam().spec;
  spec.translation_sigma = 0.03;
  spec.rotation_sigma = 3.0 * kDegree;
  TestRandom random(7);
  const CategorizationOptions options;
  double sum_t = 0.0;
  double sum_r = 0.0;
  int detections = 0;
  for (int i = 0; i < 40; ++i) {
    const GeneratedDetection d = testing::GenerateDetection(spec, &random);
    CategorizedDetection cat;
    ASSERT_TRUE(Categorize(d.hypotheses, options, nullptr, &cat).ok());
    if (cat.type != d.expected_type) continue;  // categorisation's own tests
    const HypothesisScatter scatter =
        MeasureHypothesisScatter(d.hypotheses, cat);
    EXPECT_GE(scatter.count, 20) << i;
    sum_t += scatter.sigma_t;
    sum_r += scatter.sigma_r;
    ++detections;
  }
  ASSERT_GE(detections, 30);
  EXPECT_NEAR(sum_t / detections, 0.03, 0.15 * 0.03);
  EXPECT_NEAR(sum_r / detections, 3.0 * kDegree, 0.15 * 3.0 * kDegree);
}

HypothesisSetSpec Spec(SymmetryType type, int order) {
  HypothesisSetSpec spec;
  spec.type = type;
  spec.order = order;
  return spec;
}

INSTANTIATE_TEST_SUITE_P(
    EveryType,
    HypothesisScatterTest,
    ::testing::Values(
        ScatterCase{"asymmetric", Spec(SymmetryType::kAsymmetric, 1)},
        ScatterCase{"two_fold", Spec(SymmetryType::kDiscrete, 2)},
        ScatterCase{"four_fold", Spec(SymmetryType::kDiscrete, 4)},
        ScatterCase{"continuous", Spec(SymmetryType::kContinuous, 0)}),
    [](const ::testing::TestParamInfo<ScatterCase>& info) {
      return info.param.name;
    });

// The scatter of `hyps`, categorised with the default options as
// `expected`. Use with ASSERT_NO_FATAL_FAILURE.
void CategorizedScatter(const std::vector<PoseHypothesis>& hyps,
                        SymmetryType expected,
                        HypothesisScatter* scatter) {
  CategorizedDetection cat;
  ASSERT_TRUE(Categorize(hyps, CategorizationOptions(), nullptr, &cat).ok());
  ASSERT_EQ(cat.type, expected);
  *scatter = MeasureHypothesisScatter(hyps, cat);
}

// The scatter is measured about each mode, not about one: a 2-fold
// detection whose modes lie 180 degrees apart has the rotation scatter of
// one mode.
TEST(HypothesisScatter, AnotherModeIsNoSpread) {
  const Eigen::Vector3d axis(0, 0, 1);
  std::vector<PoseHypothesis> hyps;
  for (int j = 0; j < 20; ++j) {
    PoseHypothesis h;
    const double tilt = (j % 5 - 2) * 0.01;  // rad, about x
    h.T_co =
        Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd((j % 2) * kPi, axis)) *
                    Eigen::Quaterniond(
                        Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX())),
                Eigen::Vector3d(0, 0, 2));
    hyps.push_back(h);
  }
  HypothesisScatter scatter;
  ASSERT_NO_FATAL_FAILURE(
      CategorizedScatter(hyps, SymmetryType::kDiscrete, &scatter));
  EXPECT_EQ(scatter.count, 20);
  EXPECT_LT(scatter.sigma_r, 0.02);  // tilts of 0, 0.01, 0.02 rad
  EXPECT_DOUBLE_EQ(scatter.sigma_t, 0.0);
}

// Exact value: six hypotheses of one rotation, 1 cm from their centre along
// +-x, +-y, +-z: every error 1 cm, N = 6, so sigma_t = sqrt(6 / 5) 0.01 /
// 1.5381722 (the centre is their mean), and no rotation spread.
TEST(HypothesisScatter, IsTheMedianOverTheChiMedianForAFittedCentre) {
  std::vector<PoseHypothesis> hyps;
  const Eigen::Vector3d centre(0.2, -0.1, 2.0);
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {-1.0, 1.0}) {
      PoseHypothesis h;
      h.T_co = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(
                           0.4, Eigen::Vector3d(1, 2, 3).normalized())),
                       centre + sign * 0.01 * Eigen::Vector3d::Unit(axis));
      hyps.push_back(h);
    }
  }
  HypothesisScatter scatter;
  ASSERT_NO_FATAL_FAILURE(
      CategorizedScatter(hyps, SymmetryType::kAsymmetric, &scatter));
  EXPECT_EQ(scatter.count, 6);
  EXPECT_NEAR(scatter.sigma_t, std::sqrt(1.2) * 0.01 / 1.5381722, 1e-9);
  EXPECT_NEAR(scatter.sigma_r, 0.0, 1e-7);
}

// One pose has no spread to measure.
TEST(HypothesisScatter, ASinglePoseHasNone) {
  PoseHypothesis h;
  h.T_co = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 1));
  CategorizedDetection cat;
  ASSERT_TRUE(Categorize({h}, CategorizationOptions(), nullptr, &cat).ok());
  const HypothesisScatter scatter = MeasureHypothesisScatter({h}, cat);
  EXPECT_EQ(scatter.count, 1);
  EXPECT_EQ(scatter.sigma_t, 0.0);
  EXPECT_EQ(scatter.sigma_r, 0.0);
}

}  // namespace
}  // namespace symba
