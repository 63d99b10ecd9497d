// The keyframe graph a loop closure optimises (src/backend/keyframe_graph.h):
// outside the window its chain is the camera motion measured, inside the
// window the estimate, so that a kink the window's solves left in the past
// is spread by a loop instead of kept as a measurement, and a symmetric
// object's detections level the keyframes by its axis.
#include "backend/keyframe_graph.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

namespace symba::internal {
namespace {

// Keyframe k of a turning path: 0.3 rad of yaw and 0.1 rad of roll per
// keyframe, 1 m forward in its own frame each step.
Rigid3d PathPose(int k) {
  Rigid3d T;
  for (int i = 1; i <= k; ++i) {
    const Eigen::Quaterniond turn =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())) *
        Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()));
    T = T * Rigid3d(turn, Eigen::Vector3d(1.0, 0.0, 0.0));
  }
  return Normalized(T);
}

// What a window pulled onto objects seen again while its oldest keyframes
// were held leaves: from keyframe `kink` on, the estimates are moved by
// 0.5 m and 0.2 rad against the path.
const Rigid3d kKink(
    Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())),
    Eigen::Vector3d(0.0, 0.5, 0.0));

// Keyframes along PathPose, measured exactly by odometry (the chain); each
// keyframe's motion factor relates it to the previous one.
KeyframeList KinkedKeyframes(int count, int kink) {
  KeyframeList keyframes;
  for (int k = 0; k < count; ++k) {
    auto kf = std::make_unique<KeyframeState>();
    kf->id = k;
    kf->T_wc_chain = PathPose(k);
    WritePose(k >= kink ? kKink * PathPose(k) : PathPose(k), kf->q, kf->t);
    if (k > 0) {
      kf->motion_variance_t = 0.01 * 0.01;
      kf->motion_variance_r = 0.01 * 0.01;
      kf->motion_from = k - 1;
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
  // T_chain(k-1)^-1 T_chain(k), the kinked step 3 too.
  for (int k = 1; k <= 3; ++k) {
    const ChainStep step = MeasuredStep(keyframes, k, window_begin);
    EXPECT_EQ(step.from, k - 1);
    EXPECT_LT(Distance(step.T, PathPose(k - 1).Inverse() * PathPose(k)), 1e-12)
        << "step " << k;
  }
  // Steps 4 and 5 are inside the window: the estimates' (the same, both
  // ends kinked alike).
  for (int k = 4; k <= 5; ++k) {
    const ChainStep step = MeasuredStep(keyframes, k, window_begin);
    EXPECT_EQ(step.from, k - 1);
    EXPECT_LT(Distance(step.T, PathPose(k - 1).Inverse() * PathPose(k)), 1e-12);
  }
  // With the whole run in the window the kinked step is the estimates'.
  const Rigid3d kinked = PathPose(2).Inverse() * kKink * PathPose(3);
  EXPECT_LT(Distance(MeasuredStep(keyframes, 3, 0).T, kinked), 1e-12);
  EXPECT_LT(Distance(MeasuredStep(keyframes, 3, -4).T, kinked), 1e-12);
  const PoseGraph graph = MakeKeyframeGraph(keyframes, window_begin, {}, {});
  ASSERT_EQ(graph.edges.size(), 5u);
  EXPECT_LT(Distance(graph.edges[2].T_ab, PathPose(2).Inverse() * PathPose(3)),
            1e-12);
}

TEST(KeyframeGraph, AFrontEndStepIsMeasuredFromTheKeyframeItWasPosedAfter) {
  // Keyframe 4's motion factor relates it to keyframe 1, the last the
  // front end posed before 2 and 3 (odometry only): its measured step is
  // from 1, not through 2 and 3.
  KeyframeList keyframes = KinkedKeyframes(5, 5);
  keyframes[4]->motion_from = 1;
  const ChainStep step = MeasuredStep(keyframes, 4, 5);
  EXPECT_EQ(step.from, 1);
  EXPECT_LT(Distance(step.T, PathPose(1).Inverse() * PathPose(4)), 1e-12);
  const PoseGraph graph = MakeKeyframeGraph(keyframes, 5, {}, {});
  ASSERT_EQ(graph.edges.size(), 4u);
  EXPECT_EQ(graph.edges[3].from, 1);
  EXPECT_EQ(graph.edges[3].to, 4);
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
  loop.T = PathPose(9);
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
    EXPECT_LT(Distance(keyframe_poses[k], PathPose(k)), 1e-6) << k;
  }
  // From the estimates (everything in the window) the kink stays in part.
  ASSERT_TRUE(
      OptimizeKeyframeGraph(
          keyframes, 0, {loop}, {}, &keyframe_poses, &object_poses, &summary)
          .ok());
  EXPECT_GT(Distance(keyframe_poses[5], PathPose(5)), 0.1);
}

// An axis edge's measurement turns the predicted relative rotation by the
// least rotation that takes the predicted axis onto the measured one, and
// its information leaves the turn about the axis free.
TEST(KeyframeGraph, AnAxisEdgeMeasuresTheTiltNotTheTurn) {
  const Rigid3d T_wc(Eigen::Quaterniond(Eigen::AngleAxisd(
                         0.7, Eigen::Vector3d(1, 2, 3).normalized())),
                     Eigen::Vector3d(1.0, -2.0, 0.5));
  const Rigid3d T_wo(Eigen::Quaterniond(Eigen::AngleAxisd(
                         -1.1, Eigen::Vector3d(0, 1, 1).normalized())),
                     Eigen::Vector3d(3.0, 1.0, 0.0));
  const Eigen::Vector3d axis_w = Eigen::Vector3d(0.1, 0.0, 1.0).normalized();
  const Eigen::Vector3d predicted = T_wc.q.inverse() * axis_w;
  // 0.05 rad off, about a direction perpendicular to the predicted axis.
  const Eigen::Vector3d off =
      predicted.cross(Eigen::Vector3d::UnitX()).normalized();
  const Eigen::Vector3d axis_c = Eigen::AngleAxisd(0.05, off) * predicted;
  const Eigen::Vector3d t_co(0.2, 0.1, 3.0);
  const Rigid3d M = AxisEdgeMeasurement(T_wc, T_wo, axis_w, axis_c, t_co);
  const Eigen::Vector3d a_o = T_wo.q.inverse() * axis_w;
  EXPECT_LT((M.q * a_o - axis_c).norm(), 1e-12);
  const Eigen::Quaterniond q_co = T_wc.q.inverse() * T_wo.q;
  EXPECT_NEAR(M.q.angularDistance(q_co), 0.05, 1e-12);
  EXPECT_EQ((M.t - t_co).norm(), 0.0);

  const Eigen::Matrix3d L = AxisInformation(a_o, 400.0);
  EXPECT_NEAR(a_o.dot(L * a_o), kAxisTurnInformation, 1e-12);
  const Eigen::Vector3d u = a_o.unitOrthogonal();
  const Eigen::Vector3d v = a_o.cross(u);
  EXPECT_NEAR(u.dot(L * u), 400.0, 1e-9);
  EXPECT_NEAR(v.dot(L * v), 400.0, 1e-9);
  EXPECT_NEAR(u.dot(L * v), 0.0, 1e-9);
  EXPECT_LT((L - L.transpose()).norm(), 1e-12);
}

// Twenty keyframes of a camera (z forward, y down) on a level path whose
// motion measured a roll of 0.02 rad per step (loosely: 0.1 rad), around a
// turned round table (its axis is the object frame's y) whose axis they
// measured exactly (0.01 rad) and whose position they measured loosely
// (1 m). With the axes in the graph (16 edges spread over the 20
// detections) each keyframe's tilt is the table's; without them it is the
// motion's.
TEST(KeyframeGraph, ASymmetricObjectsAxisLevelsTheKeyframesThatSawIt) {
  constexpr int kCount = 20;
  const Eigen::Quaterniond camera_to_level(
      Eigen::AngleAxisd(-0.5 * M_PI, Eigen::Vector3d::UnitX()));
  auto level_pose = [&](int k) {
    return Rigid3d(
        Eigen::Quaterniond(
            Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d::UnitZ())) *
            camera_to_level,
        Eigen::Vector3d(0.5 * std::cos(0.3 * k), 0.5 * std::sin(0.3 * k), 1.5));
  };
  const Eigen::Quaterniond roll(
      Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitZ()));  // about z_c
  KeyframeList keyframes;
  Rigid3d chain = level_pose(0);
  for (int k = 0; k < kCount; ++k) {
    auto kf = std::make_unique<KeyframeState>();
    kf->id = k;
    if (k > 0) {
      const Rigid3d step = level_pose(k - 1).Inverse() * level_pose(k);
      chain = chain * Rigid3d(step.q * roll, step.t);
      kf->motion_variance_t = 0.01 * 0.01;
      kf->motion_variance_r = 0.1 * 0.1;
      kf->motion_from = k - 1;
    }
    kf->T_wc_chain = Normalized(chain);
    WritePose(kf->T_wc_chain, kf->q, kf->t);
    keyframes.push_back(std::move(kf));
  }
  // The table's frame is turned so that its y axis is the world's up.
  const Rigid3d T_wo(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())) *
          Eigen::Quaterniond(
              Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitX())),
      Eigen::Vector3d(3.0, 2.0, 0.4));
  ASSERT_LT(
      (T_wo.q * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(),
      1e-12);
  GraphObject table;
  table.T_wo = T_wo;
  table.sigma_t = 1.0;
  table.sigma_r = 0.1;
  table.axis_w = Eigen::Vector3d::UnitZ();
  table.sigma_axis = 0.01;
  for (int k = 0; k < kCount; ++k) {
    table.keyframes.push_back(k);
    table.measured.push_back(level_pose(k).Inverse() * T_wo);
    table.measured_axes.push_back(level_pose(k).q.inverse() *
                                  Eigen::Vector3d::UnitZ());
  }
  ASSERT_TRUE(table.HasAxis());
  // Up in the camera is -y: the measured axes differ from keyframe to
  // keyframe only by the camera's tilt, here none.
  auto tilt_error = [&](const std::vector<Rigid3d>& poses, int k) {
    const Eigen::Vector3d up_estimated =
        poses[k].q.inverse() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up_true =
        level_pose(k).q.inverse() * Eigen::Vector3d::UnitZ();
    return std::acos(std::min(1.0, up_estimated.dot(up_true)));
  };
  std::vector<Rigid3d> keyframe_poses;
  std::vector<Rigid3d> object_poses;
  PoseGraphSolveSummary summary;
  ASSERT_TRUE(OptimizeKeyframeGraph(keyframes,
                                    kCount,
                                    {},
                                    {table},
                                    &keyframe_poses,
                                    &object_poses,
                                    &summary)
                  .ok());
  for (int k = 1; k < kCount; ++k) {
    EXPECT_LT(tilt_error(keyframe_poses, k), 0.005) << k;
  }
  // The table's vertex keeps its axis up.
  EXPECT_LT(
      (object_poses[0].q * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ())
          .norm(),
      0.005);
  GraphObject without_axis = table;
  without_axis.measured_axes.clear();
  ASSERT_FALSE(without_axis.HasAxis());
  ASSERT_TRUE(OptimizeKeyframeGraph(keyframes,
                                    kCount,
                                    {},
                                    {without_axis},
                                    &keyframe_poses,
                                    &object_poses,
                                    &summary)
                  .ok());
  double worst = 0.0;
  for (int k = 1; k < kCount; ++k) {
    worst = std::max(worst, tilt_error(keyframe_poses, k));
  }
  EXPECT_GT(worst, 0.05);
}

