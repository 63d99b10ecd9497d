// The scenes of the simulator and the validation of its options.
#include "symba/simulation/scene.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace symba {
namespace {

constexpr double kDeg = kPi / 180.0;

Eigen::Quaterniond Yaw(double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
}

// A rectangular table, 2-fold about its vertical axis.
SimulatedObject RectangularTable(const Eigen::Vector3d& t_wo, double yaw) {
  SimulatedObject o;
  o.class_name = "table";
  o.symmetry = SymmetryType::kDiscrete;
  o.order = 2;
  o.axis_o = Eigen::Vector3d::UnitZ();
  o.T_wo = Rigid3d(Yaw(yaw), t_wo);
  return o;
}

SimulatedObject SquareTable(const Eigen::Vector3d& t_wo, double yaw) {
  SimulatedObject o = RectangularTable(t_wo, yaw);
  o.class_name = "square_table";
  o.order = 4;
  return o;
}

SimulatedObject RoundTable(const Eigen::Vector3d& t_wo, double yaw) {
  SimulatedObject o;
  o.class_name = "round_table";
  o.symmetry = SymmetryType::kContinuous;
  o.axis_o = Eigen::Vector3d::UnitZ();
  o.T_wo = Rigid3d(Yaw(yaw), t_wo);
  return o;
}

SimulatedObject Chair(const Eigen::Vector3d& t_wo, double yaw) {
  SimulatedObject o;
  o.class_name = "chair";
  o.symmetry = SymmetryType::kAsymmetric;
  o.axis_o = Eigen::Vector3d::Zero();
  o.T_wo = Rigid3d(Yaw(yaw), t_wo);
  return o;
}

// A triangular prism lying on the floor: 3-fold about its object x axis,
// which points `elevation` above the floor in the direction `yaw`.
SimulatedObject Prism(const Eigen::Vector3d& t_wo,
                      double yaw,
                      double elevation) {
  SimulatedObject o;
  o.class_name = "prism";
  o.symmetry = SymmetryType::kDiscrete;
  o.order = 3;
  o.axis_o = Eigen::Vector3d::UnitX();
  // R_y(-elevation) turns x up by `elevation`; the yaw then turns it about
  // the vertical.
  const Eigen::Quaterniond q =
      Yaw(yaw) * Eigen::Quaterniond(
                     Eigen::AngleAxisd(-elevation, Eigen::Vector3d::UnitY()));
  o.T_wo = Rigid3d(q.normalized(), t_wo);
  return o;
}

const Eigen::Vector3d kCentre(0.05, -0.05, 0.375);

Scene Disc() {
  return {"disc",
          "a rectangular table (2-fold) at the centre: the paper's sim(disc)",
          {RectangularTable(kCentre, 0.3)}};
}

Scene Cts() {
  return {"cts",
          "a round table (continuous) at the centre: the paper's sim(cts)",
          {RoundTable(kCentre, 0.3)}};
}

Scene Asym() {
  return {"asym",
          "a chair (asymmetric) at the centre",
          {Chair(Eigen::Vector3d(0.05, -0.05, 0.45), 0.3)}};
}

Scene Square() {
  return {"square",
          "a square table (4-fold) at the centre",
          {SquareTable(kCentre, 0.3)}};
}

Scene Room() {
  // The two round tables are 1.3 m apart: same class, close enough that
  // a loose association gate could merge them.
  return {"room",
          "a rectangular table, two round tables 1.3 m apart, a chair and a "
          "3-fold prism with a tilted axis",
          {RectangularTable(kCentre, 0.3),
           RoundTable(Eigen::Vector3d(0.9, 0.7, 0.375), 0.0),
           RoundTable(Eigen::Vector3d(-0.4, 0.9, 0.375), 1.0),
           Chair(Eigen::Vector3d(-1.0, -0.4, 0.45), 2.0),
           Prism(Eigen::Vector3d(0.7, -0.9, 0.25), 0.8, 30.0 * kDeg)}};
}

Status Positive(double value, const char* name) {
  if (std::isfinite(value) && value > 0.0) return Status::Ok();
  return Status::Error(std::string("simulation option ") + name +
                       " must be positive and finite");
}

Status NonNegative(double value, const char* name) {
  if (std::isfinite(value) && value >= 0.0) return Status::Ok();
  return Status::Error(std::string("simulation option ") + name +
                       " must be non-negative and finite");
}

Status Probability(double value, const char* name) {
  if (std::isfinite(value) && value >= 0.0 && value <= 1.0) {
    return Status::Ok();
  }
  return Status::Error(std::string("simulation option ") + name +
                       " must be in [0, 1]");
}

Status Finite(double value, const char* name) {
  if (std::isfinite(value)) return Status::Ok();
  return Status::Error(std::string("simulation option ") + name +
                       " must be finite");
}

}  // namespace

std::vector<std::string> SceneNames() {
  return {"disc", "cts", "asym", "square", "room"};
}

