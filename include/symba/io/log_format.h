// The symba log format v1 (docs/log-format.md): a JSON Lines file whose first
// line is a header and every further non-blank line one keyframe. This header
// declares the reader (streaming, strict) and the writer.
//
// Every error a reader reports has the form "FILE:LINE: what is wrong", where
// LINE is the 1-based line of the file the problem is on, and "what is wrong"
// starts with the JSON path of the offending value where there is one
// ("detections[0].hypotheses[2].q: quaternion norm 1.2 is not within 1e-3 of
// 1"). docs/log-format.md lists every check and its message.
//
// Reader choices the format page leaves open:
//   - An empty file (no header) is an error; a file with only a header is a
//     valid log with zero keyframes.
//   - Blank (whitespace-only) lines after the header are skipped; line 1 must
//     be the header.
//   - A number with a zero fractional part (17.0, 1.7e1) counts as an integer
//     where an integer is required (as in JSON Schema).
//   - When an object repeats a key, the last occurrence counts (as in most
//     JSON libraries).
//   - An empty detection id ("") counts as absent and gets the default id.
#ifndef SYMBA_IO_LOG_FORMAT_H_
#define SYMBA_IO_LOG_FORMAT_H_

#include <fstream>
#include <istream>
#include <map>
#include <memory>
#include <optional>
#include <ostream>
#include <string>

#include "symba/backend/keyframe_input.h"
#include "symba/categorization/categorize.h"
#include "symba/common/status.h"
#include "symba/geometry/pinhole_intrinsics.h"

namespace symba {

inline constexpr int kLogFormatVersion = 1;

// Where a log converted from BOP files came from: the optional header key
// "bop" ({"scene_id": 7, "obj_ids": {"table": 1}}, docs/log-format.md),
// written by `symba import bop` so that `symba replay --bop-out` can write
// the refined poses back with the BOP ids. Other readers ignore it.
struct BopSource {
  int scene_id = 0;                    // >= 0
  std::map<std::string, int> obj_ids;  // class name -> BOP obj_id (>= 0)
};

struct LogHeader {
  int version = kLogFormatVersion;
  std::optional<PinholeIntrinsics> camera;
  std::map<std::string, ClassPrior> classes;
  std::optional<BopSource> bop;
};

// Reads a log keyframe by keyframe; memory does not grow with the file.
class LogReader {
 public:
  // Opens `path` and reads and validates the header (line 1).
  static Status Open(const std::string& path,
                     std::unique_ptr<LogReader>* reader);
  // Same as Open, reading from `stream` (which the reader then owns);
  // `name` stands for FILE in error messages.
  static Status OpenStream(std::unique_ptr<std::istream> stream,
                           const std::string& name,
                           std::unique_ptr<LogReader>* reader);
  ~LogReader();

  const LogHeader& header() const;

  // Reads the next keyframe into `keyframe`. At the end of the file returns
  // OK with *end = true. Validates everything the format page requires,
  // including strictly increasing ids, non-decreasing times, T_wc on the
  // first keyframe, T_wc or odometry on later ones, and `camera` in the
  // header if the keyframe has points. Detection ids default to
  // "<keyframe>/<index>". Quaternions within 1e-3 of unit are normalised
  // (left as they are when already unit to machine precision, so what
  // LogWriter writes reads back bit for bit); rotation matrices within 1e-3
  // of orthonormal are projected onto SO(3) and returned as quaternions.
  // `keyframe`'s vectors are reused (their capacity is kept). After an error
  // `keyframe` is unspecified and every further call returns the same error.
  Status Next(KeyframeInput* keyframe, bool* end);

  // The 1-based line of the last keyframe returned.
  int line() const;

 private:
  class Impl;
  explicit LogReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Writes a log. Poses are written with quaternions [qx, qy, qz, qw], numbers
// in the shortest form that reads back as the same double (at most
// max_digits10 significant digits; always with a '.' or an exponent, so
// -0.0 survives). Optional fields are written only when present: detection
// `id` when not empty, `score` and hypothesis `w` when not 1, `sigma_t`,
// `sigma_r` and point `depth` when set.
//
// The writer refuses (with "NAME: keyframe ID: path: reason") what the
// reader would reject: non-finite numbers, ids that do not increase, time
// going back, no T_wc on the first keyframe, neither T_wc nor odometry later,
// quaternions not within 1e-3 of unit, an empty hypothesis list, weights,
// sigmas or depths that are not positive, points without a camera, strings
// that are not UTF-8, an invalid class prior. Nothing of a refused keyframe
// is written.
class LogWriter {
 public:
  static Status Open(const std::string& path,
                     const LogHeader& header,
                     std::unique_ptr<LogWriter>* writer);
  // Same as Open, writing to `stream`, which must outlive the writer; `name`
  // stands for the file in error messages.
  static Status OpenStream(std::ostream* stream,
                           const std::string& name,
                           const LogHeader& header,
                           std::unique_ptr<LogWriter>* writer);
  ~LogWriter();
  Status Write(const KeyframeInput& keyframe);
  // Flushes and closes; reports a write error.
  Status Close();

 private:
  class Impl;
  explicit LogWriter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace symba

#endif  // SYMBA_IO_LOG_FORMAT_H_
