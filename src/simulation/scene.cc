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

// A scene the camera orbits (no places).
Scene OrbitScene(const char* name,
                 const char* description,
                 std::vector<SimulatedObject> objects) {
  Scene scene;
  scene.name = name;
  scene.description = description;
  scene.objects = std::move(objects);
  return scene;
}

Scene Disc() {
  return OrbitScene(
      "disc",
      "a rectangular table (2-fold) at the centre: the paper's sim(disc)",
      {RectangularTable(kCentre, 0.3)});
}

Scene Cts() {
  return OrbitScene(
      "cts",
      "a round table (continuous) at the centre: the paper's sim(cts)",
      {RoundTable(kCentre, 0.3)});
}

Scene Asym() {
  return OrbitScene("asym",
                    "a chair (asymmetric) at the centre",
                    {Chair(Eigen::Vector3d(0.05, -0.05, 0.45), 0.3)});
}

Scene Square() {
  return OrbitScene("square",
                    "a square table (4-fold) at the centre",
                    {SquareTable(kCentre, 0.3)});
}

Scene Room() {
  // The two round tables are 1.3 m apart: same class, close enough that
  // a loose association gate could merge them.
  return OrbitScene(
      "room",
      "a rectangular table, two round tables 1.3 m apart, a chair and a "
      "3-fold prism with a tilted axis",
      {RectangularTable(kCentre, 0.3),
       RoundTable(Eigen::Vector3d(0.9, 0.7, 0.375), 0.0),
       RoundTable(Eigen::Vector3d(-0.4, 0.9, 0.375), 1.0),
       Chair(Eigen::Vector3d(-1.0, -0.4, 0.45), 2.0),
       Prism(Eigen::Vector3d(0.7, -0.9, 0.25), 0.8, 30.0 * kDeg)});
}

// The long scene: six places of 3-5 objects on a 3 x 2 grid, 7 m apart.
enum class Kind { kChair, kTable, kSquareTable, kRoundTable, kTiltedPrism };

// Heights of the objects' frames (bounding-box centres) above the floor.
constexpr double kTableHeight = 0.375;  // m
constexpr double kChairHeight = 0.45;   // m
constexpr double kPrismHeight = 0.25;   // m

SimulatedObject MakeObject(Kind kind, const Eigen::Vector2d& xy, double yaw) {
  const Eigen::Vector3d table(xy.x(), xy.y(), kTableHeight);
  switch (kind) {
    case Kind::kChair:
      return Chair(Eigen::Vector3d(xy.x(), xy.y(), kChairHeight), yaw);
    case Kind::kTable:
      return RectangularTable(table, yaw);
    case Kind::kSquareTable:
      return SquareTable(table, yaw);
    case Kind::kRoundTable:
      return RoundTable(table, yaw);
    case Kind::kTiltedPrism:
      break;  // below: the compiler wants a return after the switch
  }
  return Prism(Eigen::Vector3d(xy.x(), xy.y(), kPrismHeight), yaw, 30 * kDeg);
}

// Neighbouring objects of a place are this far apart, so that association
// can tell two objects of one class apart (the room's tables: 1.3 m).
constexpr double kObjectSpacing = 1.45;  // m

// Adds a place at `centre`: `kinds` evenly spaced on a ring whose chord
// between neighbours is kObjectSpacing (radius s / (2 sin(pi / n))),
// starting at angle `phase`; yaws differ from object to object.
void AddPlace(const Eigen::Vector2d& centre,
              double phase,
              const std::vector<Kind>& kinds,
              Scene* scene) {
  const int n = static_cast<int>(kinds.size());
  const double ring = kObjectSpacing / (2.0 * std::sin(kPi / n));
  for (int i = 0; i < n; ++i) {
    const double angle = phase + kTwoPi * i / n;
    const Eigen::Vector2d xy =
        centre + ring * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    scene->objects.push_back(MakeObject(kinds[i], xy, phase + 1.1 * i));
  }
  scene->tour.push_back(static_cast<int>(scene->places.size()));
  scene->places.push_back(centre);
}

Scene Long() {
  constexpr double kSpacing = 7.0;  // m between neighbouring places
  Scene scene;
  scene.name = "long";
  scene.description =
      "23 objects (chairs, 2- and 4-fold tables, round tables, a tilted "
      "prism) at six places 7 m apart, toured lap after lap; 10000 "
      "keyframes unless --keyframes";
  scene.default_num_keyframes = 10000;
  // Listed in tour order: along the row y = 0, back along y = 7.
  using K = Kind;
  AddPlace({0.0, 0.0}, 0.2, {K::kTable, K::kChair, K::kRoundTable}, &scene);
  AddPlace({kSpacing, 0.0},
           0.5,
           {K::kSquareTable, K::kChair, K::kRoundTable, K::kChair},
           &scene);
  AddPlace({2 * kSpacing, 0.0},
           1.0,
           {K::kTable, K::kRoundTable, K::kTiltedPrism, K::kChair},
           &scene);
  AddPlace({2 * kSpacing, kSpacing},
           -0.4,
           {K::kSquareTable, K::kTable, K::kChair},
           &scene);
  AddPlace(
      {kSpacing, kSpacing},
      0.8,
      {K::kRoundTable, K::kRoundTable, K::kTable, K::kChair, K::kSquareTable},
      &scene);
  AddPlace({0.0, kSpacing},
           -0.9,
           {K::kChair, K::kTable, K::kSquareTable, K::kRoundTable},
           &scene);
  return scene;
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
  return {"disc", "cts", "asym", "square", "room", "long"};
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
  } else if (name == "long") {
    *scene = Long();
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
  if (points_per_place < 0) {
    return Status::Error("simulation option points_per_place must be >= 0");
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
      {route_step, "route_step"},
      {visit_radius, "visit_radius"},
      {place_wall_radius, "place_wall_radius"},
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
      {min_visit_arc, "min_visit_arc"},
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
  if (min_visit_arc > kTwoPi) {
    return Status::Error("simulation option min_visit_arc must be <= 2 pi");
  }
  if (!(visit_radius_variation >= 0.0 && visit_radius_variation < 1.0)) {
    return Status::Error(
        "simulation option visit_radius_variation must be in [0, 1)");
  }
  if (visit_radius * (1.0 + visit_radius_variation) >= place_wall_radius) {
    return Status::Error(
        "simulation options: the visits must lie inside the places' walls "
        "(visit_radius (1 + visit_radius_variation) < place_wall_radius)");
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
  if (single_hypothesis &&
      !(outlier_fraction >= 0.0 && outlier_fraction < 1.0)) {
    return Status::Error(
        "simulation option outlier_fraction must be in [0, 1) with "
        "single_hypothesis (the probability that a detection is an outlier)");
  }
  const int num_outliers =
      static_cast<int>(std::lround(outlier_fraction * num_hypotheses));
  if (!single_hypothesis && num_outliers >= num_hypotheses) {
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
