// Tests of symba-real-bench's drifting front end (benchmarks/
// front_end_drift.h): no drift is the identity; each keyframe step is
// scaled, then turned about the camera's y axis by the yaw per metre of its
// original length, and chained from the first keyframe; frames between
// keyframes keep their motion relative to their keyframe.
#include "front_end_drift.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "symba/geometry/angle.h"

namespace symba::bench {
namespace {

constexpr double kTolerance = 1e-12;

Rigid3d Pose(double yaw_about_y, const Eigen::Vector3d& t) {
  return Rigid3d(Eigen::Quaterniond(
                     Eigen::AngleAxisd(yaw_about_y, Eigen::Vector3d::UnitY())),
                 t);
}

void ExpectNear(const Rigid3d& actual, const Rigid3d& expected) {
  EXPECT_LT((actual.t - expected.t).norm(), kTolerance)
      << actual.t.transpose() << " vs " << expected.t.transpose();
  EXPECT_LT(actual.q.angularDistance(expected.q), kTolerance);
}

// A camera walking 1 m per keyframe along its optical axis (z), every
// frame: frame f at z = f / stride.
std::vector<Rigid3d> StraightLine(int frames, int stride) {
  std::vector<Rigid3d> poses;
  for (int f = 0; f < frames; ++f) {
    poses.push_back(
        Pose(0.0, Eigen::Vector3d(0.0, 0.0, static_cast<double>(f) / stride)));
  }
  return poses;
}

TEST(FrontEndDrift, NoDriftKeepsTheFrontEnd) {
  std::vector<Rigid3d> poses = StraightLine(7, 2);
  poses[3] = Pose(0.4, Eigen::Vector3d(0.3, -0.1, 1.2));
  poses[4] = Pose(-0.2, Eigen::Vector3d(1.0, 0.2, 2.5));
  const std::vector<Rigid3d> drifted = DriftFrontEnd(poses, 2, {});
  ASSERT_EQ(drifted.size(), poses.size());
  for (std::size_t f = 0; f < poses.size(); ++f)
    ExpectNear(drifted[f], poses[f]);
  EXPECT_TRUE(FrontEndDrift().IsNone());
  EXPECT_FALSE((FrontEndDrift{0.0, 1.1}).IsNone());
}

TEST(FrontEndDrift, ScaleLengthensEveryKeyframeStep) {
  const std::vector<Rigid3d> drifted =
      DriftFrontEnd(StraightLine(3, 1), 1, {0.0, 1.1});
  ExpectNear(drifted[0], Pose(0.0, Eigen::Vector3d::Zero()));
  ExpectNear(drifted[1], Pose(0.0, Eigen::Vector3d(0.0, 0.0, 1.1)));
  ExpectNear(drifted[2], Pose(0.0, Eigen::Vector3d(0.0, 0.0, 2.2)));
}

// 90 degrees per metre on 1 m steps along z: the first step turns to +x
// (Rot(y, 90 deg) takes z to x) and the camera with it; the second, taken
// in the turned camera, goes to -z.
TEST(FrontEndDrift, YawTurnsEachStepByItsLength) {
  const double quarter = kPi / 2.0;
  const std::vector<Rigid3d> drifted =
      DriftFrontEnd(StraightLine(3, 1), 1, {quarter, 1.0});
  ExpectNear(drifted[1], Pose(quarter, Eigen::Vector3d(1.0, 0.0, 0.0)));
  ExpectNear(drifted[2], Pose(kPi, Eigen::Vector3d(1.0, 0.0, -1.0)));
}

// The yaw uses the original step's length, before scaling: 0.5 m steps at
// 1 rad per metre turn by 0.5 rad each, scaled to 1 m.
TEST(FrontEndDrift, YawFollowsTheOriginalLengthAndTurnsTheScaledStep) {
  const std::vector<Rigid3d> poses = {
      Pose(0.0, Eigen::Vector3d::Zero()),
      Pose(0.0, Eigen::Vector3d(0.0, 0.0, 0.5)),
  };
  const std::vector<Rigid3d> drifted = DriftFrontEnd(poses, 1, {1.0, 2.0});
  ExpectNear(drifted[1],
             Pose(0.5, Eigen::Vector3d(std::sin(0.5), 0.0, std::cos(0.5))));
}

// Stride 2: keyframes 0, 2, 4 carry the drift; frames 1 and 3 follow their
// keyframe rigidly (half a step ahead of it, in its turned camera).
TEST(FrontEndDrift, FramesBetweenKeyframesFollowTheirKeyframe) {
  const double quarter = kPi / 2.0;
  const std::vector<Rigid3d> drifted =
      DriftFrontEnd(StraightLine(5, 2), 2, {quarter, 1.0});
  ASSERT_EQ(drifted.size(), 5u);
  ExpectNear(drifted[1], Pose(0.0, Eigen::Vector3d(0.0, 0.0, 0.5)));
  ExpectNear(drifted[2], Pose(quarter, Eigen::Vector3d(1.0, 0.0, 0.0)));
  ExpectNear(drifted[3], Pose(quarter, Eigen::Vector3d(1.5, 0.0, 0.0)));
  ExpectNear(drifted[4], Pose(kPi, Eigen::Vector3d(1.0, 0.0, -1.0)));
}

// A first pose away from the origin is kept, and a step is scaled in the
// previous camera's frame: a camera turned 90 degrees about y looks along
// world x, so its 1 m step forward, scaled by 1.1, ends 1.1 m further in x.
TEST(FrontEndDrift, FirstKeyframeIsKeptAndStepsAreInTheCameraFrame) {
  const double quarter = kPi / 2.0;
  const Rigid3d start = Pose(quarter, Eigen::Vector3d(2.0, 1.0, 0.0));
  const std::vector<Rigid3d> poses = {
      start, start * Pose(0.0, Eigen::Vector3d(0.0, 0.0, 1.0))};
  const std::vector<Rigid3d> drifted = DriftFrontEnd(poses, 1, {0.0, 1.1});
  ExpectNear(drifted[0], start);
  ExpectNear(drifted[1], Pose(quarter, Eigen::Vector3d(3.1, 1.0, 0.0)));
}

}  // namespace
}  // namespace symba::bench
