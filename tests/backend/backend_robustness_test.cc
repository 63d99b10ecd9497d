// The backend against a real detector's failure modes (docs/backend.md
// "Real detectors"), and the window mechanics, through the public API:
//   - a gross outlier detection leaves the map and the cameras unchanged;
//   - a new object is tentative until confirmed, and dropped with its
//     detections (object -1) if it is not;
//   - the window: keyframes before it stay bit-identical, exactly the
//     factors of the window's keyframes and of what they observe are in the
//     problem, and an object seen again brings its old edges back.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/backend/backend.h"
#include "symba/geometry/angle.h"
#include "test_support/backend_replay.h"
#include "test_support/scripted_sequence.h"

namespace symba {
namespace {

using testing::GenerateScriptedSequence;
using testing::ScriptedObject;
using testing::ScriptedSequence;
using testing::ScriptedSequenceSpec;

// A chair seen from a loop of 24 keyframes by a calibrated detector (it
// reports its noise, so nothing depends on the noise estimate).
ScriptedSequence ChairSequence() {
  ScriptedObject chair;
  chair.class_name = "chair";
  chair.symmetry = SymmetryType::kAsymmetric;
  chair.T_wo =
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.1, -0.05, 0.0));
  ScriptedSequenceSpec spec;
  spec.objects = {chair};
  spec.num_keyframes = 24;
  spec.detection_sigma_t = 0.03;
  spec.detection_sigma_r = 0.05;
  spec.seed = 11;
  return GenerateScriptedSequence(spec);
}

struct RunResult {
  std::vector<KeyframeEstimate> keyframes;
  std::vector<MapObjectEstimate> objects;
  std::vector<DetectionAssignment> assignments;
  BackendStatistics statistics;
};

RunResult Replay(const std::vector<KeyframeInput>& keyframes,
                 const BackendOptions& options,
                 const std::optional<PinholeIntrinsics>& intrinsics) {
  std::unique_ptr<Backend> backend;
  testing::ReplayWindowed(keyframes, options, intrinsics, &backend);
  if (backend == nullptr) return {};
  return {backend->Keyframes(),
          backend->Objects(),
          backend->Assignments(),
          backend->Statistics()};
}

// A copy of `detection` whose every hypothesis is moved by T_co * delta.
DetectionInput Moved(DetectionInput detection,
                     const std::string& id,
                     const Rigid3d& delta) {
  detection.id = id;
  for (PoseHypothesis& h : detection.hypotheses) h.T_co = h.T_co * delta;
  return detection;
}

// Gross outliers: one detection 1.5 m off (a new tentative object that is
// never confirmed) and one at the right place turned 180 deg about an axis
// of the chair (symba: a single flip, no edge; sh, mh: a tentative object).
// Neither may move a camera or the chair.
TEST(BackendRobustness, GrossOutliersLeaveMapAndCamerasUnchanged) {
  const ScriptedSequence seq = ChairSequence();
  std::vector<KeyframeInput> with_outliers = seq.keyframes;
  const DetectionInput& at_7 = seq.keyframes[7].detections.front();
  with_outliers[7].detections.push_back(Moved(
      at_7,
      "outlier-far",
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1.5, 0.0, 0.0))));
  const DetectionInput& at_9 = seq.keyframes[9].detections.front();
  with_outliers[9].detections = {Moved(
      at_9,
      "outlier-flip",
      Rigid3d(
          Eigen::Quaterniond(Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX())),
          Eigen::Vector3d::Zero()))};

#ifdef SYMBA_SANITIZED
  // Two replays per method take 45 s under ASan + UBSan; mh's and sh's
  // detections run there in BackendSequences.*ForEveryMethod.
  const std::vector<Method> methods = {Method::kSymba};
#else
  const std::vector<Method> methods = {
      Method::kSymba, Method::kMultiHypothesis, Method::kSingleHypothesis};
