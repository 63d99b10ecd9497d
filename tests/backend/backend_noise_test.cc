// The detector's noise and the odometry weight learned from the run
// (docs/backend.md "Detection noise learned from the run"), end to end
// through the Backend: a camera circles three asymmetric boxes, a detector
// returns one pose per box and claims no noise (or a wrong one), and the
// front end gives odometry. Each test draws its own errors with a fixed
// seed and states the truth it checks against.
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/backend/backend.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "test_support/backend_replay.h"

namespace symba {
namespace {

constexpr int kKeyframesPerLoop = 60;
constexpr double kRadius = 2.5;  // m
constexpr double kHeight = 1.0;  // m

// Keyframe k on a circle about the origin, looking at it (camera z forward,
// y down).
Rigid3d TrueCamera(int k) {
  const double phi = kTwoPi * k / kKeyframesPerLoop;
  const Eigen::Vector3d c(
      kRadius * std::cos(phi), kRadius * std::sin(phi), kHeight);
  const Eigen::Vector3d z = (-c).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  return Rigid3d(Eigen::Quaterniond(R), c);
}

std::vector<Rigid3d> TrueBoxes() {
  return {
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 0)),
      Rigid3d(
          Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ())),
          Eigen::Vector3d(0.6, 0.3, 0.0)),
      Rigid3d(
          Eigen::Quaterniond(Eigen::AngleAxisd(-1.2, Eigen::Vector3d::UnitZ())),
          Eigen::Vector3d(-0.5, 0.4, 0.1))};
}

struct NoiseSequenceSpec {
  int num_keyframes = 180;
  // The detector's position error per axis in the camera frame: white
  // (independent per detection) and an AR(1) part of this correlation per
  // keyframe, per box.
  double white_t = 0.0;
  double persistent_t = 0.0;
  double correlation = 0.0;
  double rotation_sigma = 0.01;  // rad per axis, white
  std::optional<double> claimed_t;
  std::optional<double> claimed_r;
  // The front end: odometry noise as applied, and a yaw drift per keyframe
  // about the world vertical (rad); its claim.
  double odometry_noise_t = 0.001;
  double odometry_noise_r = 0.0005;
  double yaw_drift = 0.0;
  double odometry_sigma_t = 0.005;
  double odometry_sigma_r = 0.01;
  unsigned seed = 3;
};

struct NoiseSequence {
  std::vector<KeyframeInput> keyframes;
  std::vector<Rigid3d> truth;
  std::vector<Rigid3d> front_end;  // the odometry chained from the first
};

Eigen::Vector3d Gaussian3(std::mt19937* random, double sigma) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = sigma * normal(*random);
  return v;
}

NoiseSequence MakeSequence(const NoiseSequenceSpec& spec) {
  std::mt19937 random(spec.seed);
  const std::vector<Rigid3d> boxes = TrueBoxes();
  std::vector<Eigen::Vector3d> persistent(boxes.size(),
                                          Eigen::Vector3d::Zero());
  const double innovation =
      spec.persistent_t * std::sqrt(1.0 - spec.correlation * spec.correlation);
  for (Eigen::Vector3d& p : persistent)
    p = Gaussian3(&random, spec.persistent_t);
  NoiseSequence sequence;
  for (int k = 0; k < spec.num_keyframes; ++k) {
    const Rigid3d T_wc = TrueCamera(k);
    KeyframeInput input;
    input.id = k;
    input.timestamp = 0.1 * k;
    if (k == 0) {
      input.T_wc = T_wc;
      sequence.front_end.push_back(T_wc);
    } else {
      const Rigid3d step = TrueCamera(k - 1).Inverse() * T_wc;
      const Eigen::Vector3d up_c = T_wc.q.inverse() * Eigen::Vector3d::UnitZ();
      const Rigid3d error(
          Eigen::Quaterniond(Eigen::AngleAxisd(spec.yaw_drift, up_c)) *
              ExpSO3(Gaussian3(&random, spec.odometry_noise_r)),
          Gaussian3(&random, spec.odometry_noise_t));
      Odometry odometry;
      odometry.T_prev_cur = step * error;
      odometry.sigma_t = spec.odometry_sigma_t;
      odometry.sigma_r = spec.odometry_sigma_r;
      input.odometry = odometry;
      sequence.front_end.push_back(sequence.front_end.back() *
                                   odometry.T_prev_cur);
    }
    for (size_t b = 0; b < boxes.size(); ++b) {
      persistent[b] =
          spec.correlation * persistent[b] + Gaussian3(&random, innovation);
      Rigid3d T_co = T_wc.Inverse() * boxes[b];
      T_co.t += Gaussian3(&random, spec.white_t) + persistent[b];
      T_co.q = (T_co.q * ExpSO3(Gaussian3(&random, spec.rotation_sigma)))
                   .normalized();
      DetectionInput detection;
      detection.id = std::to_string(k) + "/" + std::to_string(b);
      detection.class_name = "box";
      detection.hypotheses.push_back({T_co, 1.0});
      detection.sigma_t = spec.claimed_t;
      detection.sigma_r = spec.claimed_r;
      input.detections.push_back(detection);
    }
    sequence.keyframes.push_back(input);
    sequence.truth.push_back(T_wc);
  }
  return sequence;
}

double PositionRmse(const std::vector<Rigid3d>& estimate,
                    const std::vector<Rigid3d>& truth) {
  double sum = 0.0;
  for (size_t k = 0; k < truth.size(); ++k) {
    sum += (estimate[k].t - truth[k].t).squaredNorm();
  }
  return std::sqrt(sum / truth.size());
}

struct Replayed {
  std::unique_ptr<Backend> backend;
  std::vector<Rigid3d> cameras;
};

