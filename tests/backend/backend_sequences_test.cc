// Acceptance tests of the backend (project issue 4) on scripted sequences
// (tests/test_support/scripted_sequence.h): a camera orbits symmetric
// objects; the front end is accurate on the feature-rich half of the orbit
// and drifts in yaw (1.5 deg per keyframe) on the featureless half. symba
// must keep one map object per real object and pull the trajectory back; the
// baselines (sh, mh), which associate by the full 6-DoF pose, fragment when
// the detector's modes flip.
//
// Where the tolerances come from (measured over seeds 1-16 of these
// sequences with the default BackendOptions, at commit 3af1f64 + this file):
//   - rich half: only a point's first observation carries a depth (a 1 %
//     depth factor), later ones are bearings, and the front end's relative
//     motion enters with the default 5 cm / 0.02 rad although it is accurate
//     to 0.5 cm here; even without any object the rich half alone drifts to
//     0.04-0.12 m RMSE (max up to 0.17 m) over its 20 keyframes;
//   - featureless half: one detection fixes the camera in the object frame
//     to about |t_co| * sigma_r / 2 = 2.8 m * 3 deg / 2 = 7 cm per axis (the
//     SE(3) logarithm of Eq. 14 halves the lever arm), on top of the error of
//     the object itself, which inherits the rich half's drift;
//   - camera rotation: a camera turned about its own centre leaves the
//     translation rows of Eq. 14 unchanged (its position in the object frame
//     does not move), so only the rotation rows (sigma_r = 0.05 rad) resist
//     the biased front end (0.02 rad, 1.5 deg per keyframe), and keyframes
//     leave the window before the pull has settled: a few degrees remain.
// symba reaches 0.06-0.17 m RMSE and 0.11-0.32 m max in position, 0.9-3.8
// deg RMSE and 2.1-9.0 deg max in rotation; the tests allow 0.20 m / 0.40 m
// and 5 deg / 12 deg, against a front end at about 0.5 m / 1.4 m and 13 deg
// / 30 deg (asserted too, so the tests cannot pass on a tame sequence). The
// structural assertions (object counts, types, modes, assignments) hold on
// every one of those seeds.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "symba/backend/backend.h"
#include "symba/geometry/angle.h"
#include "symba/geometry/so3.h"
#include "test_support/scripted_sequence.h"

namespace symba {
namespace {

using testing::GenerateScriptedSequence;
using ::testing::HasSubstr;
using testing::kDegree;
using testing::ScriptedObject;
using testing::ScriptedSequence;
using testing::ScriptedSequenceSpec;

constexpr double kRmseTolerance = 0.20;      // m, see the top
constexpr double kMaxErrorTolerance = 0.40;  // m
constexpr double kRotationRmseTolerance = 5.0 * kDegree;
constexpr double kRotationMaxTolerance = 12.0 * kDegree;
constexpr double kFrontendMinRmse = 0.35;  // m: the drift is real
constexpr double kFrontendMinRotationRmse = 8.0 * kDegree;
constexpr double kObjectPositionTolerance = 0.15;  // m: the rich half's drift
// Axis and mode rotations: each is averaged over tens of detections of 3 deg
// noise per axis, but carries the camera rotation errors of the views that
// fixed it (about 1 deg on the rich half, a few on the featureless half): 5
// deg for the axis, 8 deg for a mode's full rotation (axis and twist), both
// far below the 90-180 deg between modes.
constexpr double kAxisTolerance = 5.0 * kDegree;
constexpr double kModeTolerance = 8.0 * kDegree;

struct PositionError {
  double rmse = 0.0;           // m
  double max = 0.0;            // m
  double rotation_rmse = 0.0;  // rad
  double rotation_max = 0.0;   // rad
};

PositionError Positions(const std::vector<Rigid3d>& truth,
                        const std::vector<Rigid3d>& estimate) {
  PositionError e;
  for (size_t k = 0; k < truth.size(); ++k) {
    const double d = (truth[k].t - estimate[k].t).norm();
    e.rmse += d * d;
    e.max = std::max(e.max, d);
    const double r = truth[k].q.angularDistance(estimate[k].q);
    e.rotation_rmse += r * r;
    e.rotation_max = std::max(e.rotation_max, r);
  }
  e.rmse = std::sqrt(e.rmse / static_cast<double>(truth.size()));
  e.rotation_rmse =
      std::sqrt(e.rotation_rmse / static_cast<double>(truth.size()));
  return e;
}

std::vector<Rigid3d> EstimatedPoses(const Backend& backend) {
  std::vector<Rigid3d> poses;
  for (const KeyframeEstimate& kf : backend.Keyframes()) {
    poses.push_back(kf.T_wc);
  }
  return poses;
}

std::vector<Rigid3d> FrontendPoses(const ScriptedSequence& seq) {
  std::vector<Rigid3d> poses;
  for (const KeyframeInput& kf : seq.keyframes) poses.push_back(*kf.T_wc);
  return poses;
}

// Feeds the sequence keyframe by keyframe, with a window solve after each
// (as a SLAM system runs it). With `until_objects` > 0 it stops as soon as
// the map holds that many objects; `fed` (optional) receives the number of
// keyframes fed.
void RunSequence(const ScriptedSequence& seq,
                 const BackendOptions& options,
                 std::unique_ptr<Backend>* backend,
                 size_t until_objects = 0,
                 size_t* fed = nullptr) {
  Status status = Backend::Create(options, seq.intrinsics, {}, backend);
  ASSERT_TRUE(status.ok()) << status.message();
  for (size_t k = 0; k < seq.keyframes.size(); ++k) {
    status = (*backend)->AddKeyframe(seq.keyframes[k]);
    ASSERT_TRUE(status.ok()) << status.message();
    status = (*backend)->OptimizeWindow();
    ASSERT_TRUE(status.ok()) << status.message();
    if (fed != nullptr) *fed = k + 1;
    if (until_objects > 0 && (*backend)->Objects().size() >= until_objects) {
      return;
    }
  }
}

// Angle between two axes up to sign.
double AxisAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
}

Eigen::Quaterniond Rot(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// The scene of tests 1 and 2: one object at the centre, seen in a loop of
// 40 keyframes; each view of a discrete object shows a random subset of its
// modes (one mode: read as asymmetric) and the highest-weight hypothesis
// belongs to a random visible mode. The detector reports its rotation noise
// (3 deg per axis, about 5 deg in all: sigma_r = 0.05 rad).
ScriptedSequenceSpec OrbitSpec(const ScriptedObject& object) {
  ScriptedSequenceSpec spec;
  spec.objects = {object};
  spec.min_visible_modes = 1;
  spec.max_visible_modes = object.order;
  spec.detection_sigma_r = 0.05;
  spec.seed = 1;
  return spec;
}

ScriptedObject Table(SymmetryType symmetry, int order) {
  ScriptedObject table;
  table.class_name = "table";
  table.symmetry = symmetry;
  table.order = order;
  table.axis_o = Eigen::Vector3d::UnitZ();
  table.T_wo = Rigid3d(Rot(Eigen::Vector3d::UnitZ(), 0.3),
                       Eigen::Vector3d(0.1, -0.05, 0.0));
  return table;
}

// symba: one map object of the right type whose axis, position and (for a
// discrete object) every mode match the truth, and the keyframes within the
// tolerances. sh and mh: more than one map object for the one table (fed
// only until they fragment: the rest would not change that, and the
// sanitizer build is slow).
void ExpectSymbaTracksBaselinesFragment(const ScriptedSequenceSpec& spec,
                                        const char* name) {
  const ScriptedSequence seq = GenerateScriptedSequence(spec);
  const ScriptedObject& truth = spec.objects.front();
  const PositionError frontend = Positions(seq.T_wc_true, FrontendPoses(seq));
  EXPECT_GT(frontend.rmse, kFrontendMinRmse);
  EXPECT_GT(frontend.rotation_rmse, kFrontendMinRotationRmse);

  for (Method method : {Method::kMultiHypothesis, Method::kSingleHypothesis}) {
    SCOPED_TRACE(MethodName(method));
    BackendOptions options;
    options.method = method;
    std::unique_ptr<Backend> backend;
    size_t fed = 0;
    ASSERT_NO_FATAL_FAILURE(RunSequence(seq, options, &backend, 2, &fed));
    // A detection whose pose contradicts the map makes a new tentative
    // object; if others agree with it, it is a second map object, else it
    // is dropped as an outlier. Either way the baseline cannot keep the
    // table's detections in one object.
    const size_t rejected = std::count_if(
        backend->Assignments().begin(),
        backend->Assignments().end(),
        [](const DetectionAssignment& a) { return a.object < 0; });
    std::printf(
        "[ %s ] %-5s %zu objects, %zu detections rejected after %zu of %zu "
        "keyframes\n",
        name,
        MethodName(method),
        backend->Objects().size(),
        rejected,
        fed,
        seq.keyframes.size());
    EXPECT_TRUE(backend->Objects().size() > 1u || rejected > 0);
  }

  std::unique_ptr<Backend> backend;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, BackendOptions(), &backend));
  const std::vector<MapObjectEstimate> objects = backend->Objects();
  const PositionError error =
      Positions(seq.T_wc_true, EstimatedPoses(*backend));
  std::printf(
      "[ %s ] symba %zu objects, keyframe RMSE %.3f m, max %.3f m, rotation "
      "RMSE %.1f deg, max %.1f deg (front end %.3f m / %.3f m, %.1f deg / "
      "%.1f deg)\n",
      name,
      objects.size(),
      error.rmse,
      error.max,
      error.rotation_rmse / kDegree,
      error.rotation_max / kDegree,
      frontend.rmse,
      frontend.max,
      frontend.rotation_rmse / kDegree,
      frontend.rotation_max / kDegree);
  ASSERT_EQ(objects.size(), 1u);
  const MapObjectEstimate& object = objects.front();
  EXPECT_EQ(object.symmetry, truth.symmetry);
  EXPECT_EQ(object.observations,
            static_cast<int>(backend->Assignments().size()));
  EXPECT_LT((object.t_wo - truth.T_wo.t).norm(), kObjectPositionTolerance);
  EXPECT_LT(AxisAngle(object.axis_w, truth.T_wo.q * truth.axis_o),
            kAxisTolerance);
  if (truth.symmetry == SymmetryType::kDiscrete) {
    // One angle per mode, each near a distinct true mode.
    EXPECT_EQ(static_cast<int>(object.angles.size()), truth.order);
    std::set<int> modes;
    for (const Rigid3d& pose : object.poses) {
      for (int m = 0; m < truth.order; ++m) {
        const Eigen::Quaterniond R_wo_m =
            truth.T_wo.q * Rot(truth.axis_o, kTwoPi * m / truth.order);
        if (pose.q.angularDistance(R_wo_m) < kModeTolerance) {
          modes.insert(m);
        }
      }
    }
    EXPECT_EQ(static_cast<int>(modes.size()), truth.order);
  }
  EXPECT_LT(error.rmse, kRmseTolerance);
  EXPECT_LT(error.max, kMaxErrorTolerance);
  EXPECT_LT(error.rotation_rmse, kRotationRmseTolerance);
  EXPECT_LT(error.rotation_max, kRotationMaxTolerance);
}

