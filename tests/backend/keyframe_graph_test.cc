// The keyframe graph a loop closure optimises (src/backend/keyframe_graph.h):
// outside the window its chain is the camera motion measured, inside the
// window the estimate, so that a kink the window's solves left in the past
// is spread by a loop instead of kept as a measurement.
#include "backend/keyframe_graph.h"

#include <memory>
#include <vector>

#include <gtest/gtest.h>

namespace symba::internal {
namespace {

Rigid3d PoseAt(double x, double y) {
  return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, y, 0.0));
}

// Keyframes 1 m apart along x, measured exactly by the camera motion (the
// chain), whose estimates from keyframe `kink` on are 0.5 m off in y: what
// is left when a window pulled onto objects seen again while its oldest
// keyframes were held.
KeyframeList KinkedKeyframes(int count, int kink) {
  KeyframeList keyframes;
  for (int k = 0; k < count; ++k) {
    auto kf = std::make_unique<KeyframeState>();
    kf->id = k;
    kf->T_wc_chain = PoseAt(k, 0.0);
    WritePose(PoseAt(k, k >= kink ? 0.5 : 0.0), kf->q, kf->t);
    if (k > 0) {
      kf->motion_variance_t = 0.01 * 0.01;
      kf->motion_variance_r = 0.01 * 0.01;
    }
    keyframes.push_back(std::move(kf));
  }
  return keyframes;
}

double Distance(const Rigid3d& a, const Rigid3d& b) {
  return (a.t - b.t).norm() + a.q.angularDistance(b.q);
}

TEST(KeyframeGraph, OutsideTheWindowAStepIsTheMeasuredMotion) {
  const KeyframeList keyframes = KinkedKeyframes(6, 3);
  const int window_begin = 3;
  // Steps 1-3 end at or before the window's first keyframe: the chain's
  // 1 m along x, the kinked step 3 too.
  for (int k = 1; k <= 3; ++k) {
    EXPECT_LT(Distance(ChainStep(keyframes, k, window_begin), PoseAt(1.0, 0.0)),
              1e-12)
        << "step " << k;
  }
  // Steps 4 and 5 are inside the window: the estimate's (also 1 m along x,
  // both ends kinked alike).
  for (int k = 4; k <= 5; ++k) {
    EXPECT_LT(Distance(ChainStep(keyframes, k, window_begin), PoseAt(1.0, 0.0)),
              1e-12);
  }
  // With the whole run in the window, the kinked step is the estimate's.
  EXPECT_LT(Distance(ChainStep(keyframes, 3, 0), PoseAt(1.0, 0.5)), 1e-12);
  const PoseGraph graph = MakeKeyframeGraph(keyframes, window_begin, {}, {});
  ASSERT_EQ(graph.edges.size(), 5u);
  EXPECT_LT(Distance(graph.edges[2].T_ab, PoseAt(1.0, 0.0)), 1e-12);
}

TEST(KeyframeGraph, ALoopSpreadsAKinkLeftOutsideTheWindow) {
  // A loop from keyframe 0 to keyframe 9 says where 9 truly is. The chain
  // agrees with it, so the optimised past is the truth: the kink at step
  // 5, outside the window (8, 9), is gone. Taken from the estimates, the
  // step would hold the kink against the loop.
  const KeyframeList keyframes = KinkedKeyframes(10, 5);
  LoopConstraint loop;
  loop.earlier = 0;
  loop.later = 9;
  loop.T = PoseAt(9.0, 0.0);
  loop.sigma_t = 0.01;
  loop.sigma_r = 0.01;
  std::vector<Rigid3d> keyframe_poses;
  std::vector<Rigid3d> object_poses;
  PoseGraphSolveSummary summary;
  ASSERT_TRUE(
      OptimizeKeyframeGraph(
          keyframes, 8, {loop}, {}, &keyframe_poses, &object_poses, &summary)
          .ok());
  for (int k = 0; k < 10; ++k) {
    EXPECT_LT(Distance(keyframe_poses[k], PoseAt(k, 0.0)), 1e-6) << k;
  }
  // From the estimates (everything in the window) the kink stays in part.
  ASSERT_TRUE(
      OptimizeKeyframeGraph(
          keyframes, 0, {loop}, {}, &keyframe_poses, &object_poses, &summary)
          .ok());
  EXPECT_GT(Distance(keyframe_poses[5], PoseAt(5.0, 0.0)), 0.1);
}

}  // namespace
}  // namespace symba::internal
