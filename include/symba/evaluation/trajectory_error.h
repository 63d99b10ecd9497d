// The absolute trajectory error of one timestamped trajectory against
// another, as it is (no alignment): for data whose estimate starts in the
// reference's world (e.g. a log imported with the ground truth's first pose,
// docs/import.md), any offset is an error of the estimate.
#ifndef SYMBA_EVALUATION_TRAJECTORY_ERROR_H_
#define SYMBA_EVALUATION_TRAJECTORY_ERROR_H_

#include <string>
#include <vector>

#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"
#include "symba/io/tum_trajectory.h"

namespace symba {

struct TrajectoryError {
  int poses = 0;                    // estimated poses compared
  double position_rmse = 0.0;       // sqrt(mean_k |t_k - t_k^ref|^2)   [m]
  double max_position_error = 0.0;  // max_k |t_k - t_k^ref|             [m]
};

// Compares every pose of `estimate` with the pose of `reference` at the
// same timestamp (|dt| <= kTimestampTolerance of evaluate.h, 1e-6 s);
// `reference` has increasing timestamps and may have more poses. An
// estimated pose without a reference pose is an error,
// "ESTIMATE_NAME: pose at timestamp T: no pose of REFERENCE_NAME at that
// time", and so is an empty estimate ("ESTIMATE_NAME: no poses").
Status CompareTrajectories(const std::vector<TrajectoryPose>& estimate,
                           const std::string& estimate_name,
                           const std::vector<TrajectoryPose>& reference,
                           const std::string& reference_name,
                           TrajectoryError* error);

// How an estimate is brought into the reference's world before its error is
// measured:
//   none   as it is (an estimate that starts in the reference's world);
//   first  the rigid transform that puts the first matched estimated pose
//          onto its reference pose, T_ref(0) T_est(0)^-1 (a front end that
//          starts at the identity, compared over its drift since then);
//   se3    the rigid transform that minimises the position error (Umeyama,
//          Eigen::umeyama without scaling; needs 3 matched poses);
//   sim3   the same with a scale (monocular front ends; needs 3).
enum class TrajectoryAlignment { kNone, kFirst, kSe3, kSim3 };
const char* TrajectoryAlignmentName(TrajectoryAlignment alignment);
bool ParseTrajectoryAlignment(const std::string& name,
                              TrajectoryAlignment* alignment);

struct TrajectoryEvaluationOptions {
  TrajectoryAlignment alignment = TrajectoryAlignment::kFirst;
  // An estimated pose is matched to the reference pose nearest in time
  // within this [s] (TUM's associate.py default); unmatched estimated poses
  // are counted and left out.
  double time_tolerance = 0.02;
};

struct TrajectoryEvaluation {
  int poses = 0;    // estimated poses
  int matched = 0;  // of them, with a reference pose within the tolerance
  TrajectoryAlignment alignment = TrajectoryAlignment::kFirst;
  // p_ref = scale * (T_ref_est.q * p_est) + T_ref_est.t.
  Rigid3d T_ref_est;
  double scale = 1.0;
  // ATE over the matched poses, after the alignment: CompareTrajectories of
  // the aligned poses against their matched reference poses.
  TrajectoryError ate;
  double rotation_rmse_deg = 0.0;  // sqrt(mean angle(R_ref^T R_est)^2)
  // RPE over consecutive matched poses i, i+1 (one keyframe apart):
  // E = (T_ref,i^-1 T_ref,i+1)^-1 (T_est,i^-1 T_est,i+1), aligned estimate.
  int rpe_pairs = 0;
  double rpe_translation_rmse = 0.0;   // sqrt(mean |E.t|^2)            [m]
  double rpe_rotation_rmse_deg = 0.0;  // sqrt(mean angle(E.q)^2)    [deg]
};

// Matches, aligns and measures `estimate` against `reference` (both with
// increasing timestamps). Errors: "ESTIMATE_NAME: no poses",
// "ESTIMATE_NAME: no pose within S s of a pose of REFERENCE_NAME", "se3
// alignment needs at least 3 matched poses, ESTIMATE_NAME has 2", an
// invalid tolerance.
Status EvaluateTrajectory(const std::vector<TrajectoryPose>& estimate,
                          const std::string& estimate_name,
                          const std::vector<TrajectoryPose>& reference,
                          const std::string& reference_name,
                          const TrajectoryEvaluationOptions& options,
                          TrajectoryEvaluation* evaluation);

}  // namespace symba

#endif  // SYMBA_EVALUATION_TRAJECTORY_ERROR_H_
