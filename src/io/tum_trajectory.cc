#include "symba/io/tum_trajectory.h"

#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>

namespace symba {

std::string FormatDouble(double value) {
  std::array<char, 32> buffer;
  const auto result =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  return std::string(buffer.data(), result.ptr);
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

}  // namespace symba