#endif
  for (Method method : methods) {
    SCOPED_TRACE(MethodName(method));
    BackendOptions options;
    options.method = method;
    // Without the flipped detection at keyframe 9 at all: the clean run.
    std::vector<KeyframeInput> clean = seq.keyframes;
    clean[9].detections.clear();
    const RunResult a = Replay(clean, options, seq.intrinsics);
    const RunResult b = Replay(with_outliers, options, seq.intrinsics);
    ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
    for (size_t k = 0; k < a.keyframes.size(); ++k) {
      EXPECT_LT((a.keyframes[k].T_wc.t - b.keyframes[k].T_wc.t).norm(), 1e-9)
          << k;
      EXPECT_LT(a.keyframes[k].T_wc.q.angularDistance(b.keyframes[k].T_wc.q),
                1e-9)
          << k;
    }
    ASSERT_EQ(a.objects.size(), 1u);
    ASSERT_EQ(b.objects.size(), 1u);
    EXPECT_LT((a.objects[0].t_wo - b.objects[0].t_wo).norm(), 1e-9);
    EXPECT_EQ(b.statistics.object_upgrades, 0);
    // The far outlier's tentative object was dropped: its detection is in
    // no map object.
    for (const DetectionAssignment& assignment : b.assignments) {
      if (assignment.detection == "outlier-far") {
        EXPECT_EQ(assignment.object, -1);
      }
      if (assignment.detection == "outlier-flip") {
        // symba: joined the chair without an edge; sh, mh: dropped.
        EXPECT_EQ(assignment.object,
                  method == Method::kSymba ? b.objects[0].id : -1);
      }
    }
    EXPECT_EQ(b.statistics.objects_dropped, method == Method::kSymba ? 1 : 2);
    EXPECT_EQ(b.statistics.rotation_outliers, method == Method::kSymba ? 1 : 0);
  }
}

// Hand-made keyframes for the lifecycle and window tests: camera k at
// x = 0.1 k looking along z with odometry between keyframes; `detections`
// lists which keyframes see a "box" at (0.2, 0, 2) (its pose slightly off,
// so a solve has something to do).
std::vector<KeyframeInput> BoxKeyframes(int n,
                                        const std::vector<int>& seen,
                                        double step = 0.1) {
  std::vector<KeyframeInput> keyframes;
  const Rigid3d T_wo(Eigen::Quaterniond::Identity(),
                     Eigen::Vector3d(0.2, 0.0, 2.0));
  for (int k = 0; k < n; ++k) {
    KeyframeInput kf;
    kf.id = k;
    kf.timestamp = 0.1 * k;
    const Rigid3d T_wc(Eigen::Quaterniond::Identity(),
                       Eigen::Vector3d(step * k, 0.0, 0.0));
    if (k == 0) {
      kf.T_wc = T_wc;
    } else {
      Odometry odometry;
      odometry.T_prev_cur =
          Rigid3d(Eigen::Quaterniond(
                      Eigen::AngleAxisd(0.002, Eigen::Vector3d::UnitY())),
                  Eigen::Vector3d(step, 0.001 * (k % 3), 0.0));
      odometry.sigma_t = 0.01;
      odometry.sigma_r = 0.01;
      kf.odometry = odometry;
    }
    for (int s : seen) {
      if (s != k) continue;
      DetectionInput det;
      det.id = std::to_string(k) + "/box";
      det.class_name = "box";
      det.sigma_t = 0.02;
      det.sigma_r = 0.05;
      const Rigid3d offset(Eigen::Quaterniond(Eigen::AngleAxisd(
                               0.01 * k, Eigen::Vector3d::UnitZ())),
                           Eigen::Vector3d(0.005 * (k % 2), 0.0, 0.0));
      det.hypotheses.push_back({T_wc.Inverse() * T_wo * offset, 1.0});
      kf.detections.push_back(det);
    }
    keyframes.push_back(kf);
  }
  return keyframes;
}

// A map point seen again behind the camera's initial pose (a front end that
// jumped, a point moved by a loop closure) cannot be projected: the
// observation is left out and counted, and the solve goes on.
TEST(BackendRobustness, APointBehindTheCameraIsLeftOutAndCounted) {
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(BackendOptions(),
                              PinholeIntrinsics{500.0, 500.0, 320.0, 240.0},
                              {},
                              &backend)
                  .ok());
  KeyframeInput first;
  first.id = 0;
  first.T_wc = Rigid3d();
  first.points = {{1, Eigen::Vector2d(320.0, 240.0), 2.0},
                  {2, Eigen::Vector2d(300.0, 200.0), 3.0}};
  ASSERT_TRUE(backend->AddKeyframe(first).ok());
  ASSERT_TRUE(backend->OptimizeWindow().ok());
  // Turned around: both points are behind; point 2 is seen from in front
  // again after a step back.
  KeyframeInput turned;
  turned.id = 1;
  turned.timestamp = 1.0;
  turned.T_wc = Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d::Zero());
  turned.points = {{1, Eigen::Vector2d(320.0, 240.0), std::nullopt}};
  ASSERT_TRUE(backend->AddKeyframe(turned).ok());
  EXPECT_EQ(backend->Statistics().point_observations_behind, 1);
  const Status status = backend->OptimizeWindow();
  EXPECT_TRUE(status.ok()) << status.message();
  KeyframeInput back;
  back.id = 2;
  back.timestamp = 2.0;
  back.T_wc =
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, -1.0));
  back.points = {{2, Eigen::Vector2d(305.0, 210.0), std::nullopt}};
  ASSERT_TRUE(backend->AddKeyframe(back).ok());
  EXPECT_EQ(backend->Statistics().point_observations_behind, 1);
  EXPECT_TRUE(backend->OptimizeWindow().ok());
}

