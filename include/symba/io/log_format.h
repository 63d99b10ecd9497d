// The symba log format v1 (docs/log-format.md): a JSON Lines file whose first
// line is a header and every further non-blank line one keyframe. This header
// declares the reader (streaming, strict) and the writer.
//
// Every error a reader reports has the form "FILE:LINE: what is wrong", where
// LINE is the 1-based line of the file the problem is on.
#ifndef SYMBA_IO_LOG_FORMAT_H_
#define SYMBA_IO_LOG_FORMAT_H_

#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "symba/backend/keyframe_input.h"
#include "symba/categorization/categorize.h"
#include "symba/common/status.h"
#include "symba/factors/reprojection_factor.h"

namespace symba {

inline constexpr int kLogFormatVersion = 1;

struct LogHeader {
  int version = kLogFormatVersion;
  std::optional<PinholeIntrinsics> camera;
  std::map<std::string, ClassPrior> classes;
};

// Reads a log keyframe by keyframe; memory does not grow with the file.
class LogReader {
 public:
  // Opens `path` and reads and validates the header (line 1).
  static Status Open(const std::string& path,
                     std::unique_ptr<LogReader>* reader);
  ~LogReader();

  const LogHeader& header() const;

  // Reads the next keyframe into `keyframe`. At the end of the file returns
  // OK with *end = true. Validates everything the format page requires,
  // including strictly increasing ids, non-decreasing times, T_wc on the
  // first keyframe, T_wc or odometry on later ones, and `camera` in the
  // header if the keyframe has points. Detection ids default to
  // "<keyframe>/<index>". Quaternions within 1e-3 of unit are normalised;
  // rotation matrices within 1e-3 of orthonormal are projected onto SO(3).
  Status Next(KeyframeInput* keyframe, bool* end);

  // The 1-based line of the last keyframe returned.
  int line() const;

 private:
  class Impl;
  explicit LogReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Writes a log. Poses are written with quaternions, numbers with enough
// digits to read back the same doubles.
class LogWriter {
 public:
  static Status Open(const std::string& path,
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