// ---------------------------------------------------------------------------
// A detector that declares no noise (the paper's setting): the spread of
// its 30 hypotheses about their modes is its noise (docs/backend.md "Real
// detectors", 4). Test 1's orbit with no sigma on any detection: symba
// pulls the drifting camera back within test 1's tolerances, and reports
// the scatter within 15 % of the noise the hypotheses were drawn with.
// Without the scatter (scatter_min_hypotheses 0) the same detections are
// weighed at the uncalibrated floor and the camera stays near the front
// end's.
TEST(BackendSequences, AnUndeclaredDetectorCorrectsTheCameraByItsScatter) {
  ScriptedSequenceSpec spec = OrbitSpec(Table(SymmetryType::kDiscrete, 2));
  spec.detection_sigma_r.reset();
  const ScriptedSequence seq = GenerateScriptedSequence(spec);
  const PositionError frontend = Positions(seq.T_wc_true, FrontendPoses(seq));
  ASSERT_GT(frontend.rmse, kFrontendMinRmse);

  std::unique_ptr<Backend> backend;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, BackendOptions(), &backend));
  const PositionError error =
      Positions(seq.T_wc_true, EstimatedPoses(*backend));
  BackendOptions floor;
  floor.scatter_min_hypotheses = 0;
  std::unique_ptr<Backend> floored;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, floor, &floored));
  const PositionError floored_error =
      Positions(seq.T_wc_true, EstimatedPoses(*floored));
  std::printf(
      "[ undeclared ] keyframe RMSE %.3f m by the scatter, %.3f m at the "
      "floor, front end %.3f m\n",
      error.rmse,
      floored_error.rmse,
      frontend.rmse);
  EXPECT_EQ(backend->Objects().size(), 1u);
  EXPECT_LT(error.rmse, kRmseTolerance);
  EXPECT_LT(error.rmse, 0.5 * frontend.rmse);
  EXPECT_GT(floored_error.rmse, 0.8 * frontend.rmse);

  const std::vector<ClassNoiseEstimate> noise = backend->Noise();
  ASSERT_EQ(noise.size(), 1u);
  const ClassNoiseEstimate::Scatter& scatter = noise.front().scatter;
  EXPECT_EQ(scatter.detections,
            static_cast<int>(backend->Assignments().size()));
  ASSERT_TRUE(scatter.sigma_t && scatter.sigma_r);
  EXPECT_NEAR(
      *scatter.sigma_t, spec.translation_sigma, 0.15 * spec.translation_sigma);
  EXPECT_NEAR(
      *scatter.sigma_r, spec.rotation_sigma, 0.15 * spec.rotation_sigma);
  EXPECT_EQ(floored->Noise().front().scatter.detections, 0);
  // What the edges use: every edge of the 2-fold table (one per cluster
  // of a detection, so at least one per detection) by its detection's
  // scatter (held to the class's frame-to-frame noise), about the noise
  // the hypotheses were drawn with; at the floor, weight_sigma_* itself.
  const ClassNoiseEstimate::Weights& weights = noise.front().weights;
  EXPECT_GE(weights.scatter, backend->Objects().front().observations);
  EXPECT_EQ(weights.declared + weights.unstated, 0);
  ASSERT_TRUE(weights.sigma_t && weights.sigma_r);
  EXPECT_NEAR(
      *weights.sigma_t, spec.translation_sigma, 0.15 * spec.translation_sigma);
  EXPECT_NEAR(
      *weights.sigma_r, spec.rotation_sigma, 0.15 * spec.rotation_sigma);
  const ClassNoiseEstimate at_floor = floored->Noise().front();
  EXPECT_GE(at_floor.weights.unstated, floored->Objects().front().observations);
  EXPECT_EQ(at_floor.weights.declared + at_floor.weights.scatter, 0);
  EXPECT_EQ(at_floor.weights.sigma_t, at_floor.weight_sigma_t);
  EXPECT_EQ(at_floor.weights.sigma_r, at_floor.weight_sigma_r);

  // The baselines are weighed alike (they categorise only for the scatter).
  BackendOptions mh;
  mh.method = Method::kMultiHypothesis;
  std::unique_ptr<Backend> baseline;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, mh, &baseline));
  EXPECT_EQ(baseline->Noise().front().scatter.detections,
            static_cast<int>(baseline->Assignments().size()));
}

// ---------------------------------------------------------------------------
// A detector that claims 1 cm and 0.01 rad but is off by about 10 cm and
// 0.1 rad (6 cm and 0.06 rad per axis, white, one pose per detection) on an
// accurate front end (odometry only, its noise stated truthfully, no map
// points): the claims are a prior the data overrules (docs/backend.md "Real
// detectors", 4). Until the claim scale is known (noise_min_samples pairs)
// the gates in the claimed noise keep the detections off the map; then the
// box is mapped once, the camera stays within 10 % of the front end's
// keyframe RMSE, and the claim scale is within 15 % of the truth (6 over
// the 1 cm and 0.01 rad claimed). Believed as claimed
// (claimed_noise_tolerance too large to act), no detection ever joins a
// confirmed object: the map stays empty.
// The share of the detections assigned to the map object that has most.
double LargestObjectShare(const Backend& backend) {
  size_t largest = 0;
  for (const MapObjectEstimate& object : backend.Objects()) {
    largest = std::max<size_t>(largest,
                               std::count_if(backend.Assignments().begin(),
                                             backend.Assignments().end(),
                                             [&](const DetectionAssignment& a) {
                                               return a.object == object.id;
                                             }));
  }
  return static_cast<double>(largest) /
         static_cast<double>(backend.Assignments().size());
}

// One asymmetric box seen from an accurate front end (odometry only, its
// noise stated truthfully) by a single-pose detector that claims 1 cm and
// 0.01 rad but is off by 6 cm and 0.06 rad per axis (white).
ScriptedSequence OverclaimingBoxSequence() {
  ScriptedObject box = Table(SymmetryType::kAsymmetric, 1);
  box.class_name = "box";
  ScriptedSequenceSpec spec = OrbitSpec(box);
  spec.num_keyframes = 120;
  spec.num_points = 0;
  spec.yaw_bias = 0.0;
  spec.yaw_noise = 0.0;
  spec.with_frontend_pose = false;
  spec.with_odometry = true;
  spec.odometry_sigma_t = spec.odometry_noise_t;
  spec.odometry_sigma_r = spec.odometry_noise_r;
  spec.num_hypotheses = 1;
  spec.outlier_fraction = 0.0;
  spec.translation_sigma = 0.06;
  spec.rotation_sigma = 0.06;
  spec.detection_sigma_t = 0.01;
  spec.detection_sigma_r = 0.01;
  return GenerateScriptedSequence(spec);
}

TEST(BackendSequences, ADetectorThatClaimsTooLittleNoiseDoesNotTakeTheCamera) {
  const ScriptedSequence seq = OverclaimingBoxSequence();
  // The front end: the first pose chained with the odometry.
  std::vector<Rigid3d> frontend_poses = {*seq.keyframes.front().T_wc};
  for (size_t k = 1; k < seq.keyframes.size(); ++k) {
    frontend_poses.push_back(frontend_poses.back() *
                             seq.keyframes[k].odometry->T_prev_cur);
  }
  const double frontend = Positions(seq.T_wc_true, frontend_poses).rmse;
  const auto run = [&seq](const BackendOptions& options,
                          std::unique_ptr<Backend>* backend) {
    RunSequence(seq, options, backend);
    return Positions(seq.T_wc_true, EstimatedPoses(**backend)).rmse;
  };

  std::unique_ptr<Backend> backend;
  const double tested = run(BackendOptions(), &backend);
  BackendOptions believing;
  believing.claimed_noise_tolerance = 1e6;
  std::unique_ptr<Backend> believer;
  const double believed = run(believing, &believer);
  std::printf(
      "[ claims ] keyframe RMSE %.4f m with the claims tested, %.4f m "
      "believed, front end %.4f m\n",
      tested,
      believed,
      frontend);
  EXPECT_EQ(backend->Objects().size(), 1u);
  EXPECT_LT(tested, 1.1 * frontend);
  // Believed, the gates in the claimed noise refuse nearly every detection:
  // no map object is confirmed.
  std::printf(
      "[ claims ] share of the detections on the box %.2f tested, %.2f "
      "believed\n",
      LargestObjectShare(*backend),
      LargestObjectShare(*believer));
  EXPECT_GT(LargestObjectShare(*backend), 0.6);
  EXPECT_LT(LargestObjectShare(*believer), 0.2);

  const std::vector<ClassNoiseEstimate> noise = backend->Noise();
  ASSERT_EQ(noise.size(), 1u);
  const ClassNoiseEstimate::Claims& claims = noise.front().claims;
  ASSERT_TRUE(claims.scale_t && claims.scale_r);
  EXPECT_NEAR(*claims.scale_t, 6.0, 0.15 * 6.0);
  EXPECT_NEAR(*claims.scale_r, 6.0, 0.15 * 6.0);
  // The edges were built with it (within noise_update_ratio): each of the
  // box's edges (one per detection) weighs its declared 1 cm and 0.01 rad
  // times the factors.
  EXPECT_NEAR(claims.factor_t, *claims.scale_t, 0.25 * *claims.scale_t);
  const ClassNoiseEstimate::Weights& weights = noise.front().weights;
  EXPECT_EQ(weights.declared, backend->Objects().front().observations);
  EXPECT_EQ(weights.scatter + weights.unstated, 0);
  ASSERT_TRUE(weights.sigma_t && weights.sigma_r);
  EXPECT_DOUBLE_EQ(*weights.sigma_t, 0.01 * claims.factor_t);
  EXPECT_DOUBLE_EQ(*weights.sigma_r, 0.01 * claims.factor_r);
}

