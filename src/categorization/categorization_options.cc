#include <cmath>
#include <string>
#include <utility>

#include "symba/categorization/categorize.h"

namespace symba {
namespace {

std::string Deg(double rad) { return std::to_string(rad * 180.0 / kPi); }

bool IsAngleIn0Pi(double a) { return a > 0.0 && a < kPi; }

}  // namespace

Status CategorizationOptions::Validate() const {
  const std::pair<const char*, double> angles[] = {
      {"min_axis_angle", min_axis_angle},
      {"axis_vote_angle", axis_vote_angle},
      {"swing_tolerance", swing_tolerance},
      {"cluster_eps", cluster_eps},
      {"max_cluster_extent", max_cluster_extent},
      {"min_cluster_separation", min_cluster_separation},
      {"empty_gap_angle", empty_gap_angle},
      {"asymmetric_inlier_angle", asymmetric_inlier_angle},
      {"prior_snap_angle", prior_snap_angle}};
  for (const auto& [name, value] : angles) {
    if (!IsAngleIn0Pi(value)) {
      return Status::Error(std::string("categorization options: ") + name +
                           " = " + Deg(value) + " deg is not in (0, 180) deg");
    }
  }
  if (min_points < 1) {
    return Status::Error("categorization options: min_points = " +
                         std::to_string(min_points) + " is below 1");
  }
  if (rescue_min_points < 0) {
    return Status::Error("categorization options: rescue_min_points = " +
                         std::to_string(rescue_min_points) + " is negative");
  }
  if (!(max_noise_fraction >= 0.0 && max_noise_fraction <= 1.0)) {
    return Status::Error("categorization options: max_noise_fraction = " +
                         std::to_string(max_noise_fraction) +
                         " is not in [0, 1]");
  }
  if (!(separation_ratio >= 0.0 && std::isfinite(separation_ratio))) {
    return Status::Error("categorization options: separation_ratio = " +
                         std::to_string(separation_ratio) +
                         " is not finite and >= 0");
  }
  if (!(min_empty_fraction >= 0.0 && min_empty_fraction <= 1.0)) {
    return Status::Error("categorization options: min_empty_fraction = " +
                         std::to_string(min_empty_fraction) +
                         " is not in [0, 1]");
  }
  if (!(translation_gate > 0.0)) {
    return Status::Error("categorization options: translation_gate = " +
                         std::to_string(translation_gate) +
                         " m is not positive");
  }
  return Status::Ok();
}

}  // namespace symba