TEST(BackendRobustness, TentativeObjectsAreConfirmedOrDropped) {
  BackendOptions options;
  options.confirm_keyframes = 3;
  options.tentative_timeout = 4;
  for (Method method : {Method::kSymba, Method::kSingleHypothesis}) {
    SCOPED_TRACE(MethodName(method));
    options.method = method;
    // Seen at 0, 1 (not enough), then not for 4 keyframes: dropped at 5.
    std::unique_ptr<Backend> backend;
    ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
    const std::vector<KeyframeInput> dropped = BoxKeyframes(8, {0, 1});
    for (int k = 0; k < 8; ++k) {
      ASSERT_TRUE(backend->AddKeyframe(dropped[k]).ok());
      ASSERT_TRUE(backend->OptimizeWindow().ok());
      EXPECT_TRUE(backend->Objects().empty()) << k;
      EXPECT_EQ(backend->Statistics().objects_dropped, k >= 5 ? 1 : 0) << k;
      EXPECT_EQ(backend->Assignments()[0].object, k >= 5 ? -1 : 0) << k;
    }
    EXPECT_EQ(backend->Statistics().objects, 0);

    // Seen at 0, 2, 4: confirmed by the third view, with all three.
    ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
    const std::vector<KeyframeInput> confirmed = BoxKeyframes(6, {0, 2, 4});
    for (int k = 0; k < 6; ++k) {
      ASSERT_TRUE(backend->AddKeyframe(confirmed[k]).ok());
      ASSERT_TRUE(backend->OptimizeWindow().ok());
      EXPECT_EQ(backend->Objects().size(), k >= 4 ? 1u : 0u) << k;
    }
    EXPECT_EQ(backend->Objects()[0].observations, 3);
    EXPECT_EQ(backend->Statistics().objects, 1);
    EXPECT_EQ(backend->Statistics().objects_dropped, 0);
  }
}

// An object confirmed by keyframes 0-4 of a camera that then stays put and
// keeps the object in view, but never detects it again: after
// min_support_views (20) views since its confirmation at keyframe 2 it was
// detected in 3 of them, under min_support (20 %) from 16 views on, so it is
// dropped at the 20th view, keyframe 21, with its detections.
TEST(BackendRobustness, AnObjectNoLongerDetectedInViewIsDropped) {
  BackendOptions options;
  options.confirm_keyframes = 3;
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
  const std::vector<KeyframeInput> keyframes =
      BoxKeyframes(24, {0, 1, 2, 3, 4}, 0.0);
  for (int k = 0; k < 24; ++k) {
    ASSERT_TRUE(backend->AddKeyframe(keyframes[k]).ok());
    ASSERT_TRUE(backend->OptimizeWindow().ok());
    EXPECT_EQ(backend->Objects().size(), k >= 2 && k < 21 ? 1u : 0u) << k;
  }
  EXPECT_EQ(backend->Statistics().objects_dropped, 1);
  EXPECT_EQ(backend->Statistics().objects, 0);
  for (const DetectionAssignment& a : backend->Assignments()) {
    EXPECT_EQ(a.object, -1) << a.detection;
  }
  // With min_support 0 it stays.
  options.min_support = 0.0;
  ASSERT_NO_FATAL_FAILURE(
      testing::ReplayWindowed(keyframes, options, std::nullopt, &backend));
  EXPECT_EQ(backend->Objects().size(), 1u);
}

// Keyframes before a window of `window` ending at keyframe k (and the gauge,
// keyframe 0) are bit-identical before and after a window solve.
void ExpectOutsideWindowUnchanged(const std::vector<KeyframeEstimate>& before,
                                  const std::vector<KeyframeEstimate>& after,
                                  int k,
                                  int window) {
  for (int j = 0; j < k + 1; ++j) {
    if (j > 0 && j > k - window) continue;
    EXPECT_EQ(before[j].T_wc.t, after[j].T_wc.t) << k << " " << j;
    EXPECT_EQ(before[j].T_wc.q.coeffs(), after[j].T_wc.q.coeffs())
        << k << " " << j;
  }
}