// The share of the detections of keyframes [first, first + count) of a run
// from `map` (keyframe `first` placed by the saving run's last estimate and
// the odometry, the rest by odometry) that went to a loaded object.
double ShareOnLoadedObjects(const ScriptedSequence& seq,
                            const SavedMap& map,
                            const Rigid3d& last_of_first,
                            size_t first,
                            size_t count) {
  std::unique_ptr<Backend> backend;
  EXPECT_TRUE(
      Backend::Create(BackendOptions(), seq.intrinsics, {}, &backend).ok());
  EXPECT_TRUE(backend->LoadMap(map).ok());
  std::set<ObjectId> loaded;
  for (const MapObjectEstimate& o : map.objects) loaded.insert(o.id);
  int detections = 0;
  int on_loaded = 0;
  for (size_t k = first; k < first + count; ++k) {
    KeyframeInput keyframe = seq.keyframes[k];
    if (k == first) {
      keyframe.T_wc = last_of_first * keyframe.odometry->T_prev_cur;
      keyframe.odometry.reset();
    }
    std::vector<DetectionAssignment> assignments;
    EXPECT_TRUE(backend->AddKeyframe(keyframe, &assignments).ok());
    EXPECT_TRUE(backend->OptimizeWindow().ok());
    for (const DetectionAssignment& a : assignments) {
      ++detections;
      on_loaded += static_cast<int>(loaded.count(a.object));
    }
  }
  return detections == 0
             ? 0.0
             : static_cast<double>(on_loaded) / static_cast<double>(detections);
}

// A map keeps the claim factors its run learned (docs/map-format.md): a run
// from it weighs the overclaiming detector's claims times them from its
// first keyframe, where a run that has to learn them again believes the
// claims until it has noise_min_samples pairs, and its gates refuse the
// detections meanwhile.
TEST(BackendSequences, AMapKeepsTheClaimFactorsItsRunLearned) {
  const ScriptedSequence seq = OverclaimingBoxSequence();
  const size_t half = seq.keyframes.size() / 2;
  ScriptedSequence first_half = seq;
  first_half.keyframes.resize(half);
  std::unique_ptr<Backend> before;
  ASSERT_NO_FATAL_FAILURE(RunSequence(first_half, BackendOptions(), &before));
  SavedMap map;
  ASSERT_TRUE(before->SaveMap(&map).ok());
  ASSERT_EQ(map.objects.size(), 1u);
  ASSERT_EQ(map.noise.size(), 1u);
  ASSERT_TRUE(map.noise[0].claim_factor_t && map.noise[0].claim_factor_r);
  EXPECT_GT(*map.noise[0].claim_factor_t, 3.0);
  EXPECT_GT(*map.noise[0].claim_factor_r, 3.0);
  const Rigid3d last_of_first = before->Keyframes().back().T_wc;

  SavedMap unlearned = map;
  unlearned.noise[0].claim_factor_t.reset();
  unlearned.noise[0].claim_factor_r.reset();
  const size_t count = 15;
  const double kept =
      ShareOnLoadedObjects(seq, map, last_of_first, half, count);
  const double relearned =
      ShareOnLoadedObjects(seq, unlearned, last_of_first, half, count);
  std::printf(
      "[ claims ] share of the first %zu keyframes' detections on the loaded "
      "box: %.2f with the map's claim factors, %.2f without\n",
      count,
      kept,
      relearned);
  EXPECT_GT(kept, 0.8);
  EXPECT_LT(relearned, 0.4);
}

// The keyframe position RMSE of `poses` against the truth over keyframes
// [begin, end).
double RangeRmse(const ScriptedSequence& seq,
                 const std::vector<Rigid3d>& poses,
                 size_t begin,
                 size_t end) {
  return Positions(
             std::vector<Rigid3d>(seq.T_wc_true.begin() + begin,
                                  seq.T_wc_true.begin() + end),
             std::vector<Rigid3d>(poses.begin() + begin, poses.begin() + end))
      .rmse;
}

// A sequence whose objects are out of view on keyframes [hidden_from,
// seen_again), replayed with default options: the backend, the estimated
// and the front end's poses.
struct HiddenRun {
  ScriptedSequence seq;
  std::unique_ptr<Backend> backend;
  std::vector<Rigid3d> estimated;
  std::vector<Rigid3d> frontend_poses;
};

void RunWithObjectsHidden(const ScriptedSequenceSpec& spec,
                          size_t hidden_from,
                          size_t seen_again,
                          HiddenRun* run) {
  run->seq = GenerateScriptedSequence(spec);
  for (size_t k = hidden_from; k < seen_again; ++k) {
    run->seq.keyframes[k].detections.clear();
  }
  ASSERT_NO_FATAL_FAILURE(
      RunSequence(run->seq, BackendOptions(), &run->backend));
  run->estimated = EstimatedPoses(*run->backend);
  run->frontend_poses = FrontendPoses(run->seq);
}

// ---------------------------------------------------------------------------
// A static object seen again pulls a drifting front end back. Test 1's
// orbit with a milder yaw bias (0.3 deg per featureless keyframe), and the
// table hidden on keyframes 20-34 of the featureless half: the front end
// drifts unseen, then the table is seen again on keyframes 35-39. Over those
// keyframes symba's camera is less than half the front end's error, for a
// detector that declares its noise and for one that returns hypotheses
// without a sigma (weighed by their scatter); each keeps one map object.
TEST(BackendSequences, ADriftingFrontEndIsPulledBackByAnObjectSeenAgain) {
  ScriptedSequenceSpec spec = OrbitSpec(Table(SymmetryType::kDiscrete, 2));
  spec.yaw_bias = 0.3 * kDegree;
  constexpr size_t kHiddenFrom = 20;
  constexpr size_t kSeenAgain = 35;
  for (const bool declared : {true, false}) {
    if (!declared) spec.detection_sigma_r.reset();
    HiddenRun run;
    ASSERT_NO_FATAL_FAILURE(
        RunWithObjectsHidden(spec, kHiddenFrom, kSeenAgain, &run));
    const ScriptedSequence& seq = run.seq;
    const Backend* backend = run.backend.get();
    const std::vector<Rigid3d>& estimated = run.estimated;
    const std::vector<Rigid3d>& frontend_poses = run.frontend_poses;
    const size_t end = seq.keyframes.size();
    const double frontend = RangeRmse(seq, frontend_poses, kSeenAgain, end);
    const double camera = RangeRmse(seq, estimated, kSeenAgain, end);
    std::printf(
        "[ seen again ] %s: camera %.3f m, front end %.3f m over keyframes "
        "%zu-%zu\n",
        declared ? "declared" : "undeclared",
        camera,
        frontend,
        kSeenAgain,
        seq.keyframes.size() - 1);
    EXPECT_GT(frontend, 0.1) << declared;  // the drift is real
    EXPECT_LT(camera, 0.5 * frontend) << declared;
    EXPECT_EQ(backend->Objects().size(), 1u) << declared;
  }
}

// ---------------------------------------------------------------------------
// detection_errors (docs/backend.md "Detection errors"). The scripted
// detector draws each hypothesis' position and rotation errors independently
// (2 cm and 3 deg per axis) and declares them. Read as the noise of the log
// error (the default), a rotation error is taken to swing the position with
// it, so the bearing to the object counts for as little as the rotation;
// read as independent, the bearing counts at the position's noise and ties
// the camera's direction to the object. Keyframe RMSE over seeds 1-4, mean:
// the asymmetric box 0.0419 -> 0.0387 m (one seed of four worse: 0.0373 ->
// 0.0394), the two-fold table 0.0495 -> 0.0305 m (every seed better).
TEST(BackendSequences, IndependentDetectionErrorsTieTheCameraToTheBearing) {
  ScriptedObject box = Table(SymmetryType::kAsymmetric, 1);
  box.class_name = "box";
  for (const ScriptedObject& object :
       {box, Table(SymmetryType::kDiscrete, 2)}) {
    double log_sum = 0.0;
    double independent_sum = 0.0;
    for (const unsigned seed : {1u, 2u, 3u, 4u}) {
      ScriptedSequenceSpec spec = OrbitSpec(object);
      spec.detection_sigma_t = spec.translation_sigma;
      spec.seed = seed;
      const ScriptedSequence seq = GenerateScriptedSequence(spec);
      BackendOptions independent;
      independent.detection_errors = DetectionErrors::kIndependent;
      std::unique_ptr<Backend> log_backend;
      std::unique_ptr<Backend> independent_backend;
      ASSERT_NO_FATAL_FAILURE(RunSequence(seq, BackendOptions(), &log_backend));
      ASSERT_NO_FATAL_FAILURE(
          RunSequence(seq, independent, &independent_backend));
      const double log_rmse =
          Positions(seq.T_wc_true, EstimatedPoses(*log_backend)).rmse;
      const double independent_rmse =
          Positions(seq.T_wc_true, EstimatedPoses(*independent_backend)).rmse;
      std::printf(
          "[ detection errors ] %s seed %u: log %.4f m, independent "
          "%.4f m\n",
          ToString(object.symmetry),
          seed,
          log_rmse,
          independent_rmse);
      EXPECT_EQ(log_backend->Objects().size(), 1u) << seed;
      EXPECT_EQ(independent_backend->Objects().size(), 1u) << seed;
      log_sum += log_rmse;
      independent_sum += independent_rmse;
    }
    EXPECT_LT(independent_sum, 0.95 * log_sum) << ToString(object.symmetry);
  }
}

