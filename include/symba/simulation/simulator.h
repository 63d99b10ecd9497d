// The simulator (docs/simulation.md): a scene of scene.h, orbited (or, for
// a scene with places, toured lap after lap) by a camera whose front end
// drifts on featureless keyframes, observed by a multi-hypothesis detector;
// the KeyframeInputs a front end would hand the backend, with the ground
// truth that generated them.
//
// Output directory of WriteSimulation (written atomically, complete or
// nothing):
//   log.jsonl          the log v1 (docs/log-format.md), via LogWriter
//   gt_trajectory.tum  timestamp tx ty tz qx qy qz qw, the true T_wc, one
//                      line per keyframe with the log's timestamps
//   gt_objects.json    {"objects": [{"id", "class", "symmetry", "order",
//                      "axis_o", "axis", "pose": {"t", "q"}}],
//                      "detections": {"<detection id>": <object id>}}
//                      ("order" 0 unless discrete; "axis_o" and the world
//                      "axis" = R_wo axis_o omitted for asymmetric objects)
//
// Deterministic: the same scene, options and seed give the same sequence
// bit for bit with the same standard library (one std::mt19937 drawn in a
// fixed order; std::normal_distribution's algorithm is the library's).
#ifndef SYMBA_SIMULATION_SIMULATOR_H_
#define SYMBA_SIMULATION_SIMULATOR_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/keyframe_input.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"
#include "symba/io/ground_truth_objects.h"
#include "symba/io/log_format.h"
#include "symba/simulation/scene.h"

namespace symba {

// What generated one detection.
struct SimulatedDetectionTruth {
  std::string id;   // the DetectionInput's id
  int object = -1;  // index into SimulatedSequence::objects
  // Discrete: the modes the view shows (ascending); {0} otherwise.
  std::vector<int> visible_modes;
  int dominant_mode = 0;  // the mode with the highest weights
  // Per hypothesis, in the DetectionInput's order: the mode (0 unless
  // discrete; -1 for an outlier) and the angle phi about a_o it was drawn
  // at (rad; 0 for asymmetric objects and outliers).
  std::vector<int> hypothesis_mode;
  std::vector<double> hypothesis_angle;
};

struct SimulatedSequence {
  std::string scene;
  uint32_t seed = 0;
  SimulationOptions options;
  std::vector<SimulatedObject> objects;
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  std::vector<Rigid3d> T_wc_true;         // per keyframe
  std::vector<bool> rich;                 // per keyframe: on the rich side
  std::vector<Eigen::Vector3d> points_w;  // point id = index
  // Per keyframe, in the order of its detections.
  std::vector<std::vector<SimulatedDetectionTruth>> detections;
};

// Simulates `scene_name` (SceneNames()) with `options` and `seed`.
// Errors: an unknown scene or invalid options; `out` is then unspecified.
Status Simulate(const std::string& scene_name,
                const SimulationOptions& options,
                uint32_t seed,
                SimulatedSequence* out);

// The sequence's objects as gt_objects.json holds them (id = index, unit
// axes in the object and world frames for symmetric ones).
std::vector<GroundTruthObject> GroundTruthObjects(
    const SimulatedSequence& sequence);

// The three files of a simulation, named and formatted as above. Fails
// only if LogWriter refuses a keyframe (which would be a simulator bug).
Status SimulationFiles(const SimulatedSequence& sequence,
                       std::vector<std::pair<std::string, std::string>>* files);

// Writes SimulationFiles into directory `out_dir` atomically (an existing
// directory is replaced only when everything succeeded; its parent must
// exist).
Status WriteSimulation(const SimulatedSequence& sequence,
                       const std::string& out_dir);

}  // namespace symba

#endif  // SYMBA_SIMULATION_SIMULATOR_H_
