// Evaluation of a replay against ground truth (docs/evaluation.md).
//
// Inputs, each read strictly (errors "FILE:LINE: reason" or "FILE: reason"):
//   GT dir      gt_trajectory.tum  timestamp tx ty tz qx qy qz qw (T_wc, one
//                                  line per keyframe)
//               gt_objects.json    {"objects": [{id, class, symmetry, order,
//                                  axis_o?, axis?, pose}], "detections":
//                                  {"<detection id>": <gt object id>}}
//   result dir  trajectory.tum, objects.json, associations.csv (the outputs
//               of `symba replay`, log-format.md "Outputs of a replay").
//
// Camera, over the keyframes matched by timestamp (|dt| <= 1e-6 s; every
// estimated keyframe must match one ground-truth keyframe and vice versa):
//   position_rmse     = sqrt(mean_k |t_wc,k - t_wc,k^gt|^2)               [m]
//   rotation_rmse_deg = sqrt(mean_k angle(R_wc,k^gt^T R_wc,k)^2)        [deg]
// No alignment: the backend fixes the gauge at the first keyframe's
// front-end pose, which the simulator makes exact, so both trajectories are
// in the same world frame.
//
// Per ground-truth object o, over the detections the ground truth assigns to
// it (every one must have a row in associations.csv):
//   map_objects        the number of distinct map objects they went to
//                      (fragmentation; 1 is right, more means the object was
//                      registered more than once)
//   main_object        the map object most of them went to (ties: lowest id)
//   translation_error  |t_wo(main) - t_wo^gt|                             [m]
//   axis_error_deg     symmetric o only: acos(|a_w . a_w^gt|), sign-free,
//                      where a_w is the main object's axis if it is symmetric
//                      and R_wo(main) a_o^gt otherwise                  [deg]
//   rotation_error_deg the rotation error modulo o's symmetry: asymmetric
//                      o: min over the main object's poses of
//                      angle(R^gt^T R_i); discrete o of order n: min over
//                      its poses R_i and k < n of angle((R^gt Rot(a_o^gt,
//                      2 pi k / n))^T R_i); continuous o: the axis error
//                      (nothing else of its rotation is observable)     [deg]
//   categorization     the fraction of its detections whose categorised type
//                      (associations.csv) equals o's symmetry
// Overall categorisation accuracy is over all detections; confusion[g][c]
// counts detections of ground-truth type g categorised as c (indices are
// SymmetryType values).
#ifndef SYMBA_EVALUATION_EVALUATE_H_
#define SYMBA_EVALUATION_EVALUATE_H_

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "symba/backend/estimates.h"
#include "symba/categorization/symmetry_type.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"
#include "symba/io/ground_truth_objects.h"
#include "symba/io/tum_trajectory.h"

namespace symba {

// Keyframes whose timestamps differ by at most this much are the same [s].
inline constexpr double kTimestampTolerance = 1e-6;

struct GroundTruth {
  std::string trajectory_path;  // the files it was read from
  std::string objects_path;
  std::vector<TrajectoryPose> keyframes;  // increasing timestamps
  std::vector<GroundTruthObject> objects;
  std::map<std::string, int> detections;  // detection id -> GT object id
};

// One row of associations.csv.
struct AssociationRow {
  int64_t keyframe = 0;
  std::string detection;
  int object = 0;
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  int line = 0;  // 1-based line in associations.csv
};

// The outputs of a replay as read back from its directory. MapObjectEstimate
// holds what objects.json has: axis_o is not in the file and stays zero.
struct ReplayOutputs {
  std::string trajectory_path;  // the files it was read from
  std::string objects_path;
  std::string associations_path;
  std::vector<TrajectoryPose> keyframes;  // increasing timestamps
  std::vector<MapObjectEstimate> objects;
  std::vector<AssociationRow> associations;
};

// Reads gt_dir/gt_trajectory.tum and gt_dir/gt_objects.json.
Status ReadGroundTruth(const std::string& gt_dir, GroundTruth* gt);
// Reads result_dir/trajectory.tum, objects.json and associations.csv.
Status ReadReplayOutputs(const std::string& result_dir, ReplayOutputs* outputs);

struct ObjectEvaluation {
  int gt_id = 0;
  std::string class_name;
  SymmetryType symmetry = SymmetryType::kAsymmetric;
  int order = 0;
  int detections = 0;   // its detections (all have an association row)
  int rejected = 0;     // of them, in no map object (object -1: outliers)
  int map_objects = 0;  // distinct map objects the others went to
  // Map object id -> how many of its detections went there.
  std::map<int, int> detections_per_map_object;
  int main_object = -1;  // -1 when no detection is in a map object
  SymmetryType main_object_symmetry = SymmetryType::kAsymmetric;
  // NaN when not defined (no detections; axis error of asymmetric objects).
  double translation_error = 0.0;   // m
  double axis_error_deg = 0.0;      // deg
  double rotation_error_deg = 0.0;  // deg
  // The main map object's position error normalised by its covariance,
  // e^T P^-1 e with e = t_estimated - t_true (chi-square with 3 degrees of
  // freedom if P is right); NaN without a covariance in objects.json (or
  // a singular one).
  double position_nees = 0.0;
  int categorized_correctly = 0;
  double categorization_accuracy = 0.0;  // in [0, 1]; NaN without detections
};

// e^T P^-1 e for the map object's position error e = t_wo - t_true,
// with P its position covariance; NaN without a covariance or with one
// that is not positive definite.
double PositionNees(const MapObjectEstimate& object,
                    const Eigen::Vector3d& t_true);

struct Evaluation {
  int keyframes = 0;
  double position_rmse = 0.0;       // m
  double rotation_rmse_deg = 0.0;   // deg
  double max_position_error = 0.0;  // m
  int map_objects = 0;              // in objects.json
  int detections = 0;               // rows of associations.csv
  int categorized_correctly = 0;
  double categorization_accuracy = 0.0;  // in [0, 1]; NaN without detections
  // confusion[ground-truth type][categorised type], SymmetryType indices.
  std::array<std::array<int, 3>, 3> confusion{};
  std::vector<ObjectEvaluation> objects;  // in ground-truth order

  // The largest map_objects over the ground-truth objects (0 if none).
  int MaxFragmentation() const;
};

// Compares what was read; errors name the file and line of the offending
// entry (unmatched keyframes, detections absent from one side, unknown map
// objects).
Status EvaluateReplay(const GroundTruth& gt,
                      const ReplayOutputs& result,
                      Evaluation* evaluation);

// ReadGroundTruth + ReadReplayOutputs + EvaluateReplay.
Status Evaluate(const std::string& gt_dir,
                const std::string& result_dir,
                Evaluation* evaluation);

// A markdown report: a summary table, one row per ground-truth object, and
// the categorisation confusion matrix. Lengths in m (3 decimals), angles in
// degrees (2 decimals), "n/a" where a value is not defined.
std::string FormatEvaluationTable(const Evaluation& evaluation);
// The same as JSON (every number at full precision, null where not defined).
std::string FormatEvaluationJson(const Evaluation& evaluation);

}  // namespace symba

#endif  // SYMBA_EVALUATION_EVALUATE_H_
