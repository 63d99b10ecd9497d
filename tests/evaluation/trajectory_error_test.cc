// CompareTrajectories: exact RMSE and maximum, timestamp matching within
// 1e-6 s, and the messages for an unmatched or empty estimate.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "symba/evaluation/trajectory_error.h"

namespace symba {
namespace {

TrajectoryPose At(double timestamp, double x, double y, double z) {
  TrajectoryPose pose;
  pose.timestamp = timestamp;
  pose.T_wc.t = Eigen::Vector3d(x, y, z);
  return pose;
}

TEST(CompareTrajectories, RmseAndMaxOverTheEstimatedPoses) {
  // The reference has an extra pose (0.1) that no estimate asks for.
  const std::vector<TrajectoryPose> reference = {
      At(0.0, 0, 0, 0), At(0.1, 9, 9, 9), At(0.2, 1, 0, 0), At(0.3, 0, 0, 0)};
  // Errors 0, 3 (0.2000005 matches 0.2) and 4: RMSE sqrt(25 / 3).
  const std::vector<TrajectoryPose> estimate = {
      At(0.0, 0, 0, 0), At(0.2000005, 1, 3, 0), At(0.3, 0, 0, 4)};
  TrajectoryError error;
  const Status status =
      CompareTrajectories(estimate, "est", reference, "ref", &error);
  ASSERT_TRUE(status.ok()) << status.message();
  EXPECT_EQ(error.poses, 3);
  EXPECT_DOUBLE_EQ(error.position_rmse, std::sqrt(25.0 / 3.0));
  EXPECT_EQ(error.max_position_error, 4.0);
}

TEST(CompareTrajectories, UnmatchedAndEmptyEstimates) {
  const std::vector<TrajectoryPose> reference = {At(0.0, 0, 0, 0),
                                                 At(0.2, 1, 0, 0)};
  TrajectoryError error;
  EXPECT_EQ(CompareTrajectories(
                {At(0.2000011, 0, 0, 0)}, "est", reference, "ref", &error)
                .message(),
            "est: pose at timestamp 0.2000011: no pose of ref at that time");
  EXPECT_EQ(
      CompareTrajectories({At(0.5, 0, 0, 0)}, "est", reference, "ref", &error)
          .message(),
      "est: pose at timestamp 0.5: no pose of ref at that time");
  EXPECT_EQ(CompareTrajectories({}, "est", reference, "ref", &error).message(),
            "est: no poses");
}

// EvaluateTrajectory: association by nearest time, each alignment, RPE.
namespace evaluate_trajectory {

// A reference at 100 Hz along x with a turn about z; an estimate made of
// every tenth pose moved by a known transform.
std::vector<TrajectoryPose> Reference() {
  std::vector<TrajectoryPose> poses;
  for (int i = 0; i <= 100; ++i) {
    TrajectoryPose pose = At(0.01 * i, 0.02 * i, 0.001 * i * i, 0.5);
    pose.T_wc.q = Eigen::Quaterniond(
        Eigen::AngleAxisd(0.01 * i, Eigen::Vector3d::UnitZ()));
    poses.push_back(pose);
  }
  return poses;
}

std::vector<TrajectoryPose> Moved(const std::vector<TrajectoryPose>& poses,
                                  const Rigid3d& T,
                                  double scale,
                                  double time_offset) {
  std::vector<TrajectoryPose> moved;
  for (std::size_t i = 0; i < poses.size(); i += 10) {
    TrajectoryPose pose = poses[i];
    pose.timestamp += time_offset;
    pose.T_wc.t = scale * (T.q * pose.T_wc.t) + T.t;
    pose.T_wc.q = T.q * pose.T_wc.q;
    moved.push_back(pose);
  }
  return moved;
}

Rigid3d SomeTransform() {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(
                     0.7, Eigen::Vector3d(1, 2, 3).normalized())),
                 Eigen::Vector3d(3, -1, 2));
}

TrajectoryEvaluation Evaluate(const std::vector<TrajectoryPose>& estimate,
                              TrajectoryAlignment alignment,
                              double tolerance = 0.02) {
  TrajectoryEvaluationOptions options;
  options.alignment = alignment;
  options.time_tolerance = tolerance;
  TrajectoryEvaluation e;
  const Status status =
      EvaluateTrajectory(estimate, "est", Reference(), "ref", options, &e);
  EXPECT_TRUE(status.ok()) << status.message();
  return e;
}

TEST(EvaluateTrajectory, NoAlignmentMeasuresAnOffsetAsItIs) {
  const Rigid3d shift(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 3, 4));
  const TrajectoryEvaluation e =
      Evaluate(Moved(Reference(), shift, 1.0, 0.0), TrajectoryAlignment::kNone);
  EXPECT_EQ(e.poses, 11);
  EXPECT_EQ(e.matched, 11);
  EXPECT_DOUBLE_EQ(e.ate.position_rmse, 5.0);
  EXPECT_DOUBLE_EQ(e.ate.max_position_error, 5.0);
  EXPECT_EQ(e.rotation_rmse_deg, 0.0);
  EXPECT_EQ(e.rpe_pairs, 10);
  EXPECT_NEAR(e.rpe_translation_rmse, 0.0, 1e-12);
}