Replayed Replay(const NoiseSequence& sequence) {
  Replayed run;
  testing::ReplayWindowed(
      sequence.keyframes, BackendOptions(), std::nullopt, &run.backend);
  if (run.backend == nullptr) return run;
  for (const KeyframeEstimate& k : run.backend->Keyframes()) {
    run.cameras.push_back(k.T_wc);
  }
  return run;
}

const ClassNoiseEstimate* BoxNoise(const NoiseEstimates& noise) {
  for (const ClassNoiseEstimate& c : noise.classes) {
    if (c.class_name == "box") return &c;
  }
  return nullptr;
}

TEST(BackendNoise, AKnownWhiteDetectorNoiseIsEstimatedWithin15Percent) {
  NoiseSequenceSpec spec;
  spec.white_t = 0.03;  // m per axis
  const NoiseSequence sequence = MakeSequence(spec);
  const Replayed run = Replay(sequence);
  ASSERT_NE(run.backend, nullptr);
  const ClassNoiseEstimate* box = BoxNoise(run.backend->Noise());
  ASSERT_NE(box, nullptr);
  ASSERT_TRUE(box->sigma_t.has_value());
  ASSERT_TRUE(box->translation.has_value());
  // The scatter (white and persistent) is the detector's 3 cm, and so is
  // its white part.
  const double scatter =
      std::hypot(box->translation->white, box->translation->persistent);
  EXPECT_NEAR(scatter, 0.03, 0.15 * 0.03);
  EXPECT_NEAR(box->translation->white, 0.03, 0.15 * 0.03);
  // The weight is never below the scatter. It can be above it: the
  // placements are made with the estimated cameras, whose own error is
  // smooth from keyframe to keyframe and shows as a small persistent part
  // (here a few millimetres) that the weight inflates.
  EXPECT_GE(*box->sigma_t, scatter);
  // Three boxes in every keyframe, the first 10 in the window at the end.
  EXPECT_GE(box->samples_t, 3 * (spec.num_keyframes - 10) - 20);
  // And every box is one map object.
  EXPECT_EQ(run.backend->Objects().size(), 3u);
}

TEST(BackendNoise, AKnownAR1ErrorGetsItsInflation) {
  NoiseSequenceSpec spec;
  spec.white_t = 0.005;
  spec.persistent_t = 0.04;  // m per axis
  spec.correlation = 0.95;   // per keyframe
  const Replayed run = Replay(MakeSequence(spec));
  ASSERT_NE(run.backend, nullptr);
  const ClassNoiseEstimate* box = BoxNoise(run.backend->Noise());
  ASSERT_NE(box, nullptr);
  ASSERT_TRUE(box->translation.has_value());
  // The persistence shows: a correlation near 0.95 and its inflation,
  // sqrt(1.95 / 0.05) = 6.2, at least 4 (0.9 gives 4.4).
  EXPECT_GE(box->translation->correlation, 0.9);
  EXPECT_GE(box->translation->inflation, 4.0);
  // The weight is the persistent part inflated, at least four times the
  // scatter of one detection.
  const double scatter =
      std::hypot(box->translation->white, box->translation->persistent);
  EXPECT_GE(*box->sigma_t, 4.0 * scatter);
}

TEST(BackendNoise, AnOverconfidentDetectorDoesNotTakeTheCamera) {
  // The detector claims 1 cm but is off by 10 cm per axis; an accurate
  // front end.
  NoiseSequenceSpec spec;
  spec.white_t = 0.10;
  spec.claimed_t = 0.01;
  spec.claimed_r = 0.01;
  const NoiseSequence sequence = MakeSequence(spec);
  const Replayed run = Replay(sequence);
  ASSERT_NE(run.backend, nullptr);
  ASSERT_EQ(run.cameras.size(), sequence.truth.size());
  const double front_end = PositionRmse(sequence.front_end, sequence.truth);
  const double symba = PositionRmse(run.cameras, sequence.truth);
  EXPECT_LE(symba, 1.1 * front_end) << "front end " << front_end;
  // The data contradict the claim: the class is weighed with more.
  const ClassNoiseEstimate* box = BoxNoise(run.backend->Noise());
  ASSERT_NE(box, nullptr);
  ASSERT_TRUE(box->sigma_t.has_value());
  EXPECT_GT(*box->sigma_t, 3 * 0.01);
}

TEST(BackendNoise, ADriftingFrontEndIsPulledBackByObjectsSeenAgain) {
  // The front end turns 0.5 degrees per keyframe about the vertical (two
  // loops: 180 degrees off at the end) and claims 5 mm / 0.01 rad; the
  // detector has 2 cm of white noise and claims nothing.
  NoiseSequenceSpec spec;
  spec.num_keyframes = 120;
  spec.white_t = 0.02;
  spec.yaw_drift = 0.5 * kPi / 180.0;
  const NoiseSequence sequence = MakeSequence(spec);
  const Replayed run = Replay(sequence);
  ASSERT_NE(run.backend, nullptr);
  ASSERT_EQ(run.cameras.size(), sequence.truth.size());
  const double front_end = PositionRmse(sequence.front_end, sequence.truth);
  const double symba = PositionRmse(run.cameras, sequence.truth);
  EXPECT_GT(front_end, 1.0);
  EXPECT_LT(symba, 0.2 * front_end) << "front end " << front_end;
  // The odometry's systematic error shows in its residuals: it is weighed
  // with more than it claims.
  EXPECT_TRUE(run.backend->Noise().odometry_estimated);
  EXPECT_GT(run.backend->Noise().odometry_sigma_factor, 1.0);
}

}  // namespace
}  // namespace symba