// ---------------------------------------------------------------------------
// A place revisited a little off is associated again, without a loop
// closure: the position gate grows with the camera's uncertainty since the
// place was last seen (the stated motion variance summed over the steps
// since; docs/backend.md "Real detectors", 2). The orbit with odometry
// stated at 1 cm / 0.01 rad per step and a yaw bias of 0.7 deg per
// featureless keyframe, the table hidden on keyframes 20-34: seen again,
// the front end is 0.39-0.47 m off and the table's detections lie beyond
// the gate of one step of odometry (with that gate, seeds 1-3, 6 and 7
// mapped the table twice and left the camera where the front end put it,
// 0.49-0.59 m). Where the table was last seen before the window, the
// keyframe graph then moves the past as a loop closure would (seeds 1-3, 6
// and 7): the keyframes of the hidden stretch end at about half the front
// end's error (0.08-0.11 m against 0.17-0.22 m). Seed 5 is left out: its
// front end is 0.63 m off at the revisit, beyond gate_position.
TEST(BackendSequences, APlaceRevisitedALittleOffIsAssociatedAgain) {
  ScriptedSequenceSpec spec = OrbitSpec(Table(SymmetryType::kDiscrete, 2));
  spec.with_odometry = true;
  spec.odometry_sigma_t = 0.01;
  spec.odometry_sigma_r = 0.01;
  spec.yaw_bias = 0.7 * kDegree;
  constexpr size_t kHiddenFrom = 20;
  constexpr size_t kSeenAgain = 35;
  for (const int seed : {1, 2, 3, 4, 6, 7, 8}) {
    spec.seed = seed;
    HiddenRun run;
    ASSERT_NO_FATAL_FAILURE(
        RunWithObjectsHidden(spec, kHiddenFrom, kSeenAgain, &run));
    const ScriptedSequence& seq = run.seq;
    const Backend* backend = run.backend.get();
    const std::vector<Rigid3d>& estimated = run.estimated;
    const std::vector<Rigid3d>& frontend_poses = run.frontend_poses;
    const size_t end = seq.keyframes.size();
    const double frontend = RangeRmse(seq, frontend_poses, kSeenAgain, end);
    const double camera = RangeRmse(seq, estimated, kSeenAgain, end);
    const double off =
        (frontend_poses[kSeenAgain].t - seq.T_wc_true[kSeenAgain].t).norm();
    // The stretch the table was hidden for: its keyframes that left the
    // window before the revisit move with the keyframe graph.
    const double hidden = RangeRmse(seq, estimated, kHiddenFrom, kSeenAgain);
    const double hidden_frontend =
        RangeRmse(seq, frontend_poses, kHiddenFrom, kSeenAgain);
    std::printf(
        "[ revisited ] seed %d: front end %.3f m off at the revisit; camera "
        "%.3f m, front end %.3f m over keyframes %zu-%zu; %.3f m and %.3f m "
        "while hidden; %d revisit moved the past\n",
        seed,
        off,
        camera,
        frontend,
        kSeenAgain,
        seq.keyframes.size() - 1,
        hidden,
        hidden_frontend,
        backend->Statistics().revisits_moved_past);
    EXPECT_GT(off, 0.35) << seed;  // beyond one step's gate
    EXPECT_EQ(backend->Objects().size(), 1u) << seed;
    EXPECT_EQ(backend->Statistics().loop_closures, 0) << seed;
    EXPECT_LT(camera, 0.3 * frontend) << seed;
    EXPECT_LT(hidden, 0.6 * hidden_frontend) << seed;
    // Seeds 4 and 8 came back within one step's gate.
    if (seed != 4 && seed != 8) {
      EXPECT_EQ(backend->Statistics().revisits_moved_past, 1) << seed;
    }
  }
}

// ---------------------------------------------------------------------------
// 1. A rectangular table (2-fold, axis z).

TEST(BackendSequences, RectangularTableOneObjectAndTrajectoryWithinNoise) {
  ExpectSymbaTracksBaselinesFragment(
      OrbitSpec(Table(SymmetryType::kDiscrete, 2)), "rectangular");
}

// ---------------------------------------------------------------------------
// 2. A square table (4-fold), a 3-fold object with a tilted axis that is not
// its z axis, and a round table.

TEST(BackendSequences, SquareTableOneObjectAndTrajectoryWithinNoise) {
  ExpectSymbaTracksBaselinesFragment(
      OrbitSpec(Table(SymmetryType::kDiscrete, 4)), "square");
}

TEST(BackendSequences, TiltedThreeFoldObjectOneObjectAndTrajectoryWithinNoise) {
  ScriptedObject object = Table(SymmetryType::kDiscrete, 3);
  object.class_name = "stool";
  object.axis_o = Eigen::Vector3d(1.0, 0.5, 0.3).normalized();
  // The world axis is tilted 24 deg from the vertical.
  const Eigen::Vector3d axis_w = Eigen::Vector3d(0.4, 0.2, 1.0).normalized();
  object.T_wo.q = Eigen::Quaterniond::FromTwoVectors(object.axis_o, axis_w);
  ASSERT_GT(AxisAngle(axis_w, Eigen::Vector3d::UnitZ()), 20.0 * kDegree);
  ExpectSymbaTracksBaselinesFragment(OrbitSpec(object), "tilted 3-fold");
}

// A continuous object alone leaves the rotation of the whole rig about its
// axis unobservable: a yaw-biased front end then turns the cameras about the
// table (the objects cannot see it) and only the front end's translation
// resists. This sequence therefore has a front end whose relative motion
// (given as odometry) has an accurate translation (1 cm) and the same yaw
// bias on the featureless half. The detector's angle hypotheses cover a
// half circle per view, centred anywhere (a network's hypotheses need not
// cover the whole circle): mh's 6-DoF gate then fails too.
TEST(BackendSequences, RoundTableOneObjectAndTrajectoryWithinNoise) {
  ScriptedSequenceSpec spec = OrbitSpec(Table(SymmetryType::kContinuous, 0));
  spec.with_odometry = true;
  spec.odometry_sigma_t = 0.01;
  spec.odometry_sigma_r = 0.02;
  spec.continuous_arc = kPi;
  ExpectSymbaTracksBaselinesFragment(spec, "round");
}

// With the yaw-drifting front end poses alone, the azimuth of the cameras
// about the round table is not observable, but their distance to its axis
// and their height are: those must stay within the noise (measured 0.03-0.09
// m RMSE and 0.05-0.17 m max over seeds 1-16; 0.12 m and 0.20 m are
// allowed). The azimuthal error is reported, not asserted.
TEST(BackendSequences, RoundTableFixesWhatItObserves) {
  const ScriptedSequenceSpec spec =
      OrbitSpec(Table(SymmetryType::kContinuous, 0));
  const ScriptedSequence seq = GenerateScriptedSequence(spec);
  std::unique_ptr<Backend> backend;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, BackendOptions(), &backend));
  ASSERT_EQ(backend->Objects().size(), 1u);
  EXPECT_EQ(backend->Objects()[0].symmetry, SymmetryType::kContinuous);
  const Eigen::Vector3d centre = spec.objects[0].T_wo.t;
  const std::vector<Rigid3d> estimate = EstimatedPoses(*backend);
  double sum_sq = 0.0;
  double max_error = 0.0;
  for (size_t k = 0; k < estimate.size(); ++k) {
    const Eigen::Vector3d p = estimate[k].t - centre;
    const Eigen::Vector3d q = seq.T_wc_true[k].t - centre;
    const double d =
        std::hypot(p.head<2>().norm() - q.head<2>().norm(), p.z() - q.z());
    sum_sq += d * d;
    max_error = std::max(max_error, d);
  }
  const double rmse = std::sqrt(sum_sq / estimate.size());
  const PositionError full = Positions(seq.T_wc_true, estimate);
  std::printf(
      "[ round, front end only ] radius/height RMSE %.3f m, max "
      "%.3f m; full position RMSE %.3f m\n",
      rmse,
      max_error,
      full.rmse);
  EXPECT_LT(rmse, 0.12);
  EXPECT_LT(max_error, 0.20);
}

// ---------------------------------------------------------------------------
// 3. Two round tables of one class, 1.2 m apart: two objects, never merged,
// every detection with the table that produced it. Two continuous objects
// together fix the azimuth, so the plain drifting front end is used. They
// fix it less firmly than a discrete object (through two positions 1.2 m
// apart, each known to a few cm): measured 0.10-0.26 m RMSE and 0.21-0.47 m
// max over seeds 1-16 (before and after the depth factor), hence 0.30 m and
// 0.55 m here.

TEST(BackendSequences, TwoRoundTablesStayApart) {
  ScriptedSequenceSpec spec;
  ScriptedObject left = Table(SymmetryType::kContinuous, 0);
  left.T_wo.t = Eigen::Vector3d(-0.6, 0.0, 0.0);
  ScriptedObject right = left;
  right.T_wo.t = Eigen::Vector3d(0.6, 0.0, 0.0);
  spec.objects = {left, right};
  spec.detection_sigma_r = 0.05;
  spec.seed = 3;
  const ScriptedSequence seq = GenerateScriptedSequence(spec);

  std::unique_ptr<Backend> backend;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, BackendOptions(), &backend));
  const std::vector<MapObjectEstimate> objects = backend->Objects();
  ASSERT_EQ(objects.size(), 2u);

  std::map<std::string, int> generated_by;  // detection id -> truth object
  for (const auto& truths : seq.detections) {
    for (const auto& truth : truths) generated_by[truth.id] = truth.object;
  }
  std::map<int, int> map_object_of;  // truth object -> map object id
  int count = 0;
  for (const DetectionAssignment& a : backend->Assignments()) {
    ASSERT_EQ(generated_by.count(a.detection), 1u) << a.detection;
    const int truth = generated_by[a.detection];
    const auto [it, inserted] = map_object_of.emplace(truth, a.object);
    EXPECT_EQ(it->second, a.object) << "detection " << a.detection;
    ++count;
  }
  EXPECT_EQ(count, 2 * static_cast<int>(seq.keyframes.size()));
  ASSERT_EQ(map_object_of.size(), 2u);
  EXPECT_NE(map_object_of[0], map_object_of[1]);
  for (const MapObjectEstimate& object : objects) {
    EXPECT_EQ(object.symmetry, SymmetryType::kContinuous);
    const int truth = object.id == map_object_of[0] ? 0 : 1;
    EXPECT_LT((object.t_wo - spec.objects[truth].T_wo.t).norm(),
              kObjectPositionTolerance);
  }
  const PositionError error =
      Positions(seq.T_wc_true, EstimatedPoses(*backend));
  std::printf("[ two round tables ] keyframe RMSE %.3f m, max %.3f m\n",
              error.rmse,
              error.max);
  EXPECT_LT(error.rmse, 0.30);
  EXPECT_LT(error.max, 0.55);
}

