#include "symba/io/tum_trajectory.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <system_error>

#include "io/json_tree_reader.h"
#include "io/text_file.h"
#include "symba/io/format_double.h"

namespace symba {
namespace {

// Quaternions whose norm is within this of 1 are normalised; others are
// errors (as in the log format).
constexpr double kUnitTolerance = 1e-3;

std::string_view Trimmed(std::string_view text) {
  const std::size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string_view::npos) return {};
  const std::size_t end = text.find_last_not_of(" \t");
  return text.substr(begin, end - begin + 1);
}

// The fields of a data line: comma-separated (each trimmed) when the line
// has a comma, whitespace-separated otherwise.
std::vector<std::string_view> SplitTumFields(std::string_view line) {
  if (line.find(',') == std::string_view::npos) {
    return internal::SplitFields(line);
  }
  std::vector<std::string_view> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = line.find(',', begin);
    const std::size_t end =
        comma == std::string_view::npos ? line.size() : comma;
    fields.push_back(Trimmed(line.substr(begin, end - begin)));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return fields;
}

// A first data line that starts with a word ("timestamp", "t", "time[s]";
// not "nan" or "inf", which are numbers, if not finite ones) is a header
// written without TUM's '#'.
bool LooksLikeHeader(const std::vector<std::string_view>& fields) {
  if (fields.empty() || fields.front().empty() ||
      !std::isalpha(static_cast<unsigned char>(fields.front().front()))) {
    return false;
  }
  const std::string_view first = fields.front();
  double value = 0.0;
  const auto result =
      std::from_chars(first.data(), first.data() + first.size(), value);
  return result.ec != std::errc() || result.ptr != first.data() + first.size();
}

TumTimeUnit TimeUnitOf(double first_timestamp) {
  if (first_timestamp > kNanosecondsAbove) return TumTimeUnit::kNanoseconds;
  if (first_timestamp > kMicrosecondsAbove) return TumTimeUnit::kMicroseconds;
  return TumTimeUnit::kSeconds;
}

// The timestamp in seconds. An integer count of ns or us is split into
// whole seconds and the rest, so the seconds keep every digit a double has.
double ToSeconds(std::string_view token, double value, TumTimeUnit unit) {
  if (unit == TumTimeUnit::kSeconds) return value;
  const int64_t per_second =
      unit == TumTimeUnit::kNanoseconds ? 1000000000 : 1000000;
  int64_t count = 0;
  if (internal::ParseInteger(token, &count)) {
    return static_cast<double>(count / per_second) +
           static_cast<double>(count % per_second) /
               static_cast<double>(per_second);
  }
  return value / static_cast<double>(per_second);
}

Status CheckFieldCount(const std::string& path,
                       int number,
                       const std::vector<std::string_view>& fields,
                       bool first_data_line,
                       std::string_view line) {
  if (first_data_line && LooksLikeHeader(fields)) {
    return Status::Error(
        internal::At(path, number) + ": " +
        io_internal::QuoteForMessage(Trimmed(line)) +
        " looks like a header: TUM files have none; start the line with "
        "'#' to make it a comment, or delete it");
  }
  if (fields.size() == 8) return Status::Ok();
  return Status::Error(internal::At(path, number) +
                       ": expected 8 numbers (timestamp tx ty tz qx qy qz "
                       "qw), found " +
                       std::to_string(fields.size()));
}

}  // namespace

const char* TumTimeUnitName(TumTimeUnit unit) {
  switch (unit) {
    case TumTimeUnit::kNanoseconds:
      return "nanoseconds";
    case TumTimeUnit::kMicroseconds:
      return "microseconds";
    case TumTimeUnit::kSeconds:
      break;
  }
  return "seconds";
}

std::string TumTimeUnitNote(const std::string& path,
                            const TumReadReport& report) {
  if (report.time_unit == TumTimeUnit::kSeconds) return std::string();
  return path + ": timestamps read as " + TumTimeUnitName(report.time_unit) +
         " (the first is " + report.first_timestamp + "), converted to seconds";
}

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

const TrajectoryPose* NearestPose(const std::vector<TrajectoryPose>& poses,
                                  double timestamp,
                                  double tolerance) {
  const auto after = std::lower_bound(
      poses.begin(),
      poses.end(),
      timestamp,
      [](const TrajectoryPose& pose, double t) { return pose.timestamp < t; });
  auto nearest = after;
  if (after == poses.end() ||
      (after != poses.begin() &&
       timestamp - (after - 1)->timestamp < after->timestamp - timestamp)) {
    nearest = after - 1;
  }
  if (nearest == poses.end() ||
      !(std::abs(nearest->timestamp - timestamp) <= tolerance)) {
    return nullptr;
  }
  return &*nearest;
}

Status ReadTumTrajectory(const std::string& path,
                         const TumReadOptions& options,
                         std::vector<TrajectoryPose>* poses,
                         TumReadReport* report) {
  using internal::At;
  std::string text;
  Status status = internal::ReadText(path, &text);
  if (!status.ok()) return status;
  poses->clear();
  TumReadReport found;
  const std::vector<std::string_view> lines = internal::SplitLines(text);
  double previous_timestamp = 0.0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = lines[i];
    const int number = static_cast<int>(i) + 1;
    if (internal::IsBlank(line) || Trimmed(line).front() == '#') continue;
    const std::vector<std::string_view> tokens = SplitTumFields(line);
    status = CheckFieldCount(path, number, tokens, found.rows == 0, line);
    if (!status.ok()) return status;
    double v[8];
    for (int k = 0; k < 8; ++k) {
      if (!internal::ParseDouble(tokens[k], &v[k])) {
        return Status::Error(At(path, number) + ": " +
                             io_internal::QuoteForMessage(tokens[k]) +
                             " is not a finite number");
      }
    }
    if (found.rows == 0) {
      found.time_unit = TimeUnitOf(v[0]);
      found.first_timestamp = std::string(tokens[0]);
    }
    v[0] = ToSeconds(tokens[0], v[0], found.time_unit);
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
    if (found.rows > 0 && !(v[0] > previous_timestamp)) {
      return Status::Error(At(path, number) + ": timestamp " +
                           std::string(tokens[0]) +
                           " is not after the previous one");
    }
    ++found.rows;
    previous_timestamp = v[0];
    if (skip) continue;
    pose.T_wc.q.normalize();
    poses->push_back(pose);
  }
  if (poses->empty() && !options.allow_empty) {
    return Status::Error(path + ": no poses");
  }
  if (report != nullptr) *report = found;
  return Status::Ok();
}

}  // namespace symba