// marginalize: keyframes that left the window never move again; the window
// holds its own factors and the priors only; the box seen again at keyframe
// 9, long after keyframe 0 was marginalised, is the same object.
TEST(BackendWindow, MarginalizeKeepsTheWindowAndThePriorsOnly) {
  BackendOptions options;
  options.window_size = 3;
  options.confirm_keyframes = 1;
  options.window_policy = WindowPolicy::kMarginalize;
  options.keep_history = true;  // for the batch solve at the end
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
  const std::vector<KeyframeInput> keyframes = BoxKeyframes(10, {0, 9});
  for (int k = 0; k < 10; ++k) {
    std::vector<DetectionAssignment> assignments;
    ASSERT_TRUE(backend->AddKeyframe(keyframes[k], &assignments).ok());
    ASSERT_EQ(assignments.size(), keyframes[k].detections.size());
    const std::vector<KeyframeEstimate> before = backend->Keyframes();
    SolveReport report;
    ASSERT_TRUE(backend->OptimizeWindow(&report).ok());
    const std::vector<KeyframeEstimate> after = backend->Keyframes();
    ExpectOutsideWindowUnchanged(before, after, k, 3);
    EXPECT_EQ(report.free_keyframes, std::min(k, 3)) << k;
    // Up to k = 2 nothing has left: the odometry factors and the box edge
    // of keyframe 0. From k = 3 on, the odometry factor into the window's
    // first keyframe went into the keyframe prior: 2 odometry factors and
    // the prior (6 = one pose). At k = 9 the box's edge of keyframe 9 and
    // its own prior from keyframe 0's edge.
    const int expected = k <= 2 ? k + 1 : (k == 9 ? 5 : 3);
    EXPECT_EQ(report.residual_blocks, expected) << k;
    EXPECT_EQ(report.prior_size, k >= 3 ? 6 : 0) << k;
    EXPECT_EQ(backend->Statistics().marginalized_keyframes, std::max(0, k - 2));
    if (k == 9) {
      ASSERT_EQ(assignments.size(), 1u);
      EXPECT_EQ(assignments[0].object, 0);  // the old object
    }
  }
  ASSERT_EQ(backend->Objects().size(), 1u);
  EXPECT_EQ(backend->Objects()[0].observations, 2);
  // Per-id getters agree with the lists.
  const std::optional<KeyframeEstimate> last = backend->Keyframe(9);
  ASSERT_TRUE(last.has_value());
  EXPECT_EQ(last->T_wc.t, backend->Keyframes().back().T_wc.t);
  EXPECT_FALSE(backend->Keyframe(10).has_value());
  ASSERT_TRUE(backend->Object(0).has_value());
  EXPECT_EQ(backend->Object(0)->t_wo, backend->Objects()[0].t_wo);
  EXPECT_FALSE(backend->Object(1).has_value());
  // The batch solve uses every factor, never the priors.
  SolveReport batch;
  ASSERT_TRUE(backend->OptimizeBatch(&batch).ok());
  EXPECT_EQ(batch.residual_blocks, 9 + 2);
  EXPECT_EQ(batch.prior_size, 0);
}

// keep_history only keeps what the batch solve needs: the window solves
// give bit-identical estimates with and without it, under marginalize and
// drop; without it the batch solve is refused once a keyframe has left
// (its factors were freed), and allowed before that and under condition.
TEST(BackendWindow, WithoutHistoryTheWindowIsTheSameAndTheBatchIsRefused) {
  const std::vector<KeyframeInput> keyframes = BoxKeyframes(12, {0, 4, 9, 11});
  for (WindowPolicy policy : {WindowPolicy::kMarginalize,
                              WindowPolicy::kDrop,
                              WindowPolicy::kCondition}) {
    std::vector<std::vector<KeyframeEstimate>> estimates;
    for (bool keep_history : {true, false}) {
      BackendOptions options;
      options.window_size = 3;
      options.confirm_keyframes = 1;
      options.window_policy = policy;
      options.keep_history = keep_history;
      std::unique_ptr<Backend> backend;
      ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
      for (int k = 0; k < 12; ++k) {
        ASSERT_TRUE(backend->AddKeyframe(keyframes[k]).ok());
        ASSERT_TRUE(backend->OptimizeWindow().ok());
      }
      estimates.push_back(backend->Keyframes());
      const Status batch = backend->OptimizeBatch();
      const bool refused = !keep_history && policy != WindowPolicy::kCondition;
      EXPECT_EQ(batch.ok(), !refused);
      if (refused) {
        EXPECT_NE(batch.message().find("keep_history"), std::string::npos)
            << batch.message();
      }
    }
    ASSERT_EQ(estimates[0].size(), estimates[1].size());
    for (size_t k = 0; k < estimates[0].size(); ++k) {
      EXPECT_EQ(estimates[0][k].T_wc.t, estimates[1][k].T_wc.t) << k;
      EXPECT_EQ(estimates[0][k].T_wc.q.coeffs(),
                estimates[1][k].T_wc.q.coeffs())
          << k;
    }
  }
  // Before anything left the window the batch solve has every factor.
  BackendOptions options;
  options.window_size = 3;
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
  ASSERT_TRUE(backend->AddKeyframe(keyframes[0]).ok());
  ASSERT_TRUE(backend->AddKeyframe(keyframes[1]).ok());
  ASSERT_TRUE(backend->OptimizeWindow().ok());
  EXPECT_TRUE(backend->OptimizeBatch().ok());
}