// ---------------------------------------------------------------------------
// 4. New objects and classes. Table A at the centre, a chair with exactly
// table A's pose, table B 1.2 m away (beyond every gate). Every method must
// create three objects and never put a detection on an object of another
// class, even where the poses coincide.

TEST(BackendSequences, UnmatchedDetectionsCreateObjectsAndClassesNeverMix) {
  ScriptedSequenceSpec spec;
  ScriptedObject table_a = Table(SymmetryType::kDiscrete, 2);
  ScriptedObject chair = table_a;
  chair.class_name = "chair";
  chair.symmetry = SymmetryType::kAsymmetric;
  ScriptedObject table_b = Table(SymmetryType::kDiscrete, 2);
  table_b.T_wo.t = Eigen::Vector3d(1.2, 0.3, 0.0);
  spec.objects = {table_a, chair, table_b};
  // Every view shows mode 0 only, so that sh and mh (which split a table
  // whose modes flip, see above) see one pose per object too.
  spec.mode_script = {{0}};
  spec.num_keyframes = 6;
  spec.seed = 4;
  const ScriptedSequence seq = GenerateScriptedSequence(spec);
  ASSERT_EQ(seq.detections.front().size(), 3u);

  std::map<std::string, int> generated_by;
  for (const auto& truths : seq.detections) {
    for (const auto& truth : truths) generated_by[truth.id] = truth.object;
  }
  for (Method method :
       {Method::kSymba, Method::kMultiHypothesis, Method::kSingleHypothesis}) {
    SCOPED_TRACE(MethodName(method));
    BackendOptions options;
    options.method = method;
    options.confirm_keyframes = 1;  // objects enter the map at once
    std::unique_ptr<Backend> backend;
    ASSERT_TRUE(Backend::Create(options, seq.intrinsics, {}, &backend).ok());
    ASSERT_TRUE(backend->AddKeyframe(seq.keyframes[0]).ok());
    // The first keyframe alone: three detections, nothing to match.
    EXPECT_EQ(backend->Objects().size(), 3u);
    for (size_t k = 1; k < seq.keyframes.size(); ++k) {
      ASSERT_TRUE(backend->AddKeyframe(seq.keyframes[k]).ok());
      ASSERT_TRUE(backend->OptimizeWindow().ok());
    }
    const std::vector<MapObjectEstimate> objects = backend->Objects();
    ASSERT_EQ(objects.size(), 3u);
    EXPECT_EQ(backend->Statistics().objects, 3);
    std::map<int, std::string> class_of;
    for (const MapObjectEstimate& object : objects) {
      class_of[object.id] = object.class_name;
    }
    std::map<int, int> map_object_of;
    for (const DetectionAssignment& a : backend->Assignments()) {
      const int truth = generated_by.at(a.detection);
      EXPECT_EQ(class_of[a.object], spec.objects[truth].class_name)
          << a.detection;
      const auto [it, inserted] = map_object_of.emplace(truth, a.object);
      EXPECT_EQ(it->second, a.object) << a.detection;
    }
    EXPECT_EQ(map_object_of.size(), 3u);
  }
}

// ---------------------------------------------------------------------------
// 5. An asymmetric map object becomes discrete. The first view of a 2-fold
// table shows one mode (read as asymmetric: an asymmetric object); the
// second shows only the other mode: 6 DoF fail, 5 DoF hold. One such flip
// is no evidence (a real detector flips now and then): the detection joins
// the object without an edge. The view of keyframe 4 shows both modes, a
// symmetric detection, and the object becomes discrete with a second angle
// pi from the first and keeps its identity. (Objects are confirmed at once
// here: the test is about the upgrade.)

// A 2-fold table seen in one mode, then the other, ..., both at keyframe 4.
ScriptedSequence FlipsThenBothModes() {
  ScriptedSequenceSpec spec;
  spec.objects = {Table(SymmetryType::kDiscrete, 2)};
  spec.mode_script = {{0}, {1}, {0}, {1}, {0, 1}, {1}, {0}, {0, 1}};
  spec.num_keyframes = 8;
  spec.seed = 5;
  return GenerateScriptedSequence(spec);
}

TEST(BackendSequences, AsymmetricObjectUpgradesToDiscreteOnModeFlip) {
  const ScriptedSequence seq = FlipsThenBothModes();

  BackendOptions options;
  options.confirm_keyframes = 1;
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(options, seq.intrinsics, {}, &backend).ok());
  for (size_t k = 0; k < 4; ++k) {
    ASSERT_TRUE(backend->AddKeyframe(seq.keyframes[k]).ok());
    ASSERT_TRUE(backend->OptimizeWindow().ok());
    ASSERT_EQ(backend->Objects().size(), 1u) << k;
    EXPECT_EQ(backend->Objects()[0].symmetry, SymmetryType::kAsymmetric) << k;
    EXPECT_EQ(backend->Assignments()[k].symmetry, SymmetryType::kAsymmetric);
    EXPECT_EQ(backend->Assignments()[k].object, backend->Objects()[0].id);
  }
  EXPECT_EQ(backend->Statistics().object_upgrades, 0);
  EXPECT_EQ(backend->Statistics().rotation_outliers, 2);  // keyframes 1, 3

  ASSERT_TRUE(backend->AddKeyframe(seq.keyframes[4]).ok());
  ASSERT_TRUE(backend->OptimizeWindow().ok());
  ASSERT_EQ(backend->Objects().size(), 1u);
  EXPECT_EQ(backend->Objects()[0].symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(backend->Statistics().object_upgrades, 1);
  ASSERT_TRUE(backend->Objects()[0].upgrade.has_value());
  EXPECT_EQ(backend->Objects()[0].upgrade->keyframe, seq.keyframes[4].id);
  EXPECT_EQ(backend->Objects()[0].upgrade->evidence, 1);  // one symmetric

  for (size_t k = 5; k < seq.keyframes.size(); ++k) {
    ASSERT_TRUE(backend->AddKeyframe(seq.keyframes[k]).ok());
    ASSERT_TRUE(backend->OptimizeWindow().ok());
  }
  const std::vector<MapObjectEstimate> objects = backend->Objects();
  ASSERT_EQ(objects.size(), 1u);
  const MapObjectEstimate& object = objects[0];
  EXPECT_EQ(object.symmetry, SymmetryType::kDiscrete);
  EXPECT_EQ(backend->Statistics().object_upgrades, 1);
  EXPECT_EQ(object.observations, static_cast<int>(seq.keyframes.size()));
  ASSERT_EQ(object.angles.size(), 2u);
  // Two angles pi apart (within the 3 deg hypothesis noise averaged over a
  // few views and the 1 deg camera error: 5 deg).
  EXPECT_NEAR(std::abs(WrapToPi(object.angles[1] - object.angles[0])),
              kPi,
              5 * kDegree);
  EXPECT_LT(AxisAngle(object.axis_w, Eigen::Vector3d::UnitZ()), kAxisTolerance);
  for (const DetectionAssignment& a : backend->Assignments()) {
    EXPECT_EQ(a.object, object.id);
  }

  // The same views split the 6-DoF baselines.
  for (Method method : {Method::kMultiHypothesis, Method::kSingleHypothesis}) {
    BackendOptions baseline_options = options;
    baseline_options.method = method;
    std::unique_ptr<Backend> baseline;
    ASSERT_NO_FATAL_FAILURE(RunSequence(seq, baseline_options, &baseline));
    EXPECT_EQ(baseline->Objects().size(), 2u) << MethodName(method);
    EXPECT_EQ(baseline->Statistics().object_upgrades, 0);
  }
}

// What each angle of the upgraded table got (MapObjectEstimate::
// angle_evidence), against the generator's truth: keyframes 0 and 2 (mode
// 0, with edges before the upgrade) count whole for angle 0; the flips of
// keyframes 1 and 3 (no edge) count nowhere; keyframes 4 and 7 (both modes)
// share one unit by the modes' inlier weights (dominant 1.0, other 0.8 per
// hypothesis); keyframes 5 and 6 (one mode each) count whole for theirs.
TEST(BackendSequences, AngleEvidenceSharesEachDetectionAmongItsModes) {
  const ScriptedSequence seq = FlipsThenBothModes();
  BackendOptions options;
  options.confirm_keyframes = 1;
  std::unique_ptr<Backend> backend;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, options, &backend));
  const std::vector<MapObjectEstimate> objects = backend->Objects();
  ASSERT_EQ(objects.size(), 1u);
  const MapObjectEstimate& object = objects[0];
  ASSERT_EQ(object.angles.size(), 2u);
  ASSERT_EQ(object.angle_evidence.size(), 2u);
  ASSERT_EQ(object.angle_probabilities.size(), 2u);
  // The angle that holds each true mode (pi apart, so 8 deg decides).
  const ScriptedObject truth = Table(SymmetryType::kDiscrete, 2);
  int angle_of_mode[2] = {-1, -1};
  for (int i = 0; i < 2; ++i) {
    for (int m = 0; m < 2; ++m) {
      const Eigen::Quaterniond R_wo_m =
          truth.T_wo.q * Rot(truth.axis_o, kPi * m);
      if (object.poses[i].q.angularDistance(R_wo_m) < kModeTolerance) {
        angle_of_mode[m] = i;
      }
    }
  }
  ASSERT_EQ(angle_of_mode[0], 0);  // the asymmetric pose became angle 0
  ASSERT_EQ(angle_of_mode[1], 1);
  double expected[2] = {2.0, 0.0};  // keyframes 0 and 2
  for (size_t k = 4; k < seq.keyframes.size(); ++k) {
    const testing::ScriptedDetectionTruth& detection =
        seq.detections[k].front();
    const std::vector<PoseHypothesis>& hyps =
        seq.keyframes[k].detections.front().hypotheses;
    double mode_weight[2] = {0.0, 0.0};
    for (size_t j = 0; j < hyps.size(); ++j) {
      const int m = detection.hypothesis_mode[j];
      if (m >= 0) mode_weight[m] += hyps[j].weight;
    }
    for (int m = 0; m < 2; ++m) {
      expected[angle_of_mode[m]] +=
          mode_weight[m] / (mode_weight[0] + mode_weight[1]);
    }
  }
  EXPECT_NEAR(expected[0] + expected[1], 6.0, 1e-12);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(object.angle_evidence[i], expected[i], 1e-12) << i;
    EXPECT_NEAR(object.angle_probabilities[i], expected[i] / 6.0, 1e-12) << i;
  }
  // Mode 0 was shown more often: its angle is the likelier.
  EXPECT_GT(object.angle_probabilities[0], 0.6);
}

