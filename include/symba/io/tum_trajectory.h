// TUM trajectories as text: one line "timestamp tx ty tz qx qy qz qw" per
// pose (T_wc, or T_w,id for a pose graph, or a detector's T_co), in the
// given order, quaternion scalar last. Numbers are written in the shortest
// form that reads back as the same double; the reader is strict and names
// FILE:LINE in every error.
#ifndef SYMBA_IO_TUM_TRAJECTORY_H_
#define SYMBA_IO_TUM_TRAJECTORY_H_

#include <string>
#include <utility>
#include <vector>

#include "symba/backend/estimates.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// One line of a TUM trajectory file.
struct TrajectoryPose {
  double timestamp = 0.0;
  Rigid3d T_wc;  // the pose on the line (T_wc for a camera trajectory)
  int line = 0;  // 1-based line in its file
};

struct TumReadOptions {
  // A row whose seven pose numbers are all zero means "no pose at this
  // time" (how detectors write a frame without a detection): skip it
  // instead of refusing its zero quaternion.
  bool skip_all_zero_rows = false;
  // A file without a pose is valid (a detector that never saw the object).
  bool allow_empty = false;
};

// Reads a TUM file: '#' comments and blank lines are skipped; every other
// line has exactly 8 finite numbers; quaternions within 1e-3 of unit norm
// are normalised, others are errors; timestamps strictly increase. Errors
// read "PATH:LINE: reason" ("PATH: no poses" for an empty file).
Status ReadTumTrajectory(const std::string& path,
                         const TumReadOptions& options,
                         std::vector<TrajectoryPose>* poses);
inline Status ReadTumTrajectory(const std::string& path,
                                std::vector<TrajectoryPose>* poses) {
  return ReadTumTrajectory(path, TumReadOptions{}, poses);
}

std::string FormatTumTrajectory(
    const std::vector<std::pair<double, Rigid3d>>& trajectory);
// Keyframes by their timestamps.
std::string FormatTumTrajectory(const std::vector<KeyframeEstimate>& keyframes);

// Writes FormatTumTrajectory(trajectory) to `path`.
Status WriteTumTrajectory(
    const std::string& path,
    const std::vector<std::pair<double, Rigid3d>>& trajectory);

}  // namespace symba

#endif  // SYMBA_IO_TUM_TRAJECTORY_H_