// Over a long run the window's problem stays the same size under
// marginalize and drop; under condition it grows with every keyframe that
// saw the box.
TEST(BackendWindow, ResidualBlocksStayBoundedOverALongRun) {
  // 150 keyframes: condition's cost grows with their square, which takes
  // minutes under the sanitizers at 400.
  constexpr int kKeyframes = 150;
  std::vector<int> all(kKeyframes);
  for (int k = 0; k < kKeyframes; ++k) all[k] = k;
  const std::vector<KeyframeInput> keyframes =
      BoxKeyframes(kKeyframes, all, 0.001);
  const std::pair<WindowPolicy, ChainPrior> runs[] = {
      {WindowPolicy::kMarginalize, ChainPrior::kConditional},
      {WindowPolicy::kMarginalize, ChainPrior::kMarginal},
      {WindowPolicy::kDrop, ChainPrior::kConditional},
      {WindowPolicy::kCondition, ChainPrior::kConditional}};
  for (const auto& [policy, chain_prior] : runs) {
    const std::string name = std::string(WindowPolicyName(policy)) + "/" +
                             ChainPriorName(chain_prior);
    BackendOptions options;
    options.window_size = 5;
    options.window_policy = policy;
    options.chain_prior = chain_prior;
    std::unique_ptr<Backend> backend;
    ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
    int most = 0;
    SolveReport report;
    for (const KeyframeInput& kf : keyframes) {
      ASSERT_TRUE(backend->AddKeyframe(kf).ok());
      ASSERT_TRUE(backend->OptimizeWindow(&report).ok());
      most = std::max(most, report.residual_blocks);
    }
    ASSERT_EQ(backend->Objects().size(), 1u) << name;
    if (policy == WindowPolicy::kCondition) {
      EXPECT_GE(report.residual_blocks, kKeyframes) << "every box edge";
    } else {
      // 5 box edges, 4 or 5 odometry factors, the keyframe and box priors.
      EXPECT_LE(most, 12) << name;
    }
    if (policy == WindowPolicy::kMarginalize) {
      EXPECT_EQ(report.prior_size, 6) << name << ": the oldest pose";
    }
  }
}

// A box seen by keyframe 0 and again by keyframe 29 after 29 steps of
// drifting odometry: the revisit pulls the window towards the box. The
// conditional chain anchors the window's oldest keyframe to the previous
// one's final pose (one odometry sigma); the marginal chain only with the
// uncertainty accumulated over the keyframes that left, so the window
// moves further.
TEST(BackendWindow, ConditionalChainAnchorsTheWindowMoreThanTheMarginalOne) {
  const std::vector<KeyframeInput> keyframes = BoxKeyframes(30, {0, 29});
  double moved[2] = {0.0, 0.0};
  const ChainPrior priors[2] = {ChainPrior::kConditional,
                                ChainPrior::kMarginal};
  for (int i = 0; i < 2; ++i) {
    BackendOptions options;
    options.window_size = 3;
    options.confirm_keyframes = 1;
    options.chain_prior = priors[i];
    std::unique_ptr<Backend> backend;
    ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
    for (const KeyframeInput& kf : keyframes) {
      ASSERT_TRUE(backend->AddKeyframe(kf).ok());
      if (kf.id == 29) break;
      ASSERT_TRUE(backend->OptimizeWindow().ok());
    }
    const std::optional<KeyframeEstimate> before = backend->Keyframe(29);
    ASSERT_TRUE(backend->OptimizeWindow().ok());
    const std::optional<KeyframeEstimate> after = backend->Keyframe(29);
    ASSERT_TRUE(before && after);
    ASSERT_EQ(backend->Objects().size(), 1u) << "the revisit associates";
    moved[i] = (after->T_wc.t - before->T_wc.t).norm();
  }
  EXPECT_GT(moved[0], 0.001);  // m: measured 0.007 conditional, 0.27 marginal
  EXPECT_GT(moved[1], 10.0 * moved[0])
      << "conditional " << moved[0] << " m, marginal " << moved[1] << " m";
}

