#include "symba/io/tum_trajectory.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>

#include "io/text_file.h"
#include "symba/io/format_double.h"

namespace symba {
namespace {

// Quaternions whose norm is within this of 1 are normalised; others are
// errors (as in the log format).
constexpr double kUnitTolerance = 1e-3;

}  // namespace

std::string FormatTumTrajectory(
    const std::vector<std::pair<double, Rigid3d>>& trajectory) {
  std::string text;
  for (const auto& [timestamp, T] : trajectory) {
    const Eigen::Quaterniond q = T.q.normalized();
    const double values[8] = {
        timestamp, T.t.x(), T.t.y(), T.t.z(), q.x(), q.y(), q.z(), q.w()};
    for (int i = 0; i < 8; ++i) {
      if (i > 0) text += ' ';
      text += FormatDouble(values[i]);
    }
    text += '\n';
  }
  return text;
}

std::string FormatTumTrajectory(
    const std::vector<KeyframeEstimate>& keyframes) {
  std::vector<std::pair<double, Rigid3d>> trajectory;
  trajectory.reserve(keyframes.size());
  for (const KeyframeEstimate& kf : keyframes) {
    trajectory.emplace_back(kf.timestamp, kf.T_wc);
  }
  return FormatTumTrajectory(trajectory);
}

Status WriteTumTrajectory(
    const std::string& path,
    const std::vector<std::pair<double, Rigid3d>>& trajectory) {
  std::ofstream out(path, std::ios::binary);
  if (!out) {
    return Status::Error(path + ": cannot open for writing (" +
                         std::strerror(errno) + ")");
  }
  out << FormatTumTrajectory(trajectory);
  out.close();
  if (!out) {
    return Status::Error(path + ": write error (" + std::strerror(errno) + ")");
  }
  return Status::Ok();
}

Status ReadTumTrajectory(const std::string& path,
                         const TumReadOptions& options,
                         std::vector<TrajectoryPose>* poses) {
  using internal::At;
  std::string text;
  Status status = internal::ReadText(path, &text);
  if (!status.ok()) return status;
  poses->clear();
  const std::vector<std::string_view> lines = internal::SplitLines(text);
  double previous_timestamp = 0.0;
  bool any_row = false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = lines[i];
    const int number = static_cast<int>(i) + 1;
    if (internal::IsBlank(line) || line.front() == '#') continue;
    const std::vector<std::string_view> tokens = internal::SplitFields(line);
    if (tokens.size() != 8) {
      return Status::Error(At(path, number) +
                           ": expected 8 numbers (timestamp tx ty tz qx qy "
                           "qz qw), found " +
                           std::to_string(tokens.size()));
    }
    double v[8];
    for (int k = 0; k < 8; ++k) {
      if (!internal::ParseDouble(tokens[k], &v[k])) {
        return Status::Error(At(path, number) + ": " +
                             internal::Quoted(std::string(tokens[k])) +
                             " is not a finite number");
      }
    }
    const bool all_zero =
        std::all_of(v + 1, v + 8, [](double x) { return x == 0.0; });
    const bool skip = all_zero && options.skip_all_zero_rows;
    TrajectoryPose pose;
    pose.timestamp = v[0];
    pose.T_wc.t = Eigen::Vector3d(v[1], v[2], v[3]);
    pose.T_wc.q = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);
    pose.line = number;
    const double norm = pose.T_wc.q.norm();
    if (!skip && !(std::abs(norm - 1.0) <= kUnitTolerance)) {
      return Status::Error(At(path, number) + ": quaternion norm " +
                           internal::Approx(norm) + " is not 1");
    }
    if (any_row && !(v[0] > previous_timestamp)) {
      return Status::Error(At(path, number) + ": timestamp " +
                           std::string(tokens[0]) +
                           " is not after the previous one");
    }
    any_row = true;
    previous_timestamp = v[0];
    if (skip) continue;
    pose.T_wc.q.normalize();
    poses->push_back(pose);
  }
  if (poses->empty() && !options.allow_empty) {
    return Status::Error(path + ": no poses");
  }
  return Status::Ok();
}

}  // namespace symba