// The same upgrade after the first keyframes were marginalised (window 2:
// keyframes 0-2 have left when keyframe 4 upgrades): one object, two angles,
// and the batch solve (which rebuilds the marginalised edges for the new
// type) agrees.
TEST(BackendSequences, UpgradeAfterMarginalisationKeepsOneObject) {
  const ScriptedSequence seq = FlipsThenBothModes();
  BackendOptions options;
  options.confirm_keyframes = 1;
  options.window_size = 2;
  options.window_policy = WindowPolicy::kMarginalize;
  options.keep_history = true;  // for the batch solve at the end
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(options, seq.intrinsics, {}, &backend).ok());
  for (size_t k = 0; k < seq.keyframes.size(); ++k) {
    ASSERT_TRUE(backend->AddKeyframe(seq.keyframes[k]).ok());
    ASSERT_TRUE(backend->OptimizeWindow().ok());
    if (k == 4) {
      EXPECT_EQ(backend->Statistics().marginalized_keyframes, 3);
      EXPECT_EQ(backend->Statistics().object_upgrades, 1);
    }
  }
  for (bool batch : {false, true}) {
    if (batch) {
      ASSERT_TRUE(backend->OptimizeBatch().ok());
    }
    const std::vector<MapObjectEstimate> objects = backend->Objects();
    ASSERT_EQ(objects.size(), 1u);
    EXPECT_EQ(objects[0].symmetry, SymmetryType::kDiscrete);
    EXPECT_EQ(objects[0].observations, static_cast<int>(seq.keyframes.size()));
    ASSERT_EQ(objects[0].angles.size(), 2u);
    EXPECT_NEAR(std::abs(WrapToPi(objects[0].angles[1] - objects[0].angles[0])),
                kPi,
                5 * kDegree)
        << (batch ? "batch" : "window");
    EXPECT_LT(AxisAngle(objects[0].axis_w, Eigen::Vector3d::UnitZ()),
              kAxisTolerance);
    for (const DetectionAssignment& a : backend->Assignments()) {
      EXPECT_EQ(a.object, objects[0].id);
    }
  }
}

// A 2-fold table (seed 5) whose detection in keyframe k shows the modes
// modes[k], one keyframe per entry.
ScriptedSequence TableShowingModes(const std::vector<std::vector<int>>& modes) {
  ScriptedSequenceSpec spec;
  spec.objects = {Table(SymmetryType::kDiscrete, 2)};
  spec.num_keyframes = static_cast<int>(modes.size());
  spec.seed = 5;
  spec.mode_script = modes;
  return GenerateScriptedSequence(spec);
}

// Flips alone: a single flipped view does not upgrade the object; the same
// flip repeated in upgrade_evidence (3) keyframes does, to discrete of
// order 2 with angle pi, reported with its evidence.
TEST(BackendSequences, OnlyARepeatedConsistentFlipUpgrades) {
  const ScriptedSequence single =
      TableShowingModes({{0}, {1}, {0}, {0}, {0}, {0}, {0}, {0}});
  const ScriptedSequence repeated =
      TableShowingModes({{0}, {1}, {0}, {1}, {0}, {1}, {0}, {0}});

  BackendOptions options;
  options.confirm_keyframes = 1;
  std::unique_ptr<Backend> backend;
  ASSERT_NO_FATAL_FAILURE(RunSequence(single, options, &backend));
  ASSERT_EQ(backend->Objects().size(), 1u);
  EXPECT_EQ(backend->Objects()[0].symmetry, SymmetryType::kAsymmetric);
  EXPECT_FALSE(backend->Objects()[0].upgrade.has_value());
  EXPECT_EQ(backend->Statistics().object_upgrades, 0);
  EXPECT_EQ(backend->Statistics().rotation_outliers, 1);
  // The flipped detection joined the object (no new object, no edge).
  EXPECT_EQ(backend->Assignments()[1].object, backend->Objects()[0].id);

  ASSERT_NO_FATAL_FAILURE(RunSequence(repeated, options, &backend));
  ASSERT_EQ(backend->Objects().size(), 1u);
  const MapObjectEstimate object = backend->Objects()[0];
  EXPECT_EQ(object.symmetry, SymmetryType::kDiscrete);
  ASSERT_TRUE(object.upgrade.has_value());
  EXPECT_EQ(object.upgrade->keyframe, repeated.keyframes[5].id);
  EXPECT_EQ(object.upgrade->evidence, 3);
  EXPECT_EQ(object.upgrade->order, 2);
  // The mean of |angle| of rotations near pi is biased below pi (an angle
  // cannot exceed pi): 174 deg here; within the 10 deg upgrade tolerance.
  EXPECT_NEAR(object.upgrade->angle, kPi, 10 * kDegree);
  EXPECT_EQ(backend->Statistics().rotation_outliers, 2);  // keyframes 1, 3
  for (const DetectionAssignment& a : backend->Assignments()) {
    EXPECT_EQ(a.object, object.id);
  }
}

// An object made from a turned detection (the first view shows the table's
// other pose, every later one its pose; no class prior, so each one-mode
// detection reads as asymmetric): the later views are flips of the object
// until 19 of them against its one view reject both its rotation and a
// symmetry (docs/backend.md "Real detectors", 5); it then turns to their
// rotation, its first view weighs nothing from then on, the rest are views
// of it. One object, at the table's pose, no upgrade.
TEST(BackendSequences, AnObjectMadeFromATurnedDetectionTurnsToItsViews) {
  std::vector<std::vector<int>> modes(26, {0});
  modes[0] = {1};
  const ScriptedSequence seq = TableShowingModes(modes);

  BackendOptions options;
  options.confirm_keyframes = 1;
  std::unique_ptr<Backend> backend;
  ASSERT_NO_FATAL_FAILURE(RunSequence(seq, options, &backend));
  ASSERT_EQ(backend->Objects().size(), 1u);
  const MapObjectEstimate object = backend->Objects()[0];
  EXPECT_EQ(object.symmetry, SymmetryType::kAsymmetric);
  EXPECT_FALSE(object.upgrade.has_value());
  EXPECT_EQ(backend->Statistics().objects_turned, 1);
  EXPECT_EQ(backend->Statistics().object_upgrades, 0);
  EXPECT_EQ(backend->Statistics().rotation_outliers, 18);  // keyframes 1-18
  EXPECT_LT(object.poses.front().q.angularDistance(
                Table(SymmetryType::kDiscrete, 2).T_wo.q),
            5 * kDegree);
  for (const DetectionAssignment& a : backend->Assignments()) {
    EXPECT_EQ(a.object, object.id);
  }
}

// The same for a round table whose first view is read as asymmetric (its
// hypotheses happen to agree): the later full-circle views upgrade the
// object to continuous, and the edges of the first view are rebuilt as
// continuous edges on the same object.
TEST(BackendSequences, AsymmetricObjectUpgradesToContinuous) {
  ScriptedSequenceSpec spec;
  spec.objects = {Table(SymmetryType::kContinuous, 0)};
  spec.num_keyframes = 10;
  spec.seed = 6;
  const ScriptedSequence round = GenerateScriptedSequence(spec);
  spec.objects[0].symmetry = SymmetryType::kAsymmetric;
  const ScriptedSequence first = GenerateScriptedSequence(spec);
  // Keyframe 0 of both is exact (the gauge); take its detection from the
  // asymmetric script.
  std::vector<KeyframeInput> keyframes = round.keyframes;
  keyframes[0].detections = first.keyframes[0].detections;

  BackendOptions options;
  options.confirm_keyframes = 1;  // checked from the first keyframe on
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(options, round.intrinsics, {}, &backend).ok());
  for (size_t k = 0; k < keyframes.size(); ++k) {
    ASSERT_TRUE(backend->AddKeyframe(keyframes[k]).ok());
    ASSERT_TRUE(backend->OptimizeWindow().ok());
    ASSERT_EQ(backend->Objects().size(), 1u) << "keyframe " << k;
    EXPECT_EQ(backend->Objects()[0].symmetry,
              k == 0 ? SymmetryType::kAsymmetric : SymmetryType::kContinuous);
  }
  EXPECT_EQ(backend->Statistics().object_upgrades, 1);
  const MapObjectEstimate object = backend->Objects()[0];
  EXPECT_EQ(object.observations, static_cast<int>(keyframes.size()));
  EXPECT_LT((object.t_wo - spec.objects[0].T_wo.t).norm(),
            kObjectPositionTolerance);
  EXPECT_LT(AxisAngle(object.axis_w, Eigen::Vector3d::UnitZ()), kAxisTolerance);
  const PositionError error =
      Positions(round.T_wc_true, EstimatedPoses(*backend));
  EXPECT_LT(error.rmse, kRmseTolerance);
  EXPECT_LT(error.max, kMaxErrorTolerance);
}

