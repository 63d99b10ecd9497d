// CompareTrajectories: exact RMSE and maximum, timestamp matching within
// 1e-6 s, and the messages for an unmatched or empty estimate.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace symba
