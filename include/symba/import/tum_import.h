// Import of TUM text files (a front end's camera trajectory and one file of
// detector poses per object) into a symba log v1 (docs/import.md).
//
// Frames are the lines of the trajectory (T_wc). Keyframes are frames 0, N,
// 2N, ... (N = stride); a keyframe's id is its frame index and its time the
// trajectory's timestamp. The first keyframe carries T_wc: the first pose
// file's pose at that time if one is given (so the log starts in that
// trajectory's world, e.g. the ground truth's), the front end's otherwise.
// Every later keyframe carries only odometry T_prev,cur = T_wc(prev)^-1
// T_wc(cur) from the front end, with the stated sigmas; no T_wc, because the
// backend ignores it when odometry is present and, with a first pose, the
// front end's T_wc is in another world frame.
//
// An object file holds T_co rows of one object of class NAME; an all-zero
// row means "not detected" and a file may have no detection at all (a
// warning). A row belongs to the frame nearest in time, if that is within
// `time_tolerance`; at a keyframe it becomes one detection with one
// hypothesis (weight 1); rows at other frames are ignored; a row at no
// frame of the trajectory is an error, and so are two rows of one file at
// the same frame. A keyframe's detections are in the order of `objects`,
// with the log's default ids "<keyframe>/<index>".
//
// Every file is read by ReadTumTrajectory (symba/io/tum_trajectory.h):
// comma or whitespace separators, and nanosecond or microsecond timestamps
// converted to seconds (a note names each such file).
#ifndef SYMBA_IMPORT_TUM_IMPORT_H_
#define SYMBA_IMPORT_TUM_IMPORT_H_

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "symba/backend/keyframe_input.h"
#include "symba/categorization/categorize.h"
#include "symba/common/status.h"
#include "symba/io/log_format.h"

namespace symba {

// The default of TumImportOptions::time_tolerance [s].
inline constexpr double kImportTimestampTolerance = 1e-6;

// One object's detections: a TUM file of T_co rows, and its class name.
struct TumObjectFile {
  std::string class_name;
  std::string path;
};

struct TumImportOptions {
  std::string trajectory;  // the front end's T_wc, one line per frame
  std::vector<TumObjectFile> objects;
  int stride = 5;                   // a keyframe every `stride` frames (>= 1)
  double odometry_sigma_t = 0.005;  // m, > 0
  double odometry_sigma_r = 0.01;   // rad, > 0
  // Optional TUM trajectory whose pose at the first frame's time becomes the
  // first keyframe's T_wc (empty: the front end's first pose).
  std::string first_pose;
  // Written on every detection when set (> 0); the backend's defaults apply
  // otherwise.
  std::optional<double> detection_sigma_t;    // m
  std::optional<double> detection_sigma_r;    // rad
  std::map<std::string, ClassPrior> classes;  // the header's class priors
  // Rows of different files are the same frame when their timestamps
  // differ by at most this much [s] (>= 0).
  double time_tolerance = kImportTimestampTolerance;
};

// What an import did besides the log: counts, notes (timestamps converted
// from ns or us) and warnings (an object file without a detection), each
// a sentence that starts with the file's path.
struct TumImportCounts {
  int keyframes = 0;
  int detections = 0;
  std::vector<std::string> notes;
  std::vector<std::string> warnings;
};

// Reads every input strictly and builds the log in memory. Errors read
// "FILE:LINE: reason" (a malformed or unmatched line), "FILE: reason"
// (missing file, no pose at the first frame) or "option: reason" (an
// invalid option); on an error the outputs are unspecified.
// `counts` (may be null) gets the notes and warnings; its counts are
// ImportTumToLog's.
Status ImportTum(const TumImportOptions& options,
                 LogHeader* header,
                 std::vector<KeyframeInput>* keyframes,
                 TumImportCounts* counts = nullptr);

// ImportTum, then WriteLogAtomically (symba/io/log_file.h) to `log_path`:
// on any error `log_path` is left as it was. `counts` may be null.
Status ImportTumToLog(const TumImportOptions& options,
                      const std::string& log_path,
                      TumImportCounts* counts);

}  // namespace symba

#endif  // SYMBA_IMPORT_TUM_IMPORT_H_