TEST(BackendWindow, ConditionHoldsOlderKeyframesAndOldEdgesReenter) {
  BackendOptions options;
  options.window_policy = WindowPolicy::kCondition;
  options.window_size = 3;
  options.confirm_keyframes = 1;
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
  // The box is seen by keyframes 0 and 9 only.
  const std::vector<KeyframeInput> keyframes = BoxKeyframes(10, {0, 9});
  for (int k = 0; k < 10; ++k) {
    ASSERT_TRUE(backend->AddKeyframe(keyframes[k]).ok());
    const std::vector<KeyframeEstimate> before = backend->Keyframes();
    SolveReport report;
    ASSERT_TRUE(backend->OptimizeWindow(&report).ok());
    const std::vector<KeyframeEstimate> after = backend->Keyframes();
    ExpectOutsideWindowUnchanged(before, after, k, 3);
    EXPECT_EQ(report.free_keyframes, std::min(k, 3)) << k;
    // The window's odometry factors (each keyframe's to its predecessor),
    // plus, while the box is observed in the window (k = 0..2 and 9), all
    // of its edges: at k = 9 the edge of keyframe 0 is back as context.
    const int odometry = std::min(k, 3);
    const int box_edges = k <= 2 ? 1 : (k == 9 ? 2 : 0);
    EXPECT_EQ(report.residual_blocks, odometry + box_edges) << k;
  }
  // The solve at keyframe 9 moved the window: keyframe 9 is not where the
  // odometry alone put it.
  EXPECT_EQ(backend->Objects().size(), 1u);
  EXPECT_EQ(backend->Objects()[0].observations, 2);
}

// Keyframe k of a camera stepping 1 cm sideways (x) per keyframe, looking
// along z: the pose given at keyframe 0, odometry stated at 5 mm and
// 0.01 rad after it; no detections.
Rigid3d SideStepPose(int k) {
  return Rigid3d(Eigen::Quaterniond::Identity(),
                 Eigen::Vector3d(0.01 * k, 0.0, 0.0));
}

KeyframeInput SideStepKeyframe(int k) {
  KeyframeInput kf;
  kf.id = k;
  kf.timestamp = 0.1 * k;
  if (k == 0) {
    kf.T_wc = SideStepPose(0);
    return kf;
  }
  Odometry odometry;
  odometry.T_prev_cur = SideStepPose(0).Inverse() * SideStepPose(1);
  odometry.sigma_t = 0.005;
  odometry.sigma_r = 0.01;
  kf.odometry = odometry;
  return kf;
}

// A detector that declares no noise and has lost the object part of the
// time, as DOPE on YCB-Video 0004: a box at (0.2, 0, 2) is detected in
// every one of 90 keyframes with a slowly turning bias of up to 16 cm (so
// the class's estimate, inflated for persistence, opens the position gate
// to gate_position), and in keyframes 50-69 the detector also reports a
// second box around (1.5, 0, 2.5) that jumps by 0.3-0.42 m from keyframe to
// keyframe, each report within 0.5 m of the first. The ghost's detections
// stay a tentative object whose track is not one static thing (its steps
// median ratio dozens of times the real box's), which is dropped 10
// keyframes after its last detection: one map object, and the ghost's
// detections reported with object -1. Without the track test
// (track_tolerance 0) the ghost becomes a second box.
std::vector<KeyframeInput> BoxWithAGhost() {
  std::vector<KeyframeInput> keyframes;
  const Eigen::Vector3d box(0.2, 0.0, 2.0);
  const Eigen::Vector3d ghost(1.5, 0.0, 2.5);
  for (int k = 0; k < 90; ++k) {
    KeyframeInput kf = SideStepKeyframe(k);
    const Rigid3d T_wc = SideStepPose(k);
    auto detect = [&](const std::string& id, const Eigen::Vector3d& t_w) {
      DetectionInput det;
      det.id = std::to_string(k) + "/" + id;
      det.class_name = "box";
      det.hypotheses.push_back(
          {Rigid3d(Eigen::Quaterniond::Identity(), T_wc.Inverse() * t_w), 1.0});
      kf.detections.push_back(det);
    };
    const double phase = 0.05 * k;
    detect("box",
           box + 0.08 * Eigen::Vector3d(
                            std::sin(phase), 1.0 - std::cos(phase), 0.0));
    if (k >= 50 && k < 70) {
      detect("ghost",
             ghost + 0.15 * Eigen::Vector3d(k % 2 == 0 ? 1.0 : -1.0,
                                            (k / 2) % 2 == 0 ? 1.0 : -1.0,
                                            0.0));
    }
    keyframes.push_back(kf);
  }
  return keyframes;
}

