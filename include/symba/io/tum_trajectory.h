// TUM trajectories as text: one line "timestamp tx ty tz qx qy qz qw" per
// pose (T_wc, or T_w,id for a pose graph), in the given order. Numbers are
// written in the shortest form that reads back as the same double.
#ifndef SYMBA_IO_TUM_TRAJECTORY_H_
#define SYMBA_IO_TUM_TRAJECTORY_H_

#include <string>
#include <utility>
#include <vector>

#include "symba/backend/estimates.h"
#include "symba/common/status.h"
#include "symba/geometry/rigid3.h"

namespace symba {

// The shortest decimal text that reads back as the same double.
std::string FormatDouble(double value);

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
