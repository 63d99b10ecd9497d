// Tests of the simulator (include/symba/simulation/simulator.h): it is
// deterministic, its detections are what its ground truth says they are,
// its front end drifts where and only where the scene is featureless, its
// points are visible where it reports them, and its files read back.
//
// Noise bounds: a 3-vector of N(0, s^2) per axis has norm above 6 s with
// probability 2e-7 (chi with 3 degrees of freedom), so 6 s bounds every
// draw of a sequence (a room has about 10^4 hypotheses).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "symba/io/log_format.h"
#include "symba/simulation/scene.h"
#include "symba/simulation/simulator.h"

namespace symba {
namespace {

using ::testing::HasSubstr;

constexpr double kDeg = kPi / 180.0;
constexpr double kSigmas = 6.0;  // see the top

SimulatedSequence MustSimulate(const std::string& scene,
                               const SimulationOptions& options,
                               uint32_t seed) {
  SimulatedSequence seq;
  const Status status = Simulate(scene, options, seed, &seq);
  EXPECT_TRUE(status.ok()) << status.message();
  return seq;
}

std::map<std::string, std::string> Files(const SimulatedSequence& seq) {
  std::vector<std::pair<std::string, std::string>> files;
  const Status status = SimulationFiles(seq, &files);
  EXPECT_TRUE(status.ok()) << status.message();
  return {files.begin(), files.end()};
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

double RotationAngle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return LogSO3<double>(a.conjugate() * b).norm();
}

Eigen::Quaterniond Rot(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// ---------------------------------------------------------------------------
// Scenes and options.

TEST(Simulation, EveryScenesSimulatesAndUnknownNamesAreRefused) {
  for (const std::string& name : SceneNames()) {
    SCOPED_TRACE(name);
    const SimulatedSequence seq = MustSimulate(name, SimulationOptions(), 1);
    EXPECT_EQ(seq.keyframes.size(), 72u);
    EXPECT_FALSE(seq.objects.empty());
    int detections = 0;
    for (const auto& truths : seq.detections) detections += truths.size();
    EXPECT_GT(detections, 60);
  }
  SimulatedSequence seq;
  const Status status = Simulate("kitchen", SimulationOptions(), 1, &seq);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("unknown scene 'kitchen'"));
  EXPECT_THAT(status.message(), HasSubstr("disc"));
}

TEST(Simulation, ScenesHaveTheDocumentedObjects) {
  Scene room;
  ASSERT_TRUE(MakeScene("room", &room).ok());
  std::map<std::string, std::vector<SimulatedObject>> by_class;
  for (const SimulatedObject& o : room.objects)
    by_class[o.class_name].push_back(o);
  ASSERT_EQ(by_class["round_table"].size(), 2u);
  EXPECT_GE(
      (by_class["round_table"][0].T_wo.t - by_class["round_table"][1].T_wo.t)
          .norm(),
      1.2);
  ASSERT_EQ(by_class["prism"].size(), 1u);
  const SimulatedObject& prism = by_class["prism"][0];
  EXPECT_EQ(prism.order, 3);
  const Eigen::Vector3d a_w = prism.T_wo.q * prism.axis_o;
  EXPECT_NEAR(std::asin(a_w.z()), 30.0 * kDeg, 1e-12);  // tilted
  EXPECT_EQ(by_class["chair"].size(), 1u);
  EXPECT_EQ(by_class["table"].size(), 1u);
  EXPECT_EQ(by_class["table"][0].order, 2);

  Scene square;
  ASSERT_TRUE(MakeScene("square", &square).ok());
  EXPECT_EQ(square.objects[0].order, 4);
}

TEST(Simulation, InvalidOptionsAreRefused) {
  SimulatedSequence seq;
  SimulationOptions options;
  options.outlier_fraction = 1.5;
  Status status = Simulate("disc", options, 1, &seq);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("outlier_fraction"));
  options = SimulationOptions();
  options.orbit_radius = -1.0;
  status = Simulate("disc", options, 1, &seq);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("orbit_radius"));
  options = SimulationOptions();
  options.num_keyframes = 0;
  EXPECT_FALSE(Simulate("disc", options, 1, &seq).ok());
}

// ---------------------------------------------------------------------------
// Determinism.

TEST(Simulation, SameSeedGivesIdenticalFilesAndAnotherSeedDoesNot) {
  for (const char* name : {"disc", "room"}) {
    SCOPED_TRACE(name);
    const auto a = Files(MustSimulate(name, SimulationOptions(), 7));
    const auto b = Files(MustSimulate(name, SimulationOptions(), 7));
    const auto c = Files(MustSimulate(name, SimulationOptions(), 8));
    ASSERT_EQ(a.size(), 3u);
    EXPECT_EQ(a, b);
    EXPECT_NE(a.at("log.jsonl"), c.at("log.jsonl"));
    // The truth of the scene and the orbit do not depend on the seed.
    EXPECT_EQ(a.at("gt_trajectory.tum"), c.at("gt_trajectory.tum"));
  }
}

// ---------------------------------------------------------------------------
// Detections against the ground truth.

