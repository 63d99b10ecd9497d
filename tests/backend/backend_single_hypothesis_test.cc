// A single-pose detector on symmetric objects (docs/backend.md step 4,
// docs/categorization.md "Class priors"): one pose per detection, flipping
// between the object's symmetric poses from frame to frame. With class
// priors every detection of the 2-fold table reads as discrete, a flip
// folds onto the object's one angle (modulo pi), and the table stays one
// map object with one angle; without priors the flips are the paper's
// upgrade evidence instead.
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "symba/backend/backend.h"
#include "symba/geometry/angle.h"
#include "symba/simulation/scene.h"
#include "symba/simulation/simulator.h"

namespace symba {
namespace {

struct SingleHypothesisRun {
  std::vector<KeyframeEstimate> keyframes;
  std::vector<MapObjectEstimate> objects;
  std::vector<DetectionAssignment> assignments;
  BackendStatistics statistics;
};

SimulatedSequence SingleHypothesisSequence(const std::string& scene,
                                           bool class_priors) {
  SimulationOptions options;
  options.single_hypothesis = true;
  options.write_class_priors = class_priors;
  SimulatedSequence sequence;
  EXPECT_TRUE(Simulate(scene, options, 2, &sequence).ok());
  return sequence;
}

SingleHypothesisRun RunBackend(const SimulatedSequence& sequence) {
  std::unique_ptr<Backend> backend;
  SingleHypothesisRun run;
  if (!Backend::Create(BackendOptions(),
                       sequence.header.camera,
                       sequence.header.classes,
                       &backend)
           .ok()) {
    ADD_FAILURE() << "Backend::Create";
    return run;
  }
  for (const KeyframeInput& keyframe : sequence.keyframes) {
    if (!backend->AddKeyframe(keyframe).ok() ||
        !backend->OptimizeWindow().ok()) {
      ADD_FAILURE() << "keyframe " << keyframe.id;
      return run;
    }
  }
  run.keyframes = backend->Keyframes();
  run.objects = backend->Objects();
  run.assignments = backend->Assignments();
  run.statistics = backend->Statistics();
  return run;
}

double PositionRmse(const SimulatedSequence& sequence,
                    const SingleHypothesisRun& run) {
  double sum = 0.0;
  for (size_t k = 0; k < run.keyframes.size(); ++k) {
    sum += (run.keyframes[k].T_wc.t - sequence.T_wc_true[k].t).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(run.keyframes.size()));
}

// The map objects the inlier detections of each ground-truth object went to.
std::map<int, std::map<ObjectId, int>> MapObjectsPerTruth(
    const SimulatedSequence& sequence, const SingleHypothesisRun& run) {
  std::map<std::string, int> truth_of;
  for (const auto& truths : sequence.detections) {
    for (const SimulatedDetectionTruth& truth : truths) {
      if (truth.hypothesis_mode.front() >= 0) truth_of[truth.id] = truth.object;
    }
  }
  std::map<int, std::map<ObjectId, int>> result;
  for (const DetectionAssignment& a : run.assignments) {
    const auto it = truth_of.find(a.detection);
    if (it != truth_of.end() && a.object >= 0) ++result[it->second][a.object];
  }
  return result;
}

TEST(BackendSingleHypothesis, FlipsOfATwoFoldTableFoldOntoOneAngle) {
  const SimulatedSequence sequence = SingleHypothesisSequence("disc", true);
  const SingleHypothesisRun run = RunBackend(sequence);
  ASSERT_EQ(run.objects.size(), 1u);
  const MapObjectEstimate& table = run.objects[0];
  EXPECT_EQ(table.symmetry, SymmetryType::kDiscrete);
  EXPECT_FALSE(table.upgrade.has_value());  // symmetric from the start
  // Every flip folded: one angle, no second one opened.
  EXPECT_EQ(table.angles.size(), 1u);
  EXPECT_GT(run.statistics.folded_angles, 10);
  EXPECT_EQ(run.statistics.object_upgrades, 0);
  // The axis is the vertical (the prior's z carried by the table's pose)
  // within 3 degrees, the position within 10 cm (the cameras that place it
  // are ~7 cm off themselves).
  EXPECT_GT(std::abs(table.axis_w.z()), std::cos(3.0 * kPi / 180.0));
  EXPECT_LT((table.t_wo - sequence.objects[0].T_wo.t).norm(), 0.10);
  // Every inlier detection went to the table.
  const auto per_truth = MapObjectsPerTruth(sequence, run);
  ASSERT_EQ(per_truth.size(), 1u);
  EXPECT_EQ(per_truth.at(0).size(), 1u);
  // Within the single-pose detector's noise floor (the chair, asymmetric,
  // gives 0.065 m in symba-bench); the front end alone is ~1 m off.
  EXPECT_LT(PositionRmse(sequence, run), 0.12);
}

TEST(BackendSingleHypothesis, ARoundTableWithAPriorIsOneContinuousObject) {
  const SimulatedSequence with = SingleHypothesisSequence("cts", true);
  const SingleHypothesisRun run = RunBackend(with);
  ASSERT_EQ(run.objects.size(), 1u);
  EXPECT_EQ(run.objects[0].symmetry, SymmetryType::kContinuous);
  EXPECT_EQ(MapObjectsPerTruth(with, run).at(0).size(), 1u);
  EXPECT_LT(PositionRmse(with, run), 0.10);

#ifdef SYMBA_SANITIZED
  // The second replay adds no code path the first did not run and takes
  // half a minute under ASan + UBSan; the optimised build runs it.
  GTEST_SKIP() << "the run without the prior is the optimised build's";
#endif
  // Without the prior a single pose reads as asymmetric, and flips by
  // random angles never agree on an order: the table is mapped more than
  // once and the camera is worse.
  const SimulatedSequence without = SingleHypothesisSequence("cts", false);
  const SingleHypothesisRun plain = RunBackend(without);
  EXPECT_EQ(plain.statistics.folded_angles, 0);
  EXPECT_GT(MapObjectsPerTruth(without, plain).at(0).size(), 1u);
  EXPECT_GT(PositionRmse(without, plain), 2.0 * PositionRmse(with, run));
}

}  // namespace
}  // namespace symba
