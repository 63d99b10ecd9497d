// The keyframes and points on their own (src/backend/trajectory.h): a new
// keyframe's initial and front-end chain poses, its camera motion factor
// and the motion variance it predicts with, points created from a first
// observation with a depth, and keyframes found by id.
#include "backend/trajectory.h"

#include <memory>
#include <vector>

#include <gtest/gtest.h>

namespace symba::internal {
namespace {

Rigid3d PoseAt(double x, double y, double z) {
  return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, y, z));
}

// The trajectory and the graph over its keyframes and points, built as the
// backend builds them.
struct TrajectoryAndGraph {
  TrajectoryAndGraph(const BackendOptions& options,
                     const std::optional<PinholeIntrinsics>& intrinsics,
                     BackendStatistics* statistics)
      : trajectory(options, intrinsics, &graph, statistics),
        graph(options,
              trajectory.keyframes(),
              objects,
              trajectory.points(),
              statistics) {}
  ObjectList objects;
  Trajectory trajectory;
  FactorGraph graph;
};

class TrajectoryTest : public ::testing::Test {
 protected:
  void Build(
      const std::optional<PinholeIntrinsics>& intrinsics = std::nullopt) {
    parts_ = std::make_unique<TrajectoryAndGraph>(
        options_, intrinsics, &statistics_);
  }
  Trajectory& trajectory() { return parts_->trajectory; }
  const FactorRecord& LastFactor(int k) {
    return parts_->graph.factor(trajectory().keyframes()[k]->factors.back());
  }

  BackendOptions options_;
  BackendStatistics statistics_;
  std::unique_ptr<TrajectoryAndGraph> parts_;
};