// Every inlier hypothesis is within noise of the true mode it is labelled
// with, T_co = T_cw T_wo (Rot(a_o, 2 pi m / k), 0) for discrete objects, and
// of no other mode; continuous inliers share the true axis; the highest
// weight belongs to the dominant mode; outliers number round(0.1 N).
void ExpectDetectionsMatchTruth(const SimulatedSequence& seq) {
  const SimulationOptions& opt = seq.options;
  const double rotation_bound = kSigmas * opt.rotation_sigma;
  const double translation_bound = kSigmas * opt.translation_sigma;
  const int expected_outliers =
      static_cast<int>(std::lround(opt.outlier_fraction * opt.num_hypotheses));
  int checked = 0;
  for (size_t k = 0; k < seq.keyframes.size(); ++k) {
    const KeyframeInput& kf = seq.keyframes[k];
    ASSERT_EQ(kf.detections.size(), seq.detections[k].size());
    for (size_t d = 0; d < kf.detections.size(); ++d) {
      const DetectionInput& det = kf.detections[d];
      const SimulatedDetectionTruth& truth = seq.detections[k][d];
      SCOPED_TRACE(det.id);
      ASSERT_EQ(det.id, truth.id);
      ASSERT_GE(truth.object, 0);
      const SimulatedObject& object = seq.objects[truth.object];
      EXPECT_EQ(det.class_name, object.class_name);
      ASSERT_EQ(det.hypotheses.size(), static_cast<size_t>(opt.num_hypotheses));
      ASSERT_EQ(truth.hypothesis_mode.size(), det.hypotheses.size());
      const Rigid3d T_co = seq.T_wc_true[k].Inverse() * object.T_wo;
      const Eigen::Vector3d a_o = object.axis_o.normalized();
      int outliers = 0;
      size_t best = 0;
      for (size_t j = 0; j < det.hypotheses.size(); ++j) {
        if (det.hypotheses[j].weight > det.hypotheses[best].weight) best = j;
        const int mode = truth.hypothesis_mode[j];
        if (mode < 0) {
          ++outliers;
          continue;
        }
        const Rigid3d& T = det.hypotheses[j].T_co;
        EXPECT_LT((T.t - T_co.t).norm(), translation_bound);
        switch (object.symmetry) {
          case SymmetryType::kAsymmetric:
            EXPECT_LT(RotationAngle(T.q, T_co.q), rotation_bound);
            break;
          case SymmetryType::kDiscrete: {
            EXPECT_NE(std::find(truth.visible_modes.begin(),
                                truth.visible_modes.end(),
                                mode),
                      truth.visible_modes.end());
            for (int m = 0; m < object.order; ++m) {
              const double error = RotationAngle(
                  T.q, T_co.q * Rot(a_o, kTwoPi * m / object.order));
              if (m == mode) {
                EXPECT_LT(error, rotation_bound) << "mode " << m;
              } else {
                EXPECT_GT(error, rotation_bound) << "mode " << m;
              }
            }
            break;
          }
          case SymmetryType::kContinuous: {
            const double axis_error =
                std::acos(std::clamp((T.q * a_o).dot(T_co.q * a_o), -1.0, 1.0));
            EXPECT_LT(axis_error, rotation_bound);
            // And the rotation is the labelled one about the axis.
            EXPECT_LT(RotationAngle(
                          T.q, T_co.q * Rot(a_o, truth.hypothesis_angle[j])),
                      rotation_bound);
            break;
          }
        }
        ++checked;
      }
      EXPECT_EQ(outliers, expected_outliers);
      // The highest weight is an inlier of the dominant mode.
      EXPECT_EQ(truth.hypothesis_mode[best], truth.dominant_mode);
      if (opt.write_detection_sigmas) {
        EXPECT_EQ(det.sigma_t, opt.translation_sigma);
        EXPECT_EQ(det.sigma_r, opt.rotation_sigma);
      }
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(Simulation, EveryInlierHypothesisIsNearItsTrueMode) {
  for (const std::string& name : SceneNames()) {
    SCOPED_TRACE(name);
    ExpectDetectionsMatchTruth(MustSimulate(name, SimulationOptions(), 3));
  }
}

// What breaks the baselines: views showing only some modes, and the
// highest-weight mode changing between consecutive views.
TEST(Simulation, DiscreteViewsShowSubsetsAndTheDominantModeFlips) {
  for (const char* name : {"disc", "square"}) {
    SCOPED_TRACE(name);
    const SimulatedSequence seq = MustSimulate(name, SimulationOptions(), 5);
    const int order = seq.objects[0].order;
    int full = 0;
    int subset = 0;
    int flips = 0;
    int previous = -1;
    for (const auto& truths : seq.detections) {
      for (const SimulatedDetectionTruth& truth : truths) {
        const int visible = static_cast<int>(truth.visible_modes.size());
        ASSERT_GE(visible, 1);
        ASSERT_LE(visible, order);
        (visible == order ? full : subset) += 1;
        if (previous >= 0 && truth.dominant_mode != previous) ++flips;
        previous = truth.dominant_mode;
      }
    }
    EXPECT_GT(full, 15);
    EXPECT_GT(subset, 15);
    EXPECT_GT(flips, 15);
  }
  // Full persistence keeps the dominant mode whenever it is visible.
  SimulationOptions options;
  options.dominant_mode_persistence = 1.0;
  options.subset_view_probability = 0.0;
  const SimulatedSequence seq = MustSimulate("disc", options, 5);
  std::set<int> dominant;
  for (const auto& truths : seq.detections) {
    for (const SimulatedDetectionTruth& truth : truths) {
      dominant.insert(truth.dominant_mode);
    }
  }
  EXPECT_EQ(dominant.size(), 1u);
}

// The single-pose detector: one hypothesis per detection, at a random one
// of the symmetric poses (every mode of a discrete object, flipping), an
// outlier with outlier_fraction.
TEST(Simulation, SingleHypothesisDetectorGivesOnePoseAtARandomSymmetricPose) {
  SimulationOptions options;
  options.single_hypothesis = true;
  for (const char* name : {"disc", "square", "cts", "asym"}) {
    SCOPED_TRACE(name);
    const SimulatedSequence seq = MustSimulate(name, options, 7);
    const SimulatedObject& object = seq.objects[0];
    std::set<int> modes;
    int detections = 0;
    int outliers = 0;
    int flips = 0;
    int previous = -1;
    for (size_t k = 0; k < seq.keyframes.size(); ++k) {
      const Rigid3d T_cw = seq.T_wc_true[k].Inverse();
      for (size_t d = 0; d < seq.keyframes[k].detections.size(); ++d) {
        const DetectionInput& det = seq.keyframes[k].detections[d];
        const SimulatedDetectionTruth& truth = seq.detections[k][d];
        ASSERT_EQ(det.hypotheses.size(), 1u);
        ASSERT_EQ(truth.hypothesis_mode.size(), 1u);
        ++detections;
        if (truth.hypothesis_mode[0] < 0) {
          ++outliers;
          continue;
        }
        modes.insert(truth.hypothesis_mode[0]);
        if (previous >= 0 && truth.dominant_mode != previous) ++flips;
        previous = truth.dominant_mode;
        // The pose is the labelled symmetric pose within the noise
        // (3 deg per axis: 15 deg is five sigma of the angle).
        const Rigid3d T_co = T_cw * object.T_wo;
        const Eigen::Quaterniond expected =
            T_co.q * Rot(object.axis_o, truth.hypothesis_angle[0]);
        EXPECT_LT(RotationAngle(det.hypotheses[0].T_co.q, expected),
                  15.0 * kPi / 180.0);
      }
    }
    EXPECT_GT(detections, 50);
    EXPECT_GT(outliers, 0);
    EXPECT_LT(outliers, detections / 4);
    if (object.symmetry == SymmetryType::kDiscrete) {
      EXPECT_EQ(static_cast<int>(modes.size()), object.order);
      EXPECT_GT(flips, detections / 3);
    }
  }
  options.outlier_fraction = 1.0;
  SimulatedSequence seq;
  const Status status = Simulate("disc", options, 1, &seq);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("outlier_fraction"));
}

TEST(Simulation, MissedDetectionsFollowTheirProbability) {
  SimulationOptions options;
  options.miss_probability = 0.0;
  const SimulatedSequence all = MustSimulate("disc", options, 2);
  for (const auto& truths : all.detections) EXPECT_EQ(truths.size(), 1u);
  options.miss_probability = 0.5;
  const SimulatedSequence half = MustSimulate("disc", options, 2);
  int seen = 0;
  for (const auto& truths : half.detections) seen += truths.size();
  EXPECT_GT(seen, 20);
  EXPECT_LT(seen, 52);
}

TEST(Simulation, ClassPriorsAreWrittenOnlyOnRequest) {
  EXPECT_TRUE(
      MustSimulate("room", SimulationOptions(), 1).header.classes.empty());
  SimulationOptions options;
  options.write_class_priors = true;
  const SimulatedSequence seq = MustSimulate("room", options, 1);
  ASSERT_EQ(seq.header.classes.size(), 4u);
  const ClassPrior& prism = seq.header.classes.at("prism");
  EXPECT_EQ(prism.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(prism.order, 3);
  EXPECT_EQ(prism.axis_o, Eigen::Vector3d::UnitX());
  EXPECT_EQ(seq.header.classes.at("round_table").symmetry,
            SymmetryType::kContinuous);
  EXPECT_EQ(seq.header.classes.at("chair").symmetry, SymmetryType::kAsymmetric);
}

// How often `needle` occurs in `text`.
int Occurrences(const std::string& text, const std::string& needle) {
  int count = 0;
  for (size_t at = text.find(needle); at != std::string::npos;
       at = text.find(needle, at + needle.size())) {
    ++count;
  }
  return count;
}

// A detector that declares no noise (write_detection_sigmas off, `symba
// simulate --declare-noise false`) draws exactly what the declaring one
// draws: the same detections and hypotheses bit for bit, without sigma_t and
// sigma_r; the odometry keeps its declared noise.
TEST(Simulation, UndeclaredNoiseChangesOnlyTheDetectionSigmas) {
  for (const char* name : {"disc", "room"}) {
    SCOPED_TRACE(name);
    const SimulatedSequence declared =
        MustSimulate(name, SimulationOptions(), 5);
    SimulationOptions options;
    options.write_detection_sigmas = false;
    const SimulatedSequence undeclared = MustSimulate(name, options, 5);
    ASSERT_EQ(declared.keyframes.size(), undeclared.keyframes.size());
    int detections = 0;
    for (size_t k = 0; k < declared.keyframes.size(); ++k) {
      const KeyframeInput& a = declared.keyframes[k];
      const KeyframeInput& b = undeclared.keyframes[k];
      ASSERT_EQ(a.odometry.has_value(), b.odometry.has_value());
      if (b.odometry) {
        EXPECT_EQ(b.odometry->T_prev_cur.t, a.odometry->T_prev_cur.t);
        EXPECT_EQ(b.odometry->T_prev_cur.q.coeffs(),
                  a.odometry->T_prev_cur.q.coeffs());
        EXPECT_EQ(b.odometry->sigma_t, a.odometry->sigma_t);
        EXPECT_EQ(b.odometry->sigma_r, a.odometry->sigma_r);
      }
      ASSERT_EQ(a.detections.size(), b.detections.size());
      for (size_t d = 0; d < a.detections.size(); ++d, ++detections) {
        const DetectionInput& da = a.detections[d];
        const DetectionInput& db = b.detections[d];
        EXPECT_EQ(da.sigma_t, SimulationOptions().translation_sigma);
        EXPECT_EQ(da.sigma_r, SimulationOptions().rotation_sigma);
        EXPECT_FALSE(db.sigma_t.has_value());
        EXPECT_FALSE(db.sigma_r.has_value());
        EXPECT_EQ(db.id, da.id);
        EXPECT_EQ(db.class_name, da.class_name);
        ASSERT_EQ(db.hypotheses.size(), da.hypotheses.size());
        for (size_t j = 0; j < da.hypotheses.size(); ++j) {
          EXPECT_EQ(db.hypotheses[j].T_co.t, da.hypotheses[j].T_co.t);
          EXPECT_EQ(db.hypotheses[j].T_co.q.coeffs(),
                    da.hypotheses[j].T_co.q.coeffs());
          EXPECT_EQ(db.hypotheses[j].weight, da.hypotheses[j].weight);
        }
      }
    }
    EXPECT_GT(detections, 50);
    // The ground truth is the same file; the log loses exactly the
    // detections' sigmas (the odometry's are still written).
    const auto a = Files(declared);
    const auto b = Files(undeclared);
    EXPECT_EQ(a.at("gt_objects.json"), b.at("gt_objects.json"));
    EXPECT_EQ(a.at("gt_trajectory.tum"), b.at("gt_trajectory.tum"));
    const int odometries = static_cast<int>(declared.keyframes.size()) - 1;
    EXPECT_EQ(Occurrences(a.at("log.jsonl"), "\"sigma_t\""),
              odometries + detections);
    EXPECT_EQ(Occurrences(b.at("log.jsonl"), "\"sigma_t\""), odometries);
    EXPECT_EQ(Occurrences(b.at("log.jsonl"), "\"sigma_r\""), odometries);
  }
}

// ---------------------------------------------------------------------------
// Front end.

// The yaw about the world vertical of the front end's error on the
// relative motion into keyframe k, and its full rotation error.
struct MotionError {
  double yaw = 0.0;
  double rotation = 0.0;
  double translation = 0.0;
};

MotionError FrontendMotionError(const SimulatedSequence& seq, size_t k) {
  const Rigid3d truth = seq.T_wc_true[k - 1].Inverse() * seq.T_wc_true[k];
  const Rigid3d fe =
      seq.keyframes[k - 1].T_wc->Inverse() * *seq.keyframes[k].T_wc;
  const Rigid3d error = truth.Inverse() * fe;
  const Eigen::Vector3d a_c =
      seq.T_wc_true[k].q.conjugate() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d omega = LogSO3<double>(error.q);
  return {omega.dot(a_c), omega.norm(), error.t.norm()};
}

TEST(Simulation, FrontEndDriftsOnTheFeaturelessHalfOnly) {
  const SimulationOptions opt;
  const SimulatedSequence seq = MustSimulate("disc", opt, 4);
  ASSERT_EQ(seq.keyframes.front().T_wc->t, seq.T_wc_true.front().t);
  double rich_yaw = 0.0;
  double featureless_yaw = 0.0;
  int num_rich = 0;
  int num_featureless = 0;
  for (size_t k = 1; k < seq.keyframes.size(); ++k) {
    SCOPED_TRACE(k);
    const MotionError e = FrontendMotionError(seq, k);
    if (seq.rich[k]) {
      EXPECT_LT(e.rotation, kSigmas * opt.rich_sigma_r);
      EXPECT_LT(e.translation, kSigmas * opt.rich_sigma_t);
      rich_yaw += e.yaw;
      ++num_rich;
    } else {
      EXPECT_NEAR(e.yaw,
                  opt.yaw_bias,
                  kSigmas * (opt.yaw_noise + opt.featureless_sigma_r));
      featureless_yaw += e.yaw;
      ++num_featureless;
    }
  }
  ASSERT_EQ(num_rich + num_featureless + 1, 72);
  EXPECT_EQ(num_featureless, 36);
  // The bias shows in the mean (its noise is 0.5 deg / sqrt(36)).
  EXPECT_NEAR(featureless_yaw / num_featureless, opt.yaw_bias, 0.3 * kDeg);
  EXPECT_NEAR(rich_yaw / num_rich, 0.0, 0.1 * kDeg);

  // The first rich half is accurate up to the random walk of its noise (17
  // steps of 0.9 cm, plus the lever arm of 0.2 deg rotation noise: about
  // 5 cm); the drift of the featureless half is kept (no relocalisation
  // by default).
  for (size_t k = 0; k < 18; ++k) {
    ASSERT_TRUE(seq.rich[k]);
    EXPECT_LT((seq.keyframes[k].T_wc->t - seq.T_wc_true[k].t).norm(), 0.15);
  }
  EXPECT_FALSE(seq.rich[18]);
  EXPECT_GT((seq.keyframes[35].T_wc->t - seq.T_wc_true[35].t).norm(), 1.0);
  EXPECT_GT((seq.keyframes[50].T_wc->t - seq.T_wc_true[50].t).norm(), 1.0);
}

TEST(Simulation, RelocalisingFrontEndIsAccurateOnEveryRichKeyframe) {
  SimulationOptions opt;
  opt.relocalize_on_rich = true;
  opt.with_odometry = true;
  const SimulatedSequence seq = MustSimulate("disc", opt, 4);
  for (size_t k = 1; k < seq.keyframes.size(); ++k) {
    SCOPED_TRACE(k);
    const KeyframeInput& kf = seq.keyframes[k];
    ASSERT_TRUE(kf.odometry.has_value());
    // The claimed sigmas follow the side the keyframe is on.
    EXPECT_EQ(
        kf.odometry->sigma_t,
        seq.rich[k] ? opt.odometry_sigma_t : opt.featureless_odometry_sigma_t);
    EXPECT_EQ(
        kf.odometry->sigma_r,
        seq.rich[k] ? opt.odometry_sigma_r : opt.featureless_odometry_sigma_r);
    if (seq.rich[k]) {
      EXPECT_LT((kf.T_wc->t - seq.T_wc_true[k].t).norm(), 0.05);
    }
    // Odometry is the visual odometry step, biased on the featureless half.
    const Rigid3d truth = seq.T_wc_true[k - 1].Inverse() * seq.T_wc_true[k];
    const double error =
        LogSO3<double>(truth.q.conjugate() * kf.odometry->T_prev_cur.q).norm();
    if (seq.rich[k]) {
      EXPECT_LT(error, kSigmas * opt.rich_sigma_r);
    } else {
      EXPECT_GT(error, opt.yaw_bias - kSigmas * opt.yaw_noise);
    }
  }
  EXPECT_FALSE(seq.keyframes.front().odometry.has_value());
}

// ---------------------------------------------------------------------------
// Map points.

TEST(Simulation, PointsLieOnTheRichSideAndAreObservedOnlyWhereVisible) {
  const SimulationOptions opt;
  const SimulatedSequence seq = MustSimulate("room", opt, 6);
  ASSERT_EQ(seq.points_w.size(), static_cast<size_t>(opt.num_points));
  // The rich cameras are at orbit angles [0, pi) and look across the
  // centre: the textured wall is the arc [pi, 2 pi).
  for (const Eigen::Vector3d& p : seq.points_w) {
    EXPECT_NEAR(std::hypot(p.x(), p.y()), opt.wall_radius, 1e-9);
    EXPECT_LE(p.y(), 1e-9);
    EXPECT_GE(p.z(), opt.wall_z_min);
    EXPECT_LE(p.z(), opt.wall_z_max);
  }
  std::set<int64_t> seen;
  const PinholeIntrinsics& K = opt.intrinsics;
  for (size_t k = 0; k < seq.keyframes.size(); ++k) {
    SCOPED_TRACE(k);
    const KeyframeInput& kf = seq.keyframes[k];
    if (!seq.rich[k]) {
      EXPECT_TRUE(kf.points.empty());
      continue;
    }
    EXPECT_GT(kf.points.size(), 30u);
    const Rigid3d T_cw = seq.T_wc_true[k].Inverse();
    for (const PointObservation& obs : kf.points) {
      ASSERT_GE(obs.id, 0);
      ASSERT_LT(obs.id, opt.num_points);
      const Eigen::Vector3d p_c = T_cw * seq.points_w[obs.id];
      EXPECT_GE(p_c.z(), opt.min_point_depth);
      EXPECT_GE(obs.uv.x(), 0.0);
      EXPECT_LT(obs.uv.x(), opt.image_width);
      EXPECT_GE(obs.uv.y(), 0.0);
      EXPECT_LT(obs.uv.y(), opt.image_height);
      const Eigen::Vector2d uv(K.fx * p_c.x() / p_c.z() + K.cx,
                               K.fy * p_c.y() / p_c.z() + K.cy);
      EXPECT_LT((uv - obs.uv).norm(), kSigmas * opt.pixel_sigma);
      // Depth on the first observation only.
      const bool first = seen.insert(obs.id).second;
      EXPECT_EQ(obs.depth.has_value(), first);
      if (obs.depth) {
        EXPECT_NEAR(*obs.depth, p_c.z(), kSigmas * opt.depth_sigma);
      }
    }
  }
  // The second loop sees the first loop's points again.
  EXPECT_GT(seen.size(), static_cast<size_t>(opt.num_points) / 2);
}

// ---------------------------------------------------------------------------
// The long scene: places toured lap after lap.

SimulationOptions LongOptions(int keyframes) {
  SimulationOptions options;
  options.num_keyframes = keyframes;
  return options;
}

// The place whose centre is nearest `xy`.
int NearestPlace(const Scene& scene, const Eigen::Vector2d& xy) {
  int nearest = 0;
  for (size_t p = 1; p < scene.places.size(); ++p) {
    if ((scene.places[p] - xy).norm() < (scene.places[nearest] - xy).norm()) {
      nearest = static_cast<int>(p);
    }
  }
  return nearest;
}

TEST(Simulation, LongSceneHasPlacesOfSeparableObjectsOfEveryType) {
  Scene scene;
  ASSERT_TRUE(MakeScene("long", &scene).ok());
  EXPECT_GE(scene.objects.size(), 20u);
  ASSERT_GE(scene.places.size(), 6u);
  EXPECT_EQ(scene.tour.size(), scene.places.size());
  std::set<std::pair<SymmetryType, int>> types;
  std::map<int, std::vector<Eigen::Vector2d>> by_place;
  for (const SimulatedObject& o : scene.objects) {
    types.insert({o.symmetry, o.order});
    const Eigen::Vector2d xy = o.T_wo.t.head<2>();
    const int place = NearestPlace(scene, xy);
    EXPECT_LT((xy - scene.places[place]).norm(), 1.5) << o.class_name;
    by_place[place].push_back(xy);
  }
  EXPECT_TRUE(types.count({SymmetryType::kAsymmetric, 0}));
  EXPECT_TRUE(types.count({SymmetryType::kDiscrete, 2}));
  EXPECT_TRUE(types.count({SymmetryType::kDiscrete, 4}));
  EXPECT_TRUE(types.count({SymmetryType::kContinuous, 0}));
  // Clusters of 3-5 objects, at least 1.3 m apart; places 6-8 m apart.
  ASSERT_EQ(by_place.size(), scene.places.size());
  for (const auto& [place, xys] : by_place) {
    SCOPED_TRACE(place);
    EXPECT_GE(xys.size(), 3u);
    EXPECT_LE(xys.size(), 5u);
    for (size_t i = 0; i < xys.size(); ++i) {
      for (size_t j = i + 1; j < xys.size(); ++j) {
        EXPECT_GE((xys[i] - xys[j]).norm(), 1.3);
      }
    }
  }
  for (size_t p = 0; p < scene.places.size(); ++p) {
    const int q = scene.tour[(p + 1) % scene.tour.size()];
    const double d = (scene.places[scene.tour[p]] - scene.places[q]).norm();
    EXPECT_GE(d, 6.0);
    EXPECT_LE(d, 8.0);
  }
}

TEST(Simulation, LongSceneDefaultsToTenThousandKeyframesOthersTo72) {
  for (const std::string& name : SceneNames()) {
    SCOPED_TRACE(name);
    Scene scene;
    ASSERT_TRUE(MakeScene(name, &scene).ok());
    if (name == "long") {
      EXPECT_GE(scene.default_num_keyframes, 10000);
    } else {
      EXPECT_EQ(scene.default_num_keyframes, 72);
      EXPECT_TRUE(scene.places.empty());
    }
  }
  EXPECT_EQ(SimulationOptions().num_keyframes, 72);
  // num_keyframes is what Simulate simulates, whatever the scene.
  EXPECT_EQ(MustSimulate("long", LongOptions(300), 1).keyframes.size(), 300u);
}

// Per object, the keyframes that detected it.
std::map<int, std::vector<int>> DetectingKeyframes(
    const SimulatedSequence& seq) {
  std::map<int, std::vector<int>> keyframes;
  for (size_t k = 0; k < seq.detections.size(); ++k) {
    for (const SimulatedDetectionTruth& truth : seq.detections[k]) {
      keyframes[truth.object].push_back(static_cast<int>(k));
    }
  }
  return keyframes;
}

TEST(Simulation, LongRouteRevisitsItsPlaces) {
  const SimulatedSequence seq = MustSimulate("long", LongOptions(400), 2);
  const std::map<int, std::vector<int>> detected = DetectingKeyframes(seq);
  // The first lap sees every object.
  EXPECT_EQ(detected.size(), seq.objects.size());
  // What the first place shows is shown again a lap (about 260 keyframes)
  // later, and not in between.
  std::set<int> first_place;
  for (int k = 0; k < 15; ++k) {
    for (const SimulatedDetectionTruth& truth : seq.detections[k]) {
      first_place.insert(truth.object);
    }
  }
  EXPECT_GE(first_place.size(), 2u);
  for (const int o : first_place) {
    SCOPED_TRACE(o);
    const std::vector<int>& ks = detected.at(o);
    EXPECT_EQ(
        std::count_if(
            ks.begin(), ks.end(), [](int k) { return k >= 60 && k < 200; }),
        0);
    EXPECT_GT(
        std::count_if(ks.begin(), ks.end(), [](int k) { return k >= 200; }), 5);
  }
  // Objects seen in two intervals at least 100 keyframes apart: the first
  // place and the place the first lap reaches last but one.
  int revisited = 0;
  for (const auto& [object, ks] : detected) {
    for (size_t i = 1; i < ks.size(); ++i) {
      if (ks[i] - ks[i - 1] >= 100) {
        ++revisited;
        break;
      }
    }
  }
  EXPECT_GE(revisited, 6);
}

// Over seven laps every object comes back lap after lap: its detections
// fall into at least 4 visits (runs without a gap of 50 keyframes; the
// places next to tour[0] are passed twice in a row, around the U-turn at
// tour[0] between laps, so some of their objects count only 4 or 5).
TEST(Simulation, LongRouteRevisitsEveryObjectManyTimes) {
  const SimulatedSequence seq = MustSimulate("long", LongOptions(2000), 2);
  const std::map<int, std::vector<int>> detected = DetectingKeyframes(seq);
  ASSERT_EQ(detected.size(), seq.objects.size());
  for (const auto& [object, ks] : detected) {
    SCOPED_TRACE(object);
    int visits = 1;
    for (size_t i = 1; i < ks.size(); ++i) {
      if (ks[i] - ks[i - 1] >= 50) ++visits;
    }
    EXPECT_GE(visits, 4);
  }
}

TEST(Simulation, LongRouteIsNotACircleAndMovesInSmallSteps) {
  const SimulationOptions options = LongOptions(400);
  const SimulatedSequence seq = MustSimulate("long", options, 2);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Rigid3d& T : seq.T_wc_true) centroid += T.t;
  centroid /= static_cast<double>(seq.T_wc_true.size());
  double nearest = 1e9;
  double farthest = 0.0;
  for (const Rigid3d& T : seq.T_wc_true) {
    nearest = std::min(nearest, (T.t - centroid).norm());
    farthest = std::max(farthest, (T.t - centroid).norm());
  }
  EXPECT_GT(farthest - nearest, 5.0);  // an orbit: 0
  // Keyframes route_step apart along the path (a chord is shorter), turning
  // at most route_step / r_min = 0.35 / 2.125 rad = 9.4 degrees.
  for (size_t k = 1; k < seq.T_wc_true.size(); ++k) {
    SCOPED_TRACE(k);
    const Rigid3d& a = seq.T_wc_true[k - 1];
    const Rigid3d& b = seq.T_wc_true[k];
    EXPECT_LE((b.t - a.t).norm(), options.route_step + 1e-9);
    EXPECT_GE((b.t - a.t).norm(), 0.9 * options.route_step);
    EXPECT_LE(RotationAngle(a.q, b.q), 9.5 * kDeg);
    EXPECT_EQ(b.t.z(), options.camera_height);
  }
  // Most keyframes see an object.
  int blind = 0;
  for (const auto& truths : seq.detections) blind += truths.empty() ? 1 : 0;
  EXPECT_LT(blind, 400 / 5);
}

TEST(Simulation, LongRouteHasRichAndFeaturelessStretchesWithFewPoints) {
  const SimulationOptions opt = LongOptions(600);
  const SimulatedSequence seq = MustSimulate("long", opt, 3);
  Scene scene;
  ASSERT_TRUE(MakeScene("long", &scene).ok());
  ASSERT_EQ(seq.points_w.size(), scene.places.size() * opt.points_per_place);
  // Each place's wall: a cylinder of place_wall_radius about it, on the side
  // facing the rich bearings [0, pi): y <= the place's y.
  for (size_t i = 0; i < seq.points_w.size(); ++i) {
    const Eigen::Vector2d& c = scene.places[i / opt.points_per_place];
    const Eigen::Vector3d& p = seq.points_w[i];
    EXPECT_NEAR((p.head<2>() - c).norm(), opt.place_wall_radius, 1e-9);
    EXPECT_LE(p.y(), c.y() + 1e-9);
  }
  int rich = 0;
  int observations = 0;
  std::set<int64_t> seen;
  double featureless_yaw = 0.0;
  for (size_t k = 0; k < seq.keyframes.size(); ++k) {
    SCOPED_TRACE(k);
    const KeyframeInput& kf = seq.keyframes[k];
    EXPECT_LE(kf.points.size(), 60u);
    if (!seq.rich[k]) {
      EXPECT_TRUE(kf.points.empty());
      if (k > 0) featureless_yaw += FrontendMotionError(seq, k).yaw;
      continue;
    }
    ++rich;
    observations += static_cast<int>(kf.points.size());
    // One wall at a time: the points of one place.
    std::set<int64_t> places;
    for (const PointObservation& obs : kf.points) {
      places.insert(obs.id / opt.points_per_place);
      seen.insert(obs.id);
    }
    EXPECT_LE(places.size(), 1u);
    if (k > 0) {
      EXPECT_LT(FrontendMotionError(seq, k).rotation,
                kSigmas * opt.rich_sigma_r);
    }
  }
  const int featureless = static_cast<int>(seq.keyframes.size()) - rich;
  EXPECT_GT(rich, 600 / 3);
  EXPECT_GT(featureless, 600 / 3);
  EXPECT_GT(observations, 20 * rich);  // about 30 per rich keyframe
  EXPECT_GT(seen.size(), seq.points_w.size() / 2);
  // The front end drifts by the yaw bias on featureless keyframes only.
  EXPECT_NEAR(featureless_yaw / featureless, opt.yaw_bias, 0.3 * kDeg);
}

TEST(Simulation, LongRouteIsDeterministicAndItsDetectionsMatchTheTruth) {
  const SimulatedSequence seq = MustSimulate("long", LongOptions(300), 4);
  const auto a = Files(seq);
  const auto b = Files(MustSimulate("long", LongOptions(300), 4));
  const auto c = Files(MustSimulate("long", LongOptions(300), 5));
  EXPECT_EQ(a, b);
  EXPECT_NE(a.at("log.jsonl"), c.at("log.jsonl"));
  EXPECT_EQ(a.at("gt_trajectory.tum"), c.at("gt_trajectory.tum"));
  ExpectDetectionsMatchTruth(seq);
}

TEST(Simulation, RouteOptionsAreValidated) {
  SimulatedSequence seq;
  SimulationOptions options = LongOptions(10);
  options.visit_radius_variation = 1.0;
  Status status = Simulate("long", options, 1, &seq);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("visit_radius_variation"));
  options = LongOptions(10);
  options.visit_radius = 4.0;
  status = Simulate("long", options, 1, &seq);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("place_wall_radius"));
  // Circles of 0.4 and 7.6 m about places 7 m apart have no common tangent.
  options.visit_radius_variation = 0.9;
  options.place_wall_radius = 8.0;
  status = Simulate("long", options, 1, &seq);
  ASSERT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("too close"));
}