// Control: an asymmetric object (a chair) over the whole orbit is one map
// object for every method, and all three pull the trajectory back. The
// baselines' fragmentation above is the symmetry's doing.
TEST(BackendSequences, AsymmetricObjectIsOneObjectForEveryMethod) {
  ScriptedObject chair = Table(SymmetryType::kAsymmetric, 0);
  chair.class_name = "chair";
  const ScriptedSequence seq = GenerateScriptedSequence(OrbitSpec(chair));
  const PositionError frontend = Positions(seq.T_wc_true, FrontendPoses(seq));
  EXPECT_GT(frontend.rmse, kFrontendMinRmse);
#ifdef SYMBA_SANITIZED
  // mh's 30-component mixtures take half a minute under ASan + UBSan here;
  // its code runs sanitized in the other sequences, and all three run in
  // the optimised build.
  const Method methods[] = {Method::kSymba, Method::kSingleHypothesis};
#else
  const Method methods[] = {
      Method::kSymba, Method::kMultiHypothesis, Method::kSingleHypothesis};
#endif
  for (Method method : methods) {
    SCOPED_TRACE(MethodName(method));
    BackendOptions options;
    options.method = method;
    std::unique_ptr<Backend> backend;
    ASSERT_NO_FATAL_FAILURE(RunSequence(seq, options, &backend));
    const std::vector<MapObjectEstimate> objects = backend->Objects();
    ASSERT_EQ(objects.size(), 1u);
    EXPECT_EQ(objects[0].symmetry, SymmetryType::kAsymmetric);
    EXPECT_EQ(backend->Statistics().object_upgrades, 0);
    ASSERT_EQ(objects[0].poses.size(), 1u);
    EXPECT_LT(objects[0].poses[0].q.angularDistance(chair.T_wo.q),
              kModeTolerance);
    const PositionError error =
        Positions(seq.T_wc_true, EstimatedPoses(*backend));
    std::printf(
        "[ asymmetric chair ] %-5s keyframe RMSE %.3f m, max %.3f m, "
        "rotation RMSE %.1f deg\n",
        MethodName(method),
        error.rmse,
        error.max,
        error.rotation_rmse / kDegree);
    if (method == Method::kSymba) {
      EXPECT_LT(error.rmse, kRmseTolerance);
      EXPECT_LT(error.max, kMaxErrorTolerance);
    } else {
      // mh also mixes the outlier hypotheses in (up to 0.2 m RMSE, 0.42 m
      // max over seeds 1-12): "pulled back" is half the front end's error.
      EXPECT_LT(error.rmse, 0.5 * frontend.rmse);
    }
  }
}

// ---------------------------------------------------------------------------
// 6. Batch and window agree on a sequence that fits one window (8 keyframes,
// window 10).

std::vector<Rigid3d> SolveShortSequence(const ScriptedSequence& seq,
                                        bool window_after_each,
                                        bool final_batch) {
  BackendOptions options;
  options.window_size = 10;
  options.max_iterations = 50;
  options.batch_max_iterations = 50;
  std::unique_ptr<Backend> backend;
  const Status created = Backend::Create(options, seq.intrinsics, {}, &backend);
  if (!created.ok()) {
    ADD_FAILURE() << created.message();
    return {};
  }
  for (const KeyframeInput& kf : seq.keyframes) {
    EXPECT_TRUE(backend->AddKeyframe(kf).ok());
    if (window_after_each) {
      EXPECT_TRUE(backend->OptimizeWindow().ok());
    }
  }
  SolveReport report;
  EXPECT_TRUE((final_batch ? backend->OptimizeBatch(&report)
                           : backend->OptimizeWindow(&report))
                  .ok());
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.free_keyframes, static_cast<int>(seq.keyframes.size()) - 1);
  return EstimatedPoses(*backend);
}

ScriptedSequence ShortSequence(double rotation_sigma,
                               double translation_sigma) {
  ScriptedSequenceSpec spec = OrbitSpec(Table(SymmetryType::kDiscrete, 2));
  spec.num_keyframes = 8;
  spec.rotation_sigma = rotation_sigma;
  spec.translation_sigma = translation_sigma;
  return GenerateScriptedSequence(spec);
}

// The window then frees exactly what the batch frees (all but the gauge
// keyframe), so with the same iteration cap one window solve and one batch
// solve are the same problem from the same state: the poses agree to
// rounding (1e-9 m, 1e-9 rad).
TEST(BackendSequences, BatchAndWindowAgreeWhenTheWindowHoldsEverything) {
  const ScriptedSequence seq = ShortSequence(3.0 * kDegree, 0.02);
  const std::vector<Rigid3d> batch = SolveShortSequence(seq, false, true);
  const std::vector<Rigid3d> window = SolveShortSequence(seq, false, false);
  ASSERT_EQ(batch.size(), 8u);
  ASSERT_EQ(window.size(), 8u);
  for (size_t k = 0; k < batch.size(); ++k) {
    EXPECT_LT((batch[k].t - window[k].t).norm(), 1e-9) << k;
    EXPECT_LT(batch[k].q.angularDistance(window[k].q), 1e-9) << k;
  }
  // The solve did something: the poses moved from the front end's.
  EXPECT_GT((batch.back().t - seq.keyframes.back().T_wc->t).norm(), 1e-4);
}

// Solving the window after every keyframe reaches the batch optimum by
// another path. With max-mixture edges that holds only where the optimum is
// unique: each edge follows its nearest hypothesis, so with 3 deg hypothesis
// noise every choice of winners is its own local minimum, a few cm from the
// others (on this sequence the two paths settle 8 cm apart at costs 289 and
// 285, both converged). With the hypotheses of a mode nearly identical
// (0.05 deg, 0.5 mm) there is one basin per mode, and the paths agree to
// the solver tolerance: Ceres stops when the relative cost decrease falls
// below 1e-6 (function_tolerance), i.e. by 3e-4 on a cost of ~280; along
// the flattest direction of this problem (the scale, sigma ~5 cm from the
// front end's 5 cm) that leaves sqrt(2 * 3e-4) * 5 cm ~ 1 mm per solve, and
// the two paths stop on opposite sides (measured up to 3.4 mm and 0.015 deg
// over seeds 1-12); 5 mm and 0.05 deg are allowed.
TEST(BackendSequences, IncrementalWindowReachesTheBatchOptimum) {
  const ScriptedSequence seq = ShortSequence(0.05 * kDegree, 0.0005);
  const std::vector<Rigid3d> batch = SolveShortSequence(seq, false, true);
  const std::vector<Rigid3d> incremental = SolveShortSequence(seq, true, false);
  ASSERT_EQ(batch.size(), incremental.size());
  for (size_t k = 0; k < batch.size(); ++k) {
    EXPECT_LT((batch[k].t - incremental[k].t).norm(), 5e-3) << k;
    EXPECT_LT(batch[k].q.angularDistance(incremental[k].q), 0.05 * kDegree)
        << k;
  }
}

// ---------------------------------------------------------------------------
// 7. Input errors: a clear message and nothing added.

// ---------------------------------------------------------------------------
// Mode merging.

// A static camera at the origin sees one asymmetric object twice; each
// detection is a cloud of hypotheses whose mean is the truth (I, (0, 0, 2))
// but whose members differ between the two views.
KeyframeInput CloudKeyframe(int64_t id,
                            const std::vector<Eigen::Vector3d>& offsets) {
  KeyframeInput kf;
  kf.id = id;
  kf.timestamp = static_cast<double>(id);
  kf.T_wc = Rigid3d();
  DetectionInput det;
  det.id = std::to_string(id) + "/0";
  det.class_name = "chair";
  det.sigma_t = 0.01;
  det.sigma_r = 0.02;
  for (const Eigen::Vector3d& offset : offsets) {
    det.hypotheses.push_back({Rigid3d(Eigen::Quaterniond::Identity(),
                                      Eigen::Vector3d(0, 0, 2) + offset),
                              1.0});
  }
  kf.detections.push_back(det);
  return kf;
}

// Position error of the object and of the second camera after a batch solve.
std::pair<double, double> CloudErrors(bool merge_modes) {
  BackendOptions options;
  options.merge_modes = merge_modes;
  options.confirm_keyframes = 1;  // two views
  std::unique_ptr<Backend> backend;
  EXPECT_TRUE(Backend::Create(options, std::nullopt, {}, &backend).ok());
  const double a = 0.03;
  const double b = 0.02;
  EXPECT_TRUE(backend
                  ->AddKeyframe(CloudKeyframe(
                      0, {{a, 0, 0}, {-a, 0, 0}, {0, a, 0}, {0, -a, 0}}))
                  .ok());
  EXPECT_TRUE(
      backend
          ->AddKeyframe(CloudKeyframe(
              1,
              {{b, b, 0.01}, {-b, b, 0.01}, {b, -b, -0.01}, {-b, -b, -0.01}}))
          .ok());
  EXPECT_TRUE(backend->OptimizeBatch().ok());
  const std::vector<MapObjectEstimate> objects = backend->Objects();
  EXPECT_EQ(objects.size(), 1u);
  if (objects.empty()) return {1.0, 1.0};
  return {(objects[0].t_wo - Eigen::Vector3d(0, 0, 2)).norm(),
          backend->Keyframes()[1].T_wc.t.norm()};
}

TEST(BackendModes, MergedModesPutTheObjectAtTheHypothesesMean) {
  const auto [object_error, camera_error] = CloudErrors(true);
  EXPECT_LT(object_error, 1e-6);
  EXPECT_LT(camera_error, 1e-6);
}

TEST(BackendModes, PerHypothesisMixturesFollowTheNearestHypothesis) {
  // The paper's mixtures: each edge is its nearest hypothesis, so the
  // estimate settles on the hypotheses, centimetres from their mean.
  const auto [object_error, camera_error] = CloudErrors(false);
  EXPECT_GT(object_error + camera_error, 5e-3);
}

KeyframeInput ValidKeyframe(int64_t id) {
  KeyframeInput kf;
  kf.id = id;
  kf.timestamp = 0.1 * static_cast<double>(id);
  kf.T_wc = Rigid3d(Eigen::Quaterniond::Identity(),
                    Eigen::Vector3d(0.1 * static_cast<double>(id), 0, 0));
  DetectionInput det;
  det.id = std::to_string(id) + "/0";
  det.class_name = "table";
  det.hypotheses.push_back(
      {Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 2)), 1.0});
  kf.detections.push_back(det);
  return kf;
}