TEST(EvaluateTrajectory, EachAlignmentUndoesWhatItModels) {
  const std::vector<TrajectoryPose> rigid =
      Moved(Reference(), SomeTransform(), 1.0, 0.0);
  for (TrajectoryAlignment a : {TrajectoryAlignment::kFirst,
                                TrajectoryAlignment::kSe3,
                                TrajectoryAlignment::kSim3}) {
    const TrajectoryEvaluation e = Evaluate(rigid, a);
    EXPECT_NEAR(e.ate.position_rmse, 0.0, 1e-9) << TrajectoryAlignmentName(a);
    EXPECT_NEAR(e.rotation_rmse_deg, 0.0, 1e-6) << TrajectoryAlignmentName(a);
    EXPECT_NEAR(e.scale, 1.0, 1e-9) << TrajectoryAlignmentName(a);
  }
  const TrajectoryEvaluation sim3 =
      Evaluate(Moved(Reference(), SomeTransform(), 2.5, 0.0),
               TrajectoryAlignment::kSim3);
  EXPECT_NEAR(sim3.scale, 0.4, 1e-9);
  EXPECT_NEAR(sim3.ate.position_rmse, 0.0, 1e-9);
  // A scaled estimate keeps an error under se3.
  const TrajectoryEvaluation se3 = Evaluate(
      Moved(Reference(), SomeTransform(), 2.5, 0.0), TrajectoryAlignment::kSe3);
  EXPECT_GT(se3.ate.position_rmse, 0.1);
}

TEST(EvaluateTrajectory, RelativePoseErrorOfAStretchedEstimate) {
  // Positions 10 % too long: each keyframe step (0.2 m along x plus the
  // parabola's y) is 10 % too long; the rotations are right.
  const Rigid3d identity;
  const TrajectoryEvaluation e = Evaluate(
      Moved(Reference(), identity, 1.1, 0.0), TrajectoryAlignment::kNone);
  double sum = 0.0;
  const std::vector<TrajectoryPose> ref = Reference();
  for (int k = 0; k + 10 <= 100; k += 10) {
    const Rigid3d d = ref[k].T_wc.Inverse() * ref[k + 10].T_wc;
    sum += (0.1 * d.t).squaredNorm();
  }
  EXPECT_EQ(e.rpe_pairs, 10);
  EXPECT_NEAR(e.rpe_translation_rmse, std::sqrt(sum / 10.0), 1e-12);
  EXPECT_NEAR(e.rpe_rotation_rmse_deg, 0.0, 1e-9);
}

TEST(EvaluateTrajectory, NearestReferenceWithinTheTolerance) {
  // 4 ms late: the reference at 100 Hz has its nearest pose 4 ms away.
  const Rigid3d identity;
  const std::vector<TrajectoryPose> late =
      Moved(Reference(), identity, 1.0, 0.004);
  const TrajectoryEvaluation e = Evaluate(late, TrajectoryAlignment::kNone);
  EXPECT_EQ(e.matched, 11);
  EXPECT_NEAR(e.ate.position_rmse, 0.0, 1e-12);
  const TrajectoryEvaluation strict =
      Evaluate(late, TrajectoryAlignment::kNone, 0.005);
  EXPECT_EQ(strict.matched, 11);
  TrajectoryEvaluationOptions options;
  options.time_tolerance = 0.001;
  TrajectoryEvaluation none;
  EXPECT_EQ(EvaluateTrajectory(late, "est", Reference(), "ref", options, &none)
                .message(),
            "est: no pose within 0.001 s of a pose of ref");
  // One estimate beyond the reference's end is counted, not matched.
  std::vector<TrajectoryPose> longer = late;
  longer.push_back(At(1.5, 0, 0, 0));
  EXPECT_EQ(Evaluate(longer, TrajectoryAlignment::kNone).matched, 11);
  EXPECT_EQ(Evaluate(longer, TrajectoryAlignment::kNone).poses, 12);
}

TEST(EvaluateTrajectory, Errors) {
  TrajectoryEvaluationOptions options;
  options.alignment = TrajectoryAlignment::kSe3;
  TrajectoryEvaluation e;
  const std::vector<TrajectoryPose> two = {At(0.0, 0, 0, 0), At(0.5, 1, 0, 0)};
  EXPECT_EQ(
      EvaluateTrajectory(two, "est", Reference(), "ref", options, &e).message(),
      "se3 alignment needs at least 3 matched poses, est has 2");
  EXPECT_EQ(
      EvaluateTrajectory({}, "est", Reference(), "ref", options, &e).message(),
      "est: no poses");
  const std::vector<TrajectoryPose> still = {
      At(0.0, 1, 1, 1), At(0.5, 1, 1, 1), At(1.0, 1, 1, 1)};
  options.alignment = TrajectoryAlignment::kSim3;
  EXPECT_EQ(EvaluateTrajectory(still, "est", Reference(), "ref", options, &e)
                .message(),
            "sim3 alignment: the matched positions of est do not determine a "
            "transform (all in one place)");
  options.alignment = TrajectoryAlignment::kSe3;
  options.time_tolerance = -1.0;
  EXPECT_EQ(
      EvaluateTrajectory(two, "est", Reference(), "ref", options, &e).message(),
      "time tolerance: must be finite and not negative, got -1");
}

TEST(EvaluateTrajectory, AlignmentNames) {
  TrajectoryAlignment a = TrajectoryAlignment::kNone;
  for (const char* name : {"none", "first", "se3", "sim3"}) {
    ASSERT_TRUE(ParseTrajectoryAlignment(name, &a));
    EXPECT_STREQ(TrajectoryAlignmentName(a), name);
  }
  EXPECT_FALSE(ParseTrajectoryAlignment("umeyama", &a));
}

}  // namespace evaluate_trajectory
}  // namespace
}  // namespace symba