Status MakeScene(const std::string& name, Scene* scene) {
  if (name == "disc") {
    *scene = Disc();
  } else if (name == "cts") {
    *scene = Cts();
  } else if (name == "asym") {
    *scene = Asym();
  } else if (name == "square") {
    *scene = Square();
  } else if (name == "room") {
    *scene = Room();
  } else {
    std::string known;
    for (const std::string& n : SceneNames()) {
      known += (known.empty() ? "" : ", ") + n;
    }
    return Status::Error("unknown scene '" + name + "' (known: " + known + ")");
  }
  return Status::Ok();
}

Status SimulationOptions::Validate() const {
  if (num_keyframes < 1) {
    return Status::Error("simulation option num_keyframes must be >= 1");
  }
  if (keyframes_per_loop < 2) {
    return Status::Error("simulation option keyframes_per_loop must be >= 2");
  }
  if (num_points < 0) {
    return Status::Error("simulation option num_points must be >= 0");
  }
  if (num_hypotheses < 1) {
    return Status::Error("simulation option num_hypotheses must be >= 1");
  }
  if (image_width < 1 || image_height < 1) {
    return Status::Error("simulation option image size must be positive");
  }
  const std::pair<double, const char*> positive[] = {
      {orbit_radius, "orbit_radius"},
      {seconds_per_keyframe, "seconds_per_keyframe"},
      {odometry_sigma_t, "odometry_sigma_t"},
      {odometry_sigma_r, "odometry_sigma_r"},
      {featureless_odometry_sigma_t, "featureless_odometry_sigma_t"},
      {featureless_odometry_sigma_r, "featureless_odometry_sigma_r"},
      {wall_radius, "wall_radius"},
      {min_point_depth, "min_point_depth"},
      {intrinsics.fx, "fx"},
      {intrinsics.fy, "fy"},
      {max_detection_range, "max_detection_range"},
      {dominant_weight, "dominant_weight"},
      {other_weight, "other_weight"},
  };
  for (const auto& [value, name] : positive) {
    Status status = Positive(value, name);
    if (!status.ok()) return status;
  }
  const std::pair<double, const char*> non_negative[] = {
      {rich_arc, "rich_arc"},
      {rich_sigma_t, "rich_sigma_t"},
      {rich_sigma_r, "rich_sigma_r"},
      {yaw_noise, "yaw_noise"},
      {featureless_sigma_t, "featureless_sigma_t"},
      {featureless_sigma_r, "featureless_sigma_r"},
      {pixel_sigma, "pixel_sigma"},
      {depth_sigma, "depth_sigma"},
      {rotation_sigma, "rotation_sigma"},
      {translation_sigma, "translation_sigma"},
      {outlier_translation_sigma, "outlier_translation_sigma"},
      {continuous_arc, "continuous_arc"},
      {continuous_dominant_spread, "continuous_dominant_spread"},
  };
  for (const auto& [value, name] : non_negative) {
    Status status = NonNegative(value, name);
    if (!status.ok()) return status;
  }
  const std::pair<double, const char*> probability[] = {
      {outlier_fraction, "outlier_fraction"},
      {subset_view_probability, "subset_view_probability"},
      {dominant_mode_persistence, "dominant_mode_persistence"},
      {miss_probability, "miss_probability"},
  };
  for (const auto& [value, name] : probability) {
    Status status = Probability(value, name);
    if (!status.ok()) return status;
  }
  const std::pair<double, const char*> finite[] = {
      {camera_height, "camera_height"},
      {look_at_height, "look_at_height"},
      {start_angle, "start_angle"},
      {rich_arc_start, "rich_arc_start"},
      {yaw_bias, "yaw_bias"},
      {wall_z_min, "wall_z_min"},
      {wall_z_max, "wall_z_max"},
      {intrinsics.cx, "cx"},
      {intrinsics.cy, "cy"},
  };
  for (const auto& [value, name] : finite) {
    Status status = Finite(value, name);
    if (!status.ok()) return status;
  }
  if (rich_arc > kTwoPi) {
    return Status::Error("simulation option rich_arc must be <= 2 pi");
  }
  if (continuous_arc > kTwoPi) {
    return Status::Error("simulation option continuous_arc must be <= 2 pi");
  }
  if (wall_z_max < wall_z_min) {
    return Status::Error("simulation option wall_z_max must be >= wall_z_min");
  }
  if (!(weight_jitter >= 0.0 && weight_jitter < 1.0)) {
    return Status::Error("simulation option weight_jitter must be in [0, 1)");
  }
  const int num_outliers =
      static_cast<int>(std::lround(outlier_fraction * num_hypotheses));
  if (num_outliers >= num_hypotheses) {
    return Status::Error(
        "simulation option outlier_fraction leaves no inlier hypothesis");
  }
  if (orbit_radius >= wall_radius) {
    return Status::Error(
        "simulation options: the orbit must lie inside the wall "
        "(orbit_radius < wall_radius)");
  }
  return Status::Ok();
}

}  // namespace symba