struct Counts {
  size_t keyframes, objects, assignments;
  int detections, points;
  bool operator==(const Counts& o) const {
    return keyframes == o.keyframes && objects == o.objects &&
           assignments == o.assignments && detections == o.detections &&
           points == o.points;
  }
};

Counts CountsOf(const Backend& backend) {
  return {backend.Keyframes().size(),
          backend.Objects().size(),
          backend.Assignments().size(),
          backend.Statistics().detections,
          backend.Statistics().points};
}

void ExpectRejected(Backend* backend,
                    const KeyframeInput& kf,
                    const std::string& message) {
  const Counts before = CountsOf(*backend);
  const Status status = backend->AddKeyframe(kf);
  EXPECT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr(message));
  EXPECT_TRUE(CountsOf(*backend) == before) << status.message();
}

TEST(BackendInput, RejectsBadKeyframesAndAddsNothing) {
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(
      Backend::Create(BackendOptions(), std::nullopt, {}, &backend).ok());

  KeyframeInput no_pose = ValidKeyframe(1);
  no_pose.T_wc.reset();
  ExpectRejected(backend.get(), no_pose, "the first keyframe needs T_wc");
  EXPECT_TRUE(backend->Keyframes().empty());

  ASSERT_TRUE(backend->AddKeyframe(ValidKeyframe(5)).ok());
  ASSERT_EQ(backend->Keyframes().size(), 1u);

  ExpectRejected(backend.get(), ValidKeyframe(5), "id must be greater");
  ExpectRejected(backend.get(), ValidKeyframe(4), "id must be greater");

  KeyframeInput no_hypotheses = ValidKeyframe(6);
  no_hypotheses.detections[0].hypotheses.clear();
  ExpectRejected(backend.get(), no_hypotheses, "has no hypotheses");

  KeyframeInput nan_hypothesis = ValidKeyframe(6);
  nan_hypothesis.detections[0].hypotheses.push_back(
      nan_hypothesis.detections[0].hypotheses[0]);
  nan_hypothesis.detections[0].hypotheses[1].T_co.t.y() =
      std::numeric_limits<double>::quiet_NaN();
  ExpectRejected(backend.get(), nan_hypothesis, "hypothesis 1");
  ExpectRejected(backend.get(), nan_hypothesis, "not finite");

  // A valid detection before the bad one must not be added either.
  KeyframeInput nan_second = ValidKeyframe(6);
  nan_second.detections.push_back(nan_hypothesis.detections[0]);
  nan_second.detections[1].id = "6/1";
  ExpectRejected(backend.get(), nan_second, "detection 6/1");

  // Positive and finite is not enough for a sigma: 1 / sigma^2 and the
  // determinant of its 6 x 6 square-root information must be finite and
  // non-zero (a sigma of 1e-100 or 1e200 used to abort in the edge's check).
  for (const double sigma : {1e-100, 1e-10, 2e9, 1e200}) {
    KeyframeInput tiny_or_huge = ValidKeyframe(6);
    tiny_or_huge.detections[0].sigma_t = sigma;
    ExpectRejected(
        backend.get(), tiny_or_huge, "sigma_t must be in [1e-9, 1e9]");
    tiny_or_huge.detections[0].sigma_t.reset();
    tiny_or_huge.detections[0].sigma_r = sigma;
    ExpectRejected(
        backend.get(), tiny_or_huge, "sigma_r must be in [1e-9, 1e9]");
  }
  // Finite coordinates whose squares are not: every solve would fail.
  KeyframeInput far_hypothesis = ValidKeyframe(6);
  far_hypothesis.detections[0].hypotheses[0].T_co.t.x() = 2e9;
  ExpectRejected(backend.get(), far_hypothesis, "translation beyond 1e9 m");
  KeyframeInput far_step = ValidKeyframe(6);
  far_step.odometry = Odometry{Rigid3d(), 0.01, 0.01};
  far_step.odometry->T_prev_cur.t.z() = -1e300;
  ExpectRejected(backend.get(), far_step, "odometry: translation beyond 1e9 m");

  KeyframeInput tiny_odometry = ValidKeyframe(6);
  tiny_odometry.odometry = Odometry{Rigid3d(), 1e-300, 0.01};
  ExpectRejected(backend.get(), tiny_odometry, "odometry sigma_t must be in");

  KeyframeInput with_points = ValidKeyframe(6);
  PointObservation point;
  point.id = 7;
  point.uv = Eigen::Vector2d(320, 240);
  point.depth = 3.0;
  with_points.points.push_back(point);
  ExpectRejected(backend.get(), with_points, "intrinsics");

  // After all the rejections the backend still takes the next keyframe.
  EXPECT_TRUE(backend->AddKeyframe(ValidKeyframe(6)).ok());
  EXPECT_EQ(backend->Keyframes().size(), 2u);
  EXPECT_TRUE(backend->OptimizeWindow().ok());
}

// A principal point of 1e300 px is finite, but every reprojection's square
// overflowed and every solve failed.
TEST(BackendInput, IntrinsicsBeyondTheirRangeAreRejectedAtCreate) {
  std::unique_ptr<Backend> backend;
  for (const PinholeIntrinsics& bad :
       {PinholeIntrinsics{500.0, 500.0, 1e300, 240.0},
        PinholeIntrinsics{500.0, 500.0, 320.0, -2e9},
        PinholeIntrinsics{2e9, 500.0, 320.0, 240.0},
        PinholeIntrinsics{500.0, 0.0, 320.0, 240.0}}) {
    const Status status = Backend::Create(BackendOptions(), bad, {}, &backend);
    EXPECT_THAT(status.message(),
                HasSubstr("fx, fy must be in (0, 1e9] and cx, cy within"));
    EXPECT_EQ(backend, nullptr);
  }
  EXPECT_TRUE(Backend::Create(BackendOptions(),
                              PinholeIntrinsics{1e9, 1e9, -1e9, 1e9},
                              {},
                              &backend)
                  .ok());
}

TEST(BackendInput, OptionsAreValidated) {
  BackendOptions options;
  EXPECT_TRUE(options.Validate().ok());
  options.window_size = 0;
  const Status status = options.Validate();
  EXPECT_FALSE(status.ok());
  EXPECT_THAT(status.message(), HasSubstr("window_size"));

  std::unique_ptr<Backend> backend;
  const Status created = Backend::Create(options, std::nullopt, {}, &backend);
  EXPECT_FALSE(created.ok());
  EXPECT_THAT(created.message(), HasSubstr("window_size"));
  EXPECT_EQ(backend, nullptr);

  options = BackendOptions();
  options.gate_position = -1.0;
  EXPECT_THAT(options.Validate().message(), HasSubstr("gate_position"));
}

// A class prior Categorize would reject must be rejected by Create: found
// by this test, AddKeyframe used to add the keyframe and only then fail on
// the detection's categorisation, leaving a half-added keyframe.
TEST(BackendInput, InvalidClassPriorsAreRejectedAtCreate) {
  ClassPrior bad_order;
  bad_order.symmetry = SymmetryType::kDiscrete;
  bad_order.order = 1;
  ClassPrior bad_axis;
  bad_axis.symmetry = SymmetryType::kContinuous;
  bad_axis.axis_o = Eigen::Vector3d(0.0, std::nan(""), 1.0);
  for (const ClassPrior& prior : {bad_order, bad_axis}) {
    std::unique_ptr<Backend> backend;
    const Status status = Backend::Create(
        BackendOptions(), std::nullopt, {{"table", prior}}, &backend);
    EXPECT_FALSE(status.ok());
    EXPECT_THAT(status.message(), HasSubstr("table"));
    EXPECT_EQ(backend, nullptr);
  }
  // A valid prior is accepted and used.
  ClassPrior good;
  good.symmetry = SymmetryType::kDiscrete;
  good.order = 2;
  good.axis_o = Eigen::Vector3d::UnitZ();
  std::unique_ptr<Backend> backend;
  ASSERT_TRUE(Backend::Create(
                  BackendOptions(), std::nullopt, {{"table", good}}, &backend)
                  .ok());
  EXPECT_TRUE(backend->AddKeyframe(ValidKeyframe(1)).ok());
  EXPECT_EQ(backend->Keyframes().size(), 1u);
}

// The generator is deterministic for a seed (the tests above rely on it).
TEST(ScriptedSequence, DeterministicForASeed) {
  const ScriptedSequenceSpec spec =
      OrbitSpec(Table(SymmetryType::kDiscrete, 2));
  const ScriptedSequence a = GenerateScriptedSequence(spec);
  const ScriptedSequence b = GenerateScriptedSequence(spec);
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (size_t k = 0; k < a.keyframes.size(); ++k) {
    EXPECT_EQ(a.keyframes[k].T_wc->t, b.keyframes[k].T_wc->t);
    ASSERT_EQ(a.keyframes[k].detections.size(),
              b.keyframes[k].detections.size());
    for (size_t d = 0; d < a.keyframes[k].detections.size(); ++d) {
      const auto& ha = a.keyframes[k].detections[d].hypotheses;
      const auto& hb = b.keyframes[k].detections[d].hypotheses;
      ASSERT_EQ(ha.size(), hb.size());
      for (size_t j = 0; j < ha.size(); ++j) {
        EXPECT_EQ(ha[j].T_co.q.coeffs(), hb[j].T_co.q.coeffs());
        EXPECT_EQ(ha[j].weight, hb[j].weight);
      }
    }
    EXPECT_EQ(a.keyframes[k].points.size(), b.keyframes[k].points.size());
  }
  // Points only on the rich half, and plenty of them there.
  for (size_t k = 0; k < a.keyframes.size(); ++k) {
    if (a.rich[k]) {
      EXPECT_GE(a.keyframes[k].points.size(), 20u) << k;
    } else {
      EXPECT_TRUE(a.keyframes[k].points.empty()) << k;
    }
  }
}

}  // namespace
}  // namespace symba