TEST(BackendRobustness, AWanderingGhostOfALostObjectIsNotMapped) {
  const std::vector<KeyframeInput> keyframes = BoxWithAGhost();
  for (const double tolerance : {3.0, 0.0}) {
    SCOPED_TRACE(tolerance);
    BackendOptions options;
    options.track_tolerance = tolerance;
    std::unique_ptr<Backend> backend;
    testing::ReplayWindowed(keyframes, options, std::nullopt, &backend);
    ASSERT_NE(backend, nullptr);
    const RunResult run = {backend->Keyframes(),
                           backend->Objects(),
                           backend->Assignments(),
                           backend->Statistics()};
    ASSERT_EQ(run.assignments.size(), 110u);
    // What the ghost's track was compared with: the box's steps, of about
    // 4 mm against some 2 cm of stated motion noise at its distance.
    const std::vector<ClassNoiseEstimate> noise = backend->Noise();
    ASSERT_EQ(noise.size(), 1u);
    ASSERT_TRUE(noise[0].track_ratio.has_value());
    EXPECT_GT(*noise[0].track_ratio, 0.05);
    EXPECT_LT(*noise[0].track_ratio, 0.5);
    int ghost_objects = 0;
    for (const DetectionAssignment& a : run.assignments) {
      if (a.detection.find("ghost") == std::string::npos) {
        EXPECT_EQ(a.object, run.assignments[0].object) << a.detection;
      } else if (a.object >= 0) {
        ++ghost_objects;
      }
    }
    if (tolerance > 0.0) {
      EXPECT_EQ(run.objects.size(), 1u);
      EXPECT_EQ(ghost_objects, 0);
      EXPECT_EQ(run.statistics.objects_dropped, 1);
    } else {
      EXPECT_EQ(run.objects.size(), 2u);
      EXPECT_EQ(ghost_objects, 20);
    }
  }
}

// A can made from a detector's wrong pose (YCB-Video 0014): in keyframe 0
// of 90 the detector reports it turned by 86 degrees about z and 9 cm off,
// then at its true pose (within 1 cm). The first view makes the object
// (confirmed at once); the right views are flips without an edge until they
// outvote its rotation and turn it. The turn takes the first view's
// rotation and position out of the object (a detector that had the
// rotation wrong had the pose wrong) wherever it is:
//   - undeclared noise, window 3: the first view left the window with its
//     edge, weighed before the class had an estimate, for the object's
//     prior, and the right views are weighed with the class's estimate;
//     when the turn took the rotation only, that prior held the can 8.2 cm
//     off;
//   - declared noise (1 cm, 0.05 rad), window 40: the first view is still
//     in the window; when it kept its position, the can stayed 7.3 cm off
//     (the right views, 9 cm from it, failed the 1 cm detector's gate);
//   - with keep_history, the batch solve over every edge as well.
std::vector<KeyframeInput> CanFirstSeenTurned(const Eigen::Vector3d& can,
                                              bool declared) {
  std::vector<KeyframeInput> keyframes;
  const Eigen::Quaterniond turned(
      Eigen::AngleAxisd(86.0 * kPi / 180.0, Eigen::Vector3d::UnitZ()));
  for (int k = 0; k < 90; ++k) {
    KeyframeInput kf = SideStepKeyframe(k);
    const Rigid3d T_wc = SideStepPose(k);
    const bool wrong = k == 0;
    const Eigen::Vector3d wobble =
        0.01 * Eigen::Vector3d(std::sin(0.7 * k), std::cos(1.3 * k), 0.0);
    const Eigen::Vector3d t_w =
        can + (wrong ? Eigen::Vector3d(0.09, 0.0, 0.0) : wobble);
    DetectionInput det;
    det.id = std::to_string(k) + "/can";
    det.class_name = "can";
    if (declared) {
      det.sigma_t = 0.01;
      det.sigma_r = 0.05;
    }
    det.hypotheses.push_back(
        {Rigid3d(wrong ? turned : Eigen::Quaterniond::Identity(),
                 T_wc.Inverse() * t_w),
         1.0});
    kf.detections.push_back(det);
    keyframes.push_back(kf);
  }
  return keyframes;
}

TEST(BackendRobustness, AnObjectTurnedAwayFromItsFirstViewsIsPlacedByTheRest) {
  const Eigen::Vector3d can(0.2, 0.0, 2.0);
  struct Case {
    bool declared;
    int window;
    double bound;  // m
  };
  for (const Case& c : {Case{false, 3, 0.005}, Case{true, 40, 0.015}}) {
    for (const bool batch : {false, true}) {
      SCOPED_TRACE(std::string(c.declared ? "declared" : "undeclared") +
                   (batch ? ", batch" : ""));
      std::unique_ptr<Backend> backend;
      BackendOptions options;
      options.window_size = c.window;
      options.confirm_keyframes = 1;
      options.keep_history = batch;
      testing::ReplayWindowed(
          CanFirstSeenTurned(can, c.declared), options, std::nullopt, &backend);
      ASSERT_NE(backend, nullptr);
      if (batch) {
        SolveReport report;
        ASSERT_TRUE(backend->OptimizeBatch(&report).ok());
      }
      EXPECT_EQ(backend->Statistics().objects_turned, 1);
      const std::vector<MapObjectEstimate> objects = backend->Objects();
      ASSERT_EQ(objects.size(), 1u);
      EXPECT_LT((objects[0].t_wo - can).norm(), c.bound)
          << objects[0].t_wo.transpose();
      EXPECT_LT(
          objects[0].poses[0].q.angularDistance(Eigen::Quaterniond::Identity()),
          1.0 * kPi / 180.0);
    }
  }
}