// ---------------------------------------------------------------------------
// Files.

TEST(Simulation, RgbdFrontEndGivesEveryObservationItsDepth) {
  SimulationOptions opt;
  opt.depth_every_observation = true;
  const SimulatedSequence seq = MustSimulate("disc", opt, 7);
  size_t observations = 0;
  for (size_t k = 0; k < seq.keyframes.size(); ++k) {
    const Rigid3d T_cw = seq.T_wc_true[k].Inverse();
    for (const PointObservation& obs : seq.keyframes[k].points) {
      ASSERT_TRUE(obs.depth.has_value());
      const Eigen::Vector3d p_c =
          T_cw * seq.points_w[static_cast<size_t>(obs.id)];
      EXPECT_NEAR(*obs.depth, p_c.z(), kSigmas * opt.depth_sigma);
      ++observations;
    }
  }
  EXPECT_GT(observations, 1000u);
}

TEST(Simulation, FilesReadBackAndEveryDetectionMapsToAGroundTruthObject) {
  const SimulatedSequence seq = MustSimulate("room", SimulationOptions(), 9);
  const std::string dir = ::testing::TempDir() + "symba_simulation_test_room";
  const Status written = WriteSimulation(seq, dir);
  ASSERT_TRUE(written.ok()) << written.message();

  // The log reads back with LogReader, keyframe for keyframe.
  std::unique_ptr<LogReader> reader;
  Status status = LogReader::Open(dir + "/log.jsonl", &reader);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_TRUE(reader->header().camera.has_value());
  EXPECT_EQ(reader->header().camera->fx, 525.0);
  EXPECT_EQ(reader->header().camera->cy, 239.5);
  std::vector<KeyframeInput> read;
  for (;;) {
    KeyframeInput kf;
    bool end = false;
    status = reader->Next(&kf, &end);
    ASSERT_TRUE(status.ok()) << status.message();
    if (end) break;
    read.push_back(kf);
  }
  ASSERT_EQ(read.size(), seq.keyframes.size());

  // gt_objects.json: the documented shape.
  const nlohmann::json gt =
      nlohmann::json::parse(ReadFile(dir + "/gt_objects.json"));
  ASSERT_EQ(gt.size(), 2u);
  const nlohmann::json& objects = gt.at("objects");
  ASSERT_EQ(objects.size(), seq.objects.size());
  for (size_t i = 0; i < objects.size(); ++i) {
    const nlohmann::json& o = objects[i];
    const SimulatedObject& truth = seq.objects[i];
    EXPECT_EQ(o.at("id").get<int>(), static_cast<int>(i));
    EXPECT_EQ(o.at("class").get<std::string>(), truth.class_name);
    EXPECT_EQ(o.at("symmetry").get<std::string>(), ToString(truth.symmetry));
    EXPECT_EQ(o.at("order").get<int>(),
              truth.symmetry == SymmetryType::kDiscrete ? truth.order : 0);
    const std::vector<double> t = o.at("pose").at("t");
    const std::vector<double> q = o.at("pose").at("q");
    ASSERT_EQ(t.size(), 3u);
    ASSERT_EQ(q.size(), 4u);
    const Eigen::Quaterniond q_wo(q[3], q[0], q[1], q[2]);
    EXPECT_LT(RotationAngle(q_wo, truth.T_wo.q), 1e-12);
    EXPECT_LT((Eigen::Vector3d(t[0], t[1], t[2]) - truth.T_wo.t).norm(), 1e-12);
    if (truth.symmetry == SymmetryType::kAsymmetric) {
      EXPECT_FALSE(o.contains("axis"));
      EXPECT_FALSE(o.contains("axis_o"));
    } else {
      const std::vector<double> a_o = o.at("axis_o");
      const std::vector<double> a_w = o.at("axis");
      const Eigen::Vector3d axis_o(a_o[0], a_o[1], a_o[2]);
      EXPECT_LT((axis_o - truth.axis_o).norm(), 1e-12);
      EXPECT_LT(
          (Eigen::Vector3d(a_w[0], a_w[1], a_w[2]) - q_wo * axis_o).norm(),
          1e-12);
    }
  }
  const nlohmann::json& detections = gt.at("detections");
  size_t num_detections = 0;
  for (size_t k = 0; k < read.size(); ++k) {
    EXPECT_EQ(read[k].id, seq.keyframes[k].id);
    EXPECT_EQ(read[k].timestamp, seq.keyframes[k].timestamp);
    EXPECT_EQ(read[k].points.size(), seq.keyframes[k].points.size());
    ASSERT_EQ(read[k].detections.size(), seq.keyframes[k].detections.size());
    for (size_t d = 0; d < read[k].detections.size(); ++d) {
      const DetectionInput& det = read[k].detections[d];
      ASSERT_TRUE(detections.contains(det.id)) << det.id;
      const int object = detections.at(det.id).get<int>();
      EXPECT_EQ(object, seq.detections[k][d].object);
      EXPECT_EQ(objects.at(object).at("class").get<std::string>(),
                det.class_name);
      // Exact round trip of the hypotheses.
      const DetectionInput& orig = seq.keyframes[k].detections[d];
      ASSERT_EQ(det.hypotheses.size(), orig.hypotheses.size());
      for (size_t j = 0; j < det.hypotheses.size(); ++j) {
        EXPECT_EQ(det.hypotheses[j].T_co.t, orig.hypotheses[j].T_co.t);
        EXPECT_EQ(det.hypotheses[j].weight, orig.hypotheses[j].weight);
      }
      ++num_detections;
    }
  }
  EXPECT_EQ(detections.size(), num_detections);

  // gt_trajectory.tum: one line per keyframe with the log's timestamps.
  std::istringstream tum(ReadFile(dir + "/gt_trajectory.tum"));
  std::string line;
  size_t k = 0;
  while (std::getline(tum, line)) {
    ASSERT_LT(k, seq.keyframes.size());
    std::istringstream fields(line);
    double v[8];
    for (double& x : v) ASSERT_TRUE(fields >> x) << line;
    EXPECT_EQ(v[0], seq.keyframes[k].timestamp);
    EXPECT_LT((Eigen::Vector3d(v[1], v[2], v[3]) - seq.T_wc_true[k].t).norm(),
              1e-12);
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    EXPECT_LT(RotationAngle(q, seq.T_wc_true[k].q), 1e-9);
    ++k;
  }
  EXPECT_EQ(k, seq.keyframes.size());
}

TEST(Simulation, WritingIntoAMissingParentFailsAndLeavesNothing) {
  const SimulatedSequence seq = MustSimulate("disc", SimulationOptions(), 1);
  const std::string dir =
      ::testing::TempDir() + "symba_simulation_no_such_parent/out";
  EXPECT_FALSE(WriteSimulation(seq, dir).ok());
  EXPECT_FALSE(std::ifstream(dir + "/log.jsonl").good());
}

}  // namespace
}  // namespace symba