// Odometry chains from the previous keyframe's optimised pose; the chain
// pose from the previous chain pose, never optimised.
TEST_F(TrajectoryTest, OdometryMovesTheOptimisedPoseAndTheChain) {
  Build();
  KeyframeInput first;
  first.id = 10;
  first.T_wc = PoseAt(1, 0, 0);
  EXPECT_EQ(trajectory().Add(first, nullptr), 0);
  // As if a solve had moved keyframe 0 by 0.5 m along y.
  Eigen::Map<Eigen::Vector3d>(trajectory().keyframes()[0]->t) =
      Eigen::Vector3d(1, 0.5, 0);
  KeyframeInput second;
  second.id = 11;
  second.odometry = Odometry{PoseAt(0, 0, 2), 0.1, 0.2};
  EXPECT_EQ(trajectory().Add(second, nullptr), 1);
  const KeyframeState& kf = *trajectory().keyframes()[1];
  EXPECT_LT((kf.T_wc().t - Eigen::Vector3d(1, 0.5, 2)).norm(), 1e-12);
  EXPECT_LT((kf.T_wc_chain.t - Eigen::Vector3d(1, 0, 2)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(kf.motion_variance_t, 0.1 * 0.1);
  EXPECT_DOUBLE_EQ(kf.motion_variance_r, 0.2 * 0.2);
  const FactorRecord& odometry = LastFactor(1);
  EXPECT_EQ(odometry.keyframe, 1);
  EXPECT_EQ(odometry.keyframe2, 0);
  EXPECT_EQ(statistics_.keyframes, 2);
  EXPECT_EQ(trajectory().Find(11), &kf);
  EXPECT_EQ(trajectory().Find(12), nullptr);
}

// Front-end poses: the relative motion since the last keyframe the front
// end posed, applied to that keyframe's optimised pose, with the options'
// front-end noise.
TEST_F(TrajectoryTest, FrontEndPosesChainTheirRelativeMotion) {
  Build();
  KeyframeInput first;
  first.id = 0;
  first.T_wc = PoseAt(0, 0, 0);
  trajectory().Add(first, nullptr);
  Eigen::Map<Eigen::Vector3d>(trajectory().keyframes()[0]->t) =
      Eigen::Vector3d(0, 0, 1);
  KeyframeInput second;
  second.id = 1;
  second.T_wc = PoseAt(3, 0, 0);
  trajectory().Add(second, nullptr);
  const KeyframeState& kf = *trajectory().keyframes()[1];
  EXPECT_LT((kf.T_wc().t - Eigen::Vector3d(3, 0, 1)).norm(), 1e-12);
  EXPECT_LT((kf.T_wc_chain.t - Eigen::Vector3d(3, 0, 0)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(kf.motion_variance_t,
                   options_.frontend_sigma_t * options_.frontend_sigma_t);
  EXPECT_EQ(LastFactor(1).keyframe2, 0);
}

// A point is created from its first observation with a depth (back-projected
// through the intrinsics); an observation without one before that adds
// nothing, after it a reprojection factor.
// The motion noise report: per source, the steps and the median sigmas
// their factors were built with (odometry as stated, front-end poses at
// frontend_sigma_*); the first keyframe has no factor.
TEST_F(TrajectoryTest, ReportsTheNoiseOfEachMotionFactorsSource) {
  options_.frontend_sigma_t = 0.04;
  options_.frontend_sigma_r = 0.03;
  Build();
  EXPECT_EQ(trajectory().MotionNoise().odometry_steps, 0);
  EXPECT_FALSE(trajectory().MotionNoise().odometry_sigma_t.has_value());
  KeyframeInput kf;
  kf.id = 1;
  kf.T_wc = PoseAt(0, 0, 0);
  trajectory().Add(kf, nullptr);
  for (const double sigma_t : {0.01, 0.03, 0.02}) {
    KeyframeInput next;
    next.id = ++kf.id;
    next.odometry = Odometry{PoseAt(0, 0, 1), sigma_t, 2.0 * sigma_t};
    trajectory().Add(next, nullptr);
  }
  KeyframeInput posed;
  posed.id = ++kf.id;
  posed.T_wc = PoseAt(0, 0, 4);
  trajectory().Add(posed, nullptr);
  const MotionNoiseReport report = trajectory().MotionNoise();
  EXPECT_EQ(report.odometry_steps, 3);
  EXPECT_DOUBLE_EQ(*report.odometry_sigma_t, 0.02);
  EXPECT_DOUBLE_EQ(*report.odometry_sigma_r, 0.04);
  EXPECT_EQ(report.frontend_steps, 1);
  EXPECT_DOUBLE_EQ(*report.frontend_sigma_t, 0.04);
  EXPECT_DOUBLE_EQ(*report.frontend_sigma_r, 0.03);
  // The motion variances summed keyframe after keyframe: the front end's
  // pose, a step from the last keyframe it posed (the first), counts from
  // the previous keyframe.
  const KeyframeList& keyframes = trajectory().keyframes();
  EXPECT_DOUBLE_EQ(keyframes[0]->summed_motion_variance_t, 0.0);
  EXPECT_NEAR(keyframes[3]->summed_motion_variance_t,
              0.01 * 0.01 + 0.03 * 0.03 + 0.02 * 0.02,
              1e-15);
  EXPECT_NEAR(keyframes[3]->summed_motion_variance_r,
              0.02 * 0.02 + 0.06 * 0.06 + 0.04 * 0.04,
              1e-15);
  EXPECT_NEAR(keyframes[4]->summed_motion_variance_t,
              keyframes[3]->summed_motion_variance_t + 0.04 * 0.04,
              1e-15);
  EXPECT_NEAR(keyframes[4]->summed_motion_variance_r,
              keyframes[3]->summed_motion_variance_r + 0.03 * 0.03,
              1e-15);
}

TEST_F(TrajectoryTest, PointsAreCreatedFromADepth) {
  options_.point_depth_sigma_relative = 0.0;  // no depth factors
  Build(PinholeIntrinsics{100, 100, 50, 50});
  KeyframeInput first;
  first.id = 0;
  first.T_wc = PoseAt(1, 0, 0);
  first.points = {PointObservation{7, Eigen::Vector2d(150, 50), std::nullopt}};
  trajectory().Add(first, nullptr);
  EXPECT_TRUE(trajectory().points().empty());
  EXPECT_TRUE(trajectory().keyframes()[0]->factors.empty());
  KeyframeInput second;
  second.id = 1;
  second.T_wc = PoseAt(1, 0, 0);
  second.points = {PointObservation{7, Eigen::Vector2d(150, 50), 2.0}};
  trajectory().Add(second, nullptr);
  ASSERT_EQ(trajectory().points().size(), 1u);
  // (150 - 50) / 100 * 2 = 2 m right of the camera, 2 m ahead.
  EXPECT_LT((Eigen::Map<const Eigen::Vector3d>(trajectory().points()[0]->p) -
             Eigen::Vector3d(3, 0, 2))
                .norm(),
            1e-12);
  EXPECT_EQ(LastFactor(1).point, 0);
  EXPECT_EQ(statistics_.points, 1);
}

// With the front end's statements tested (motion_claims.h), a step of a
// group the objects found understated is built with its stated sigmas
// times the group's factor: its variances and its factor's whitening; the
// report keeps the sigmas as stated.
TEST_F(TrajectoryTest, AStepOfAScaledGroupIsWeighedWithTheFactor) {
  Build();
  MotionClaims claims(10, 1, 1.2, 1.0);
  const double chi2 = kChi3Median * kChi3Median;
  claims.Add(0.005, 0.01, 0.0, 1e-3, 1e-4);  // vouches (g 0, s^2 < c)
  claims.Add(0.01, 0.02, chi2 * (4.0 * 1e-4 + 1e-3), 1e-3, 1e-4);  // g = 2
  KeyframeInput first;
  first.id = 1;
  first.T_wc = PoseAt(0, 0, 0);
  trajectory().Add(first, &claims);
  KeyframeInput next;
  next.id = 2;
  next.odometry = Odometry{PoseAt(0, 0, 1), 0.01, 0.02};
  trajectory().Add(next, &claims);
  const KeyframeState& kf = *trajectory().keyframes()[1];
  EXPECT_DOUBLE_EQ(kf.stated_motion_sigma_t, 0.01);
  EXPECT_DOUBLE_EQ(kf.stated_motion_sigma_r, 0.02);
  EXPECT_NEAR(kf.motion_variance_t, 0.02 * 0.02, 1e-15);
  EXPECT_NEAR(kf.motion_variance_r, 0.04 * 0.04, 1e-15);
  EXPECT_NEAR(kf.summed_motion_variance_t, 0.02 * 0.02, 1e-15);
  EXPECT_DOUBLE_EQ(*trajectory().MotionNoise().odometry_sigma_t, 0.01);
  // The factor's residual for the keyframe 0.1 m off along x: 0.1 / 0.02.
  const FactorRecord& factor = LastFactor(1);
  double t_moved[3] = {kf.t[0] + 0.1, kf.t[1], kf.t[2]};
  const double* parameters[4] = {
      factor.blocks[0], factor.blocks[1], factor.blocks[2], t_moved};
  double residual[6];
  ASSERT_TRUE(factor.cost->Evaluate(parameters, residual, nullptr));
  const Vector6d whitened = Eigen::Map<const Vector6d>(residual);
  EXPECT_NEAR(whitened.norm(), 5.0, 1e-9);
  // A step stated otherwise (no samples) is taken as stated.
  KeyframeInput other;
  other.id = 3;
  other.odometry = Odometry{PoseAt(0, 0, 1), 0.05, 0.1};
  trajectory().Add(other, &claims);
  EXPECT_NEAR(
      trajectory().keyframes()[2]->motion_variance_t, 0.05 * 0.05, 1e-15);
}

}  // namespace
}  // namespace symba::internal
