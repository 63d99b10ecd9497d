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

// The unit a file's timestamps were written in (TUM's is seconds).
enum class TumTimeUnit { kSeconds, kMicroseconds, kNanoseconds };
const char* TumTimeUnitName(TumTimeUnit unit);  // "seconds", ...

// First timestamps above these are read as nanoseconds / microseconds: in
// seconds they would be over 3 million years (1e14 s); Unix time now is
// 1.7e9 s = 1.7e15 us = 1.7e18 ns, and a clock counting from boot reaches
// 1e14 us only after 3 years. Milliseconds are not recognised.
inline constexpr double kNanosecondsAbove = 1e17;
inline constexpr double kMicrosecondsAbove = 1e14;

// What a read found besides the poses.
struct TumReadReport {
  TumTimeUnit time_unit = TumTimeUnit::kSeconds;
  std::string first_timestamp;  // as written (empty: no data line)
  int rows = 0;                 // data lines, all-zero rows included
};

// "PATH: timestamps read as nanoseconds (the first is T), converted to
// seconds"; empty for seconds.
std::string TumTimeUnitNote(const std::string& path,
                            const TumReadReport& report);

// Reads a TUM file: '#' comments and blank lines are skipped; every other
// line has exactly 8 finite numbers, separated by spaces or tabs, or by
// commas (with optional spaces around them); quaternions within 1e-3 of
// unit norm are normalised, others are errors; timestamps strictly
// increase. The unit of the timestamps is the first one's (above
// kNanosecondsAbove: ns; above kMicrosecondsAbove: us; else s) and every
// timestamp is converted to seconds. Errors read "PATH:LINE: reason"
// ("PATH: no poses" for an empty file); a first data line that starts with
// a word is named as a header without '#'. `report` may be null.
Status ReadTumTrajectory(const std::string& path,
                         const TumReadOptions& options,
                         std::vector<TrajectoryPose>* poses,
                         TumReadReport* report);
inline Status ReadTumTrajectory(const std::string& path,
                                const TumReadOptions& options,
                                std::vector<TrajectoryPose>* poses) {
  return ReadTumTrajectory(path, options, poses, nullptr);
}
inline Status ReadTumTrajectory(const std::string& path,
                                std::vector<TrajectoryPose>* poses) {
  return ReadTumTrajectory(path, TumReadOptions{}, poses, nullptr);
}

// The pose of `poses` (increasing timestamps) nearest in time to
// `timestamp` if it is within `tolerance`, else null.
const TrajectoryPose* NearestPose(const std::vector<TrajectoryPose>& poses,
                                  double timestamp,
                                  double tolerance);

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