TEST(KeyframeGraph, EachEdgesRoleInTheCovariancesNoise) {
  // Six keyframes, the window from keyframe 4; keyframes 1-3 shared
  // kMinSharedPoints map points with their predecessors, keyframe 5 too
  // (inside the window), keyframe 2 stated wider; a loop 0 -> 5; three
  // objects: one of 12 views with a declared noise, one of 3, one of 12
  // weighed with the class's estimate (noise not stated).
  KeyframeList keyframes = KinkedKeyframes(6, 6);
  for (int k : {1, 2, 3, 5}) {
    keyframes[k]->points_shared_with_previous = kMinSharedPoints;
  }
  keyframes[4]->points_shared_with_previous = kMinSharedPoints - 1;
  keyframes[2]->motion_variance_t = 0.05 * 0.05;
  LoopConstraint loop{0,
                      5,
                      ReadPose(keyframes[0]->q, keyframes[0]->t).Inverse() *
                          ReadPose(keyframes[5]->q, keyframes[5]->t),
                      0.1,
                      0.1};
  auto object = [&](const char* name, int views, bool stated) {
    GraphObject g;
    g.T_wo = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 5));
    g.rotation = true;
    g.sigma_t = 0.05;
    g.sigma_r = 0.1;
    g.class_name = name;
    g.noise_stated = stated;
    for (int v = 0; v < views; ++v) {
      g.keyframes.push_back(v % 6);
      g.measured.push_back(
          ReadPose(keyframes[v % 6]->q, keyframes[v % 6]->t).Inverse() *
          g.T_wo);
    }
    return g;
  };
  const std::vector<GraphObject> objects = {object("chair", 12, true),
                                            object("table", 3, true),
                                            object("can", 12, false)};
  std::vector<GraphEdgeRole> roles;
  const PoseGraph graph =
      MakeKeyframeGraph(keyframes, 4, {loop}, objects, &roles);
  ASSERT_EQ(roles.size(), graph.edges.size());
  ASSERT_EQ(roles.size(), 5u + 1u + 12u + 3u + 12u);
  const std::string rich = "motion 0.01 m 0.01 rad";
  EXPECT_EQ(roles[0].group, rich + ", shared points");  // keyframe 1
  EXPECT_TRUE(roles[0].held_by_others);
  EXPECT_EQ(roles[0].previous, -1);
  EXPECT_EQ(roles[1].group, "motion 0.05 m 0.01 rad, shared points");
  EXPECT_EQ(roles[2].group, rich + ", shared points");
  EXPECT_EQ(roles[2].previous, 1);
  EXPECT_EQ(roles[3].group, rich + ", no shared points");  // keyframe 4
  EXPECT_FALSE(roles[3].held_by_others);
  EXPECT_TRUE(roles[3].measured);
  EXPECT_EQ(roles[3].previous, 2);
  EXPECT_FALSE(roles[4].measured);      // 4 -> 5: the window's estimate
  EXPECT_TRUE(roles[5].group.empty());  // the loop
  EXPECT_EQ(roles[6].group, "detections chair");
  EXPECT_TRUE(roles[6].held_by_others);
  EXPECT_EQ(roles[6].previous, -1);
  EXPECT_EQ(roles[7].previous, 6);
  EXPECT_DOUBLE_EQ(roles[6].weight, 1.0);
  EXPECT_EQ(roles[6].rotation_dof, 3);
  EXPECT_EQ(roles[18].group, "detections table, few views");
  EXPECT_FALSE(roles[18].held_by_others);
  EXPECT_EQ(roles[21].group, "detections can, unstated noise");
  EXPECT_FALSE(roles[21].held_by_others);
  EXPECT_EQ(roles[21].previous, -1);
}

}  // namespace
}  // namespace symba::internal
