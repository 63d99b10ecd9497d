// The absolute trajectory error of one timestamped trajectory against
// another, as it is (no alignment): for data whose estimate starts in the
// reference's world (e.g. a log imported with the ground truth's first pose,
// docs/import.md), any offset is an error of the estimate.
#ifndef SYMBA_EVALUATION_TRAJECTORY_ERROR_H_
#define SYMBA_EVALUATION_TRAJECTORY_ERROR_H_

#include <string>
#include <vector>

#include "symba/common/status.h"
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

}  // namespace symba

#endif  // SYMBA_EVALUATION_TRAJECTORY_ERROR_H_