// A detector that declares no noise and whose errors lie along its lines of
// sight, as DOPE's depth (docs/backend.md "Real detectors", mechanism 8):
// a box at the origin seen from 90 keyframes on a quarter circle of 2 m
// about it (the camera looking at it, odometry stated at 5 mm and 0.01
// rad), each detection 6 cm too far along its line of sight on average
// and scattered by up to 10 cm along it, within 5 mm of it across. The
// floor weighs the edges, so the cameras follow the odometry; the class's
// errors are wider along the sight lines than across them, and the sight
// rows place the box where the views' sight lines cross.
Rigid3d ArcPose(int k) {
  const double theta = 0.5 * M_PI * k / 89.0;
  return Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(-theta, Eigen::Vector3d::UnitY())),
      2.0 * Eigen::Vector3d(std::sin(theta), 0.0, -std::cos(theta)));
}

std::vector<KeyframeInput> BoxSeenTooFar() {
  std::vector<KeyframeInput> keyframes;
  for (int k = 0; k < 90; ++k) {
    KeyframeInput kf;
    kf.id = k;
    kf.timestamp = 0.1 * k;
    if (k == 0) {
      kf.T_wc = ArcPose(0);
    } else {
      Odometry odometry;
      odometry.T_prev_cur = ArcPose(k - 1).Inverse() * ArcPose(k);
      odometry.sigma_t = 0.005;
      odometry.sigma_r = 0.01;
      kf.odometry = odometry;
    }
    const Eigen::Vector3d t_co = ArcPose(k).Inverse() * Eigen::Vector3d::Zero();
    const Eigen::Vector3d sight = t_co.normalized();
    const Eigen::Vector3d across =
        sight.cross(Eigen::Vector3d::UnitY()).normalized();
    const double depth_error = 0.06 + 0.10 * std::sin(2.3 * k);
    DetectionInput det;
    det.id = std::to_string(k);
    det.class_name = "box";
    det.hypotheses.push_back({Rigid3d(ArcPose(k).q.inverse(),
                                      t_co + depth_error * sight +
                                          0.005 * std::cos(1.7 * k) * across),
                              1.0});
    kf.detections.push_back(det);
    keyframes.push_back(kf);
  }
  return keyframes;
}

TEST(BackendRobustness, SightLinesPlaceAnObjectWhoseDetectionsAreTooFar) {
  const std::vector<KeyframeInput> keyframes = BoxSeenTooFar();
  std::vector<std::vector<KeyframeEstimate>> cameras;
  std::vector<double> box_errors;
  for (const bool sight_rows : {true, false}) {
    SCOPED_TRACE(sight_rows);
    BackendOptions options;
    options.sight_rows = sight_rows;
    std::unique_ptr<Backend> backend;
    testing::ReplayWindowed(keyframes, options, std::nullopt, &backend);
    ASSERT_NE(backend, nullptr);
    const std::vector<MapObjectEstimate> objects = backend->Objects();
    ASSERT_EQ(objects.size(), 1u);
    box_errors.push_back(objects[0].t_wo.norm());
    cameras.push_back(backend->Keyframes());
  }
  // With the rows the box is within 2.5 cm (1.0 cm at this commit); without,
  // the detections' mean keeps much of their bias (5.9 cm).
  EXPECT_LT(box_errors[0], 0.025);
  EXPECT_GT(box_errors[1], 0.04);
  // The cameras stay about where the floor leaves them.
  ASSERT_EQ(cameras[0].size(), cameras[1].size());
  double moved = 0.0;
  double error_with = 0.0;
  double error_without = 0.0;
  for (size_t k = 0; k < cameras[0].size(); ++k) {
    const Eigen::Vector3d truth = ArcPose(static_cast<int>(k)).t;
    moved =
        std::max(moved, (cameras[0][k].T_wc.t - cameras[1][k].T_wc.t).norm());
    error_with = std::max(error_with, (cameras[0][k].T_wc.t - truth).norm());
    error_without =
        std::max(error_without, (cameras[1][k].T_wc.t - truth).norm());
  }
  // 0.2 and 0.3 mm at this commit; the odometry states 5 mm a step.
  EXPECT_LT(error_without, 0.002);
  EXPECT_LT(error_with, 0.002);
  EXPECT_LT(moved, 0.002);
}

}  // namespace
}  // namespace symba
