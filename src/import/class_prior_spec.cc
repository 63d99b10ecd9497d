#include "symba/import/class_prior_spec.h"

#include <optional>
#include <string_view>
#include <vector>

#include "io/text_file.h"
#include "symba/categorization/symmetry_type.h"

namespace symba {
namespace {

constexpr int kMaxOrder = 1000000;  // as the log format

std::vector<std::string_view> Split(std::string_view text, char separator) {
  std::vector<std::string_view> parts;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = text.find(separator, begin);
    if (end == std::string_view::npos) {
      parts.push_back(text.substr(begin));
      return parts;
    }
    parts.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
}

}  // namespace

Status ParseClassPriorSpec(const std::string& spec,
                           std::string* name,
                           ClassPrior* prior) {
  const auto error = [&](const std::string& reason) {
    return Status::Error("class prior \"" + spec + "\": " + reason);
  };
  const std::size_t equals = spec.find('=');
  if (equals == std::string::npos || equals == 0) {
    return error(
        "expected NAME=asymmetric, NAME=discrete:ORDER[:ax,ay,az] or "
        "NAME=continuous[:ax,ay,az]");
  }
  *name = spec.substr(0, equals);
  const std::vector<std::string_view> parts =
      Split(std::string_view(spec).substr(equals + 1), ':');
  const std::optional<SymmetryType> type = ParseSymmetryType(parts[0]);
  if (!type) {
    return error("unknown symmetry \"" + std::string(parts[0]) +
                 "\" (expected asymmetric, discrete or continuous)");
  }
  *prior = ClassPrior();
  prior->symmetry = *type;
  std::size_t next = 1;
  if (*type == SymmetryType::kDiscrete) {
    if (parts.size() < 2) {
      return error("a discrete class needs its order: NAME=discrete:ORDER");
    }
    if (!internal::ParseInteger(parts[1], &prior->order) || prior->order < 2 ||
        prior->order > kMaxOrder) {
      return error("the order must be an integer from 2 to " +
                   std::to_string(kMaxOrder) + ", got \"" +
                   std::string(parts[1]) + "\"");
    }
    next = 2;
  }
  if (parts.size() > next + 1 ||
      (parts.size() == next + 1 && *type == SymmetryType::kAsymmetric)) {
    return error(*type == SymmetryType::kAsymmetric
                     ? "an asymmetric class has no order or axis"
                     : "too many ':' fields");
  }
  if (parts.size() == next + 1) {
    const std::vector<std::string_view> axis = Split(parts[next], ',');
    bool ok = axis.size() == 3;
    for (int i = 0; ok && i < 3; ++i) {
      ok = internal::ParseDouble(axis[i], &prior->axis_o[i]);
    }
    if (!ok) {
      return error("the axis must be three numbers ax,ay,az, got \"" +
                   std::string(parts[next]) + "\"");
    }
    if (prior->axis_o == Eigen::Vector3d::Zero()) {
      return error("the axis must not be the zero vector");
    }
  }
  return Status::Ok();
}

}  // namespace symba
