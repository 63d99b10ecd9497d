#include "symba/import/tum_import.h"
#include "symba/io/format_double.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <utility>

#include "io/text_file.h"
#include "symba/backend/backend_options.h"
#include "symba/io/file_output.h"
#include "symba/io/log_file.h"
#include "symba/io/tum_trajectory.h"

namespace symba {
namespace {

using internal::Approx;
using internal::At;

// The index in `poses` of NearestPose(poses, timestamp, tolerance), or -1.
int FindByTimestamp(const std::vector<TrajectoryPose>& poses,
                    double timestamp,
                    double tolerance) {
  const TrajectoryPose* nearest = NearestPose(poses, timestamp, tolerance);
  return nearest == nullptr ? -1 : static_cast<int>(nearest - poses.data());
}

// Reads one input file, noting a conversion of its time unit.
Status ReadInput(const std::string& path,
                 const TumReadOptions& read_options,
                 std::vector<TrajectoryPose>* poses,
                 TumImportCounts* counts) {
  TumReadReport report;
  const Status status = ReadTumTrajectory(path, read_options, poses, &report);
  if (!status.ok()) return status;
  const std::string note = TumTimeUnitNote(path, report);
  if (counts != nullptr && !note.empty()) counts->notes.push_back(note);
  if (counts != nullptr && poses->empty()) {
    counts->warnings.push_back(
        path + ": no detection (" +
        (report.rows == 0 ? std::string("no data line")
                          : std::to_string(report.rows) + " all-zero rows") +
        "): the object is never seen");
  }
  return Status::Ok();
}

// A sigma the backend takes (symba/backend/backend_options.h).
Status CheckSigma(const char* name, double value) {
  if (!IsUsableNoiseSigma(value)) {
    return Status::Error(std::string(name) + ": must be in [1e-9, 1e9], got " +
                         Approx(value));
  }
  return Status::Ok();
}

Status CheckOptions(const TumImportOptions& options) {
  if (options.stride < 1) {
    return Status::Error("stride: must be at least 1, got " +
                         std::to_string(options.stride));
  }
  Status status = CheckSigma("odometry sigma_t", options.odometry_sigma_t);
  if (status.ok()) {
    status = CheckSigma("odometry sigma_r", options.odometry_sigma_r);
  }
  if (status.ok() && options.detection_sigma_t) {
    status = CheckSigma("detection sigma_t", *options.detection_sigma_t);
  }
  if (status.ok() && options.detection_sigma_r) {
    status = CheckSigma("detection sigma_r", *options.detection_sigma_r);
  }
  if (status.ok() && !(options.time_tolerance >= 0.0 &&
                       std::isfinite(options.time_tolerance))) {
    status = Status::Error(
        "time tolerance: must be finite and not negative, "
        "got " +
        Approx(options.time_tolerance));
  }
  for (std::size_t i = 0; status.ok() && i < options.objects.size(); ++i) {
    if (options.objects[i].class_name.empty()) {
      status = Status::Error(options.objects[i].path +
                             ": the object's class name is empty");
    }
  }
  return status;
}

}  // namespace

Status ImportTum(const TumImportOptions& options,
                 LogHeader* header,
                 std::vector<KeyframeInput>* keyframes,
                 TumImportCounts* counts) {
  Status status = CheckOptions(options);
  if (!status.ok()) return status;
  const double tolerance = options.time_tolerance;

  std::vector<TrajectoryPose> frames;
  status = ReadInput(options.trajectory, TumReadOptions{}, &frames, counts);
  if (!status.ok()) return status;

  Rigid3d first_T_wc = frames.front().T_wc;
  if (!options.first_pose.empty()) {
    std::vector<TrajectoryPose> first;
    status = ReadInput(options.first_pose, TumReadOptions{}, &first, counts);
    if (!status.ok()) return status;
    const int index =
        FindByTimestamp(first, frames.front().timestamp, tolerance);
    if (index < 0) {
      return Status::Error(options.first_pose +
                           ": no pose at the first frame's timestamp " +
                           FormatDouble(frames.front().timestamp) + " (" +
                           At(options.trajectory, frames.front().line) + ")");
    }
    first_T_wc = first[index].T_wc;
  }

  header->version = kLogFormatVersion;
  header->camera.reset();
  header->classes = options.classes;

  keyframes->clear();
  const std::size_t stride = static_cast<std::size_t>(options.stride);
  for (std::size_t f = 0; f < frames.size(); f += stride) {
    KeyframeInput keyframe;
    keyframe.id = static_cast<int64_t>(f);
    keyframe.timestamp = frames[f].timestamp;
    if (f == 0) {
      keyframe.T_wc = first_T_wc;
    } else {
      Odometry odometry;
      odometry.T_prev_cur = frames[f - stride].T_wc.Inverse() * frames[f].T_wc;
      odometry.T_prev_cur.q.normalize();
      odometry.sigma_t = options.odometry_sigma_t;
      odometry.sigma_r = options.odometry_sigma_r;
      keyframe.odometry = odometry;
    }
    keyframes->push_back(std::move(keyframe));
  }

  TumReadOptions detection_options;
  detection_options.skip_all_zero_rows = true;
  detection_options.allow_empty = true;
  for (const TumObjectFile& object : options.objects) {
    std::vector<TrajectoryPose> rows;
    status = ReadInput(object.path, detection_options, &rows, counts);
    if (!status.ok()) return status;
    std::map<int, int> line_of_frame;  // frame -> the row's line
    for (const TrajectoryPose& row : rows) {
      const int frame = FindByTimestamp(frames, row.timestamp, tolerance);
      if (frame < 0) {
        return Status::Error(
            At(object.path, row.line) + ": timestamp " +
            FormatDouble(row.timestamp) + " is not the time of any frame of " +
            options.trajectory + " (within " + Approx(tolerance) + " s)");
      }
      const auto [it, inserted] = line_of_frame.emplace(frame, row.line);
      if (!inserted) {
        return Status::Error(At(object.path, row.line) + ": timestamp " +
                             FormatDouble(row.timestamp) +
                             " is at the same frame (" +
                             At(options.trajectory, frames[frame].line) +
                             ") as line " + std::to_string(it->second) +
                             " (within " + Approx(tolerance) + " s)");
      }
      if (static_cast<std::size_t>(frame) % stride != 0) continue;
      DetectionInput detection;
      detection.class_name = object.class_name;
      detection.hypotheses.push_back(PoseHypothesis{row.T_wc, 1.0});
      detection.sigma_t = options.detection_sigma_t;
      detection.sigma_r = options.detection_sigma_r;
      (*keyframes)[static_cast<std::size_t>(frame) / stride]
          .detections.push_back(std::move(detection));
    }
  }
  return Status::Ok();
}

Status ImportTumToLog(const TumImportOptions& options,
                      const std::string& log_path,
                      TumImportCounts* counts) {
  std::vector<std::string> inputs = {options.trajectory, options.first_pose};
  for (const TumObjectFile& object : options.objects) {
    inputs.push_back(object.path);
  }
  Status status = CheckOutputSparesInputs(log_path, inputs);
  LogHeader header;
  std::vector<KeyframeInput> keyframes;
  if (status.ok()) status = ImportTum(options, &header, &keyframes, counts);
  if (status.ok()) status = WriteLogAtomically(log_path, header, keyframes);
  if (!status.ok() || counts == nullptr) return status;
  counts->keyframes = static_cast<int>(keyframes.size());
  counts->detections = 0;
  for (const KeyframeInput& keyframe : keyframes) {
    counts->detections += static_cast<int>(keyframe.detections.size());
  }
  return status;
}

}  // namespace symba
