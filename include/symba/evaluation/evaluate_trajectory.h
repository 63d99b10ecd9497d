// Evaluation of a replay against a ground-truth camera trajectory at any
// rate (docs/evaluation.md, "Against a ground-truth trajectory"): what a
// user with real data has, instead of the simulator's files.
//
//   gt trajectory   a TUM file of the true T_wc, at any rate; read by
//                   ReadTumTrajectory (separators, ns/us timestamps).
//   result dir      what `symba replay` wrote (trajectory.tum, objects.json,
//                   associations.csv).
//   front end       optional: the front end's TUM trajectory (every frame);
//                   its poses at the result's keyframes are scored the same
//                   way, and the ATE ratio result / front end is given.
//   gt objects      optional: "CLASS tx ty tz qx qy qz qw" lines, the true
//                   T_wo of each object in the ground truth's world ('#'
//                   comments and blank lines skipped; spaces or tabs).
//
// Camera: EvaluateTrajectory (trajectory_error.h) of the keyframes against
// the ground truth. Objects: the map objects are carried into the ground
// truth's world by the result's alignment; each ground-truth object is
// matched to the map object of its class nearest to it, and its position
// error (and, unless that map object is continuous, the rotation error:
// the least angle over its poses) is given.
#ifndef SYMBA_EVALUATION_EVALUATE_TRAJECTORY_H_
#define SYMBA_EVALUATION_EVALUATE_TRAJECTORY_H_

#include <string>
#include <vector>

#include "symba/common/status.h"
#include "symba/evaluation/trajectory_error.h"
#include "symba/geometry/rigid3.h"

namespace symba {

struct GroundTruthObjectPose {
  std::string class_name;
  Rigid3d T_wo;
  int line = 0;  // 1-based line in its file
};

// Reads a ground-truth object list. Errors "PATH:LINE: reason" (a line
// without a class and 7 numbers, a number that is not finite, a quaternion
// not of unit norm) or "PATH: no objects".
Status ReadGroundTruthObjectList(const std::string& path,
                                 std::vector<GroundTruthObjectPose>* objects);

struct TrajectoryEvalInputs {
  std::string gt_trajectory;
  std::string result_dir;
  std::string frontend;    // empty: none
  std::string gt_objects;  // empty: none
  TrajectoryEvaluationOptions options;
};

struct ObjectPositionError {
  GroundTruthObjectPose gt;
  int map_objects_of_class = 0;
  int nearest_map_object = -1;      // its id; -1 when none has the class
  double position_error = 0.0;      // m; NaN without a map object
  double rotation_error_deg = 0.0;  // deg; NaN for none or continuous
};

struct GroundTruthTrajectoryEvaluation {
  std::string gt_path;      // the files read
  std::string result_path;  // RESULT/trajectory.tum
  std::string frontend_path;
  TrajectoryEvaluation result;
  bool has_frontend = false;
  TrajectoryEvaluation frontend;  // its poses at the result's keyframes
  double ate_ratio = 0.0;         // result ATE / front-end ATE; NaN without one
  int map_objects = 0;            // in objects.json
  std::vector<ObjectPositionError> objects;  // in the list's order
};

// Reads every input and evaluates; errors name the file (and line).
Status EvaluateAgainstTrajectory(const TrajectoryEvalInputs& inputs,
                                 GroundTruthTrajectoryEvaluation* evaluation);

// A markdown report: the inputs and alignment, a table of the result's
// (and front end's) ATE and RPE, the ratio, and one row per ground-truth
// object. Lengths in m (4 decimals), angles in degrees (2 decimals).
std::string FormatTrajectoryEvaluationTable(
    const GroundTruthTrajectoryEvaluation& evaluation);
// The same as JSON, every number at full precision, null where undefined.
std::string FormatTrajectoryEvaluationJson(
    const GroundTruthTrajectoryEvaluation& evaluation);

}  // namespace symba

#endif  // SYMBA_EVALUATION_EVALUATE_TRAJECTORY_H_
