// `symba simulate`: simulates a scene and writes log.jsonl,
// gt_trajectory.tum and gt_objects.json atomically (docs/simulation.md).
// Every SimulationOptions field is a flag with its default; angles are in
// degrees on the command line. Without --keyframes a scene gets its own
// default number of keyframes (Scene::default_num_keyframes).
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "symba/geometry/angle.h"
#include "symba/simulation/scene.h"
#include "symba/simulation/simulator.h"
#include "tools/commands.h"

namespace {

constexpr double kDeg = symba::kPi / 180.0;

// An angle option of SimulationOptions (radians) shown in degrees.
struct DegreeFlag {
  const char* name;
  double symba::SimulationOptions::*field;
  const char* help;
  double degrees = 0.0;
};

struct SimulateFlags {
  std::string scene;
  std::string out;
  uint32_t seed = 1;
  bool quiet = false;
  symba::SimulationOptions options;
  const CLI::Option* keyframes = nullptr;  // --keyframes, to see if given
  std::vector<DegreeFlag> degree_flags = {
      {"--start-angle",
       &symba::SimulationOptions::start_angle,
       "orbit scenes: orbit angle of keyframe 0 (degrees)"},
      {"--min-visit-arc",
       &symba::SimulationOptions::min_visit_arc,
       "route scenes: least arc circled about a place per visit (degrees)"},
      {"--rich-arc-start",
       &symba::SimulationOptions::rich_arc_start,
       "bearing where the feature-rich arc begins (degrees; on the orbit, "
       "the orbit angle)"},
      {"--rich-arc",
       &symba::SimulationOptions::rich_arc,
       "length of the feature-rich arc of bearings (degrees)"},
      {"--rich-sigma-r",
       &symba::SimulationOptions::rich_sigma_r,
       "front-end rotation noise per rich keyframe (degrees per axis)"},
      {"--yaw-bias",
       &symba::SimulationOptions::yaw_bias,
       "front-end yaw drift per featureless keyframe (degrees)"},
      {"--yaw-noise",
       &symba::SimulationOptions::yaw_noise,
       "noise of the featureless yaw drift (degrees)"},
      {"--featureless-sigma-r",
       &symba::SimulationOptions::featureless_sigma_r,
       "front-end rotation noise per featureless keyframe (degrees per "
       "axis)"},
      {"--rotation-sigma",
       &symba::SimulationOptions::rotation_sigma,
       "hypothesis rotation noise (degrees per axis)"},
      {"--continuous-arc",
       &symba::SimulationOptions::continuous_arc,
       "arc a continuous object's hypotheses cover (degrees)"},
      {"--continuous-dominant-spread",
       &symba::SimulationOptions::continuous_dominant_spread,
       "spread of a continuous object's highest-weight angle between views "
       "(degrees)"},
  };

  SimulateFlags() {
    for (DegreeFlag& flag : degree_flags) {
      flag.degrees = options.*(flag.field) / kDeg;
    }
  }
};

std::string SceneHelp() {
  std::string help = "scene to simulate:";
  for (const std::string& name : symba::SceneNames()) {
    symba::Scene scene;
    if (symba::MakeScene(name, &scene).ok()) {
      help += "\n  " + name + ": " + scene.description;
    }
  }
  return help;
}

std::string KeyframesHelp() {
  std::string help = "number of keyframes; default: the scene's (";
  const int common = symba::SimulationOptions().num_keyframes;
  for (const std::string& name : symba::SceneNames()) {
    symba::Scene scene;
    if (symba::MakeScene(name, &scene).ok() &&
        scene.default_num_keyframes != common) {
      help += name + ": " + std::to_string(scene.default_num_keyframes) + ", ";
    }
  }
  return help + "else the value shown)";
}

// Adds the degree flag `name` of f->degree_flags.
void AddDegreeOption(CLI::App* cmd, SimulateFlags* f, const std::string& name) {
  for (DegreeFlag& flag : f->degree_flags) {
    if (name == flag.name) {
      cmd->add_option(flag.name, flag.degrees, flag.help)
          ->capture_default_str();
      return;
    }
  }
}

CLI::App* AddSimulateOptions(CLI::App* app, SimulateFlags* f) {
  CLI::App* cmd = app->add_subcommand(
      "simulate",
      "Simulate a camera orbiting a scene or touring its places "
      "(feature-rich and featureless views, multi-hypothesis detections) "
      "and write log.jsonl, gt_trajectory.tum and gt_objects.json");
  symba::SimulationOptions& o = f->options;
  cmd->add_option("--scene", f->scene, SceneHelp())
      ->required()
      ->check(CLI::IsMember(symba::SceneNames()));
  cmd->add_option("--out",
                  f->out,
                  "output directory (replaced atomically, parent must exist)")
      ->required();
  cmd->add_option("--seed", f->seed, "random seed")->capture_default_str();

  // Trajectory.
  f->keyframes =
      cmd->add_option("--keyframes", o.num_keyframes, KeyframesHelp())
          ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
          ->capture_default_str();
  cmd->add_option("--keyframes-per-loop",
                  o.keyframes_per_loop,
                  "orbit scenes: keyframes per orbit")
      ->check(CLI::Range(2, 1000000))
      ->capture_default_str();
  cmd->add_option(
         "--orbit-radius", o.orbit_radius, "orbit scenes: orbit radius (m)")
      ->capture_default_str();
  cmd->add_option(
         "--camera-height", o.camera_height, "camera height above floor (m)")
      ->capture_default_str();
  cmd->add_option("--look-at-height",
                  o.look_at_height,
                  "height of the point the camera looks at (m)")
      ->capture_default_str();
  AddDegreeOption(cmd, f, "--start-angle");
  cmd->add_option("--seconds-per-keyframe",
                  o.seconds_per_keyframe,
                  "time between keyframes (s)")
      ->capture_default_str();

  // Route (scenes with places).
  cmd->add_option("--route-step",
                  o.route_step,
                  "route scenes: path length between keyframes (m)")
      ->capture_default_str();
  cmd->add_option("--visit-radius",
                  o.visit_radius,
                  "route scenes: radius of the circle about a place (m)")
      ->capture_default_str();
  cmd->add_option("--visit-radius-variation",
                  o.visit_radius_variation,
                  "route scenes: relative change of the visit radius from "
                  "visit to visit, in [0, 1)")
      ->capture_default_str();
  AddDegreeOption(cmd, f, "--min-visit-arc");

  // Feature-rich and featureless sides.
  AddDegreeOption(cmd, f, "--rich-arc-start");
  AddDegreeOption(cmd, f, "--rich-arc");

  // Front end.
  cmd->add_option("--rich-sigma-t",
                  o.rich_sigma_t,
                  "front-end translation noise per rich keyframe (m per axis)")
      ->capture_default_str();
  AddDegreeOption(cmd, f, "--rich-sigma-r");
  AddDegreeOption(cmd, f, "--yaw-bias");
  AddDegreeOption(cmd, f, "--yaw-noise");
  AddDegreeOption(cmd, f, "--featureless-sigma-r");
  cmd->add_option(
         "--featureless-sigma-t",
         o.featureless_sigma_t,
         "front-end translation noise per featureless keyframe (m per axis)")
      ->capture_default_str();
  cmd->add_flag("--relocalize-on-rich",
                o.relocalize_on_rich,
                "reset the front end to the truth on rich keyframes");
  cmd->add_option("--with-odometry",
                  o.with_odometry,
                  "also write the front end's relative motion as odometry "
                  "(true/false)")
      ->capture_default_str();
  cmd->add_option("--odometry-sigma-t",
                  o.odometry_sigma_t,
                  "odometry sigma_t written on rich keyframes (m)")
      ->capture_default_str();
  cmd->add_option("--odometry-sigma-r",
                  o.odometry_sigma_r,
                  "odometry sigma_r written on rich keyframes (rad)")
      ->capture_default_str();
  cmd->add_option("--featureless-odometry-sigma-t",
                  o.featureless_odometry_sigma_t,
                  "odometry sigma_t written on featureless keyframes (m)")
      ->capture_default_str();
  cmd->add_option("--featureless-odometry-sigma-r",
                  o.featureless_odometry_sigma_r,
                  "odometry sigma_r written on featureless keyframes (rad)")
      ->capture_default_str();

  // Map points.
  cmd->add_option(
         "--points", o.num_points, "orbit scenes: map points on the wall")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option(
         "--wall-radius", o.wall_radius, "orbit scenes: wall radius (m)")
      ->capture_default_str();
  cmd->add_option("--points-per-place",
                  o.points_per_place,
                  "route scenes: map points on the wall about each place")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--place-wall-radius",
                  o.place_wall_radius,
                  "route scenes: radius of the wall about each place (m)")
      ->capture_default_str();
  cmd->add_option("--wall-z-min", o.wall_z_min, "lowest wall point (m)")
      ->capture_default_str();
  cmd->add_option("--wall-z-max", o.wall_z_max, "highest wall point (m)")
      ->capture_default_str();
  cmd->add_option("--pixel-sigma", o.pixel_sigma, "pixel noise (px per axis)")
      ->capture_default_str();
  cmd->add_option(
         "--depth-sigma", o.depth_sigma, "noise of a point's depth (m)")
      ->capture_default_str();
  cmd->add_option("--depth-every-observation",
                  o.depth_every_observation,
                  "every point observation carries its depth, as from an "
                  "RGB-D camera; false: only the first (true/false)")
      ->capture_default_str();
  cmd->add_option("--min-point-depth",
                  o.min_point_depth,
                  "nearest observed point depth (m)")
      ->capture_default_str();
  cmd->add_option("--fx", o.intrinsics.fx, "focal length x (px)")
      ->capture_default_str();
  cmd->add_option("--fy", o.intrinsics.fy, "focal length y (px)")
      ->capture_default_str();
  cmd->add_option("--cx", o.intrinsics.cx, "principal point x (px)")
      ->capture_default_str();
  cmd->add_option("--cy", o.intrinsics.cy, "principal point y (px)")
      ->capture_default_str();
  cmd->add_option("--width", o.image_width, "image width (px)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--height", o.image_height, "image height (px)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();

  // Detector.
  cmd->add_option("--hypotheses", o.num_hypotheses, "hypotheses per detection")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--single-hypothesis",
                  o.single_hypothesis,
                  "a single-pose detector: one hypothesis per detection at a "
                  "random one of the symmetric poses (--outlier-fraction is "
                  "then the probability of an outlier)")
      ->capture_default_str();
  AddDegreeOption(cmd, f, "--rotation-sigma");
  cmd->add_option("--translation-sigma",
                  o.translation_sigma,
                  "hypothesis translation noise (m per axis)")
      ->capture_default_str();
  cmd->add_option("--outlier-fraction",
                  o.outlier_fraction,
                  "fraction of outlier hypotheses")
      ->capture_default_str();
  cmd->add_option("--outlier-translation-sigma",
                  o.outlier_translation_sigma,
                  "outlier hypothesis translation noise (m per axis)")
      ->capture_default_str();
  cmd->add_option("--subset-view-probability",
                  o.subset_view_probability,
                  "probability that a view of a discrete object shows only "
                  "some of its modes")
      ->capture_default_str();
  cmd->add_option("--dominant-mode-persistence",
                  o.dominant_mode_persistence,
                  "probability that the highest-weight mode stays that of "
                  "the previous view")
      ->capture_default_str();
  AddDegreeOption(cmd, f, "--continuous-arc");
  AddDegreeOption(cmd, f, "--continuous-dominant-spread");
  cmd->add_option("--dominant-weight",
                  o.dominant_weight,
                  "weight of the dominant mode's hypotheses")
      ->capture_default_str();
  cmd->add_option(
         "--other-weight", o.other_weight, "weight of every other hypothesis")
      ->capture_default_str();
  cmd->add_option("--weight-jitter",
                  o.weight_jitter,
                  "relative uniform jitter of every weight")
      ->capture_default_str();
  cmd->add_option("--miss-probability",
                  o.miss_probability,
                  "probability that a visible object is not detected")
      ->capture_default_str();
  cmd->add_option("--max-detection-range",
                  o.max_detection_range,
                  "farthest detected object centre (m)")
      ->capture_default_str();
  cmd->add_option("--declare-noise,--write-detection-sigmas",
                  o.write_detection_sigmas,
                  "the detector declares its noise: write it as each "
                  "detection's sigma_t, sigma_r (true/false; false draws the "
                  "same detections without them)")
      ->capture_default_str();
  cmd->add_option("--write-class-priors",
                  o.write_class_priors,
                  "write the true class symmetries into the log header "
                  "(true/false)")
      ->capture_default_str();

  cmd->add_flag("--quiet", f->quiet, "no summary on stdout");
  return cmd;
}

int RunSimulate(SimulateFlags* f) {
  for (const DegreeFlag& flag : f->degree_flags) {
    f->options.*(flag.field) = flag.degrees * kDeg;
  }
  symba::Scene scene;
  if (f->keyframes->count() == 0 && symba::MakeScene(f->scene, &scene).ok()) {
    f->options.num_keyframes = scene.default_num_keyframes;
  }
  symba::SimulatedSequence sequence;
  symba::Status status =
      symba::Simulate(f->scene, f->options, f->seed, &sequence);
  if (status.ok()) status = symba::WriteSimulation(sequence, f->out);
  if (!status.ok()) {
    std::fprintf(stderr, "symba simulate: %s\n", status.message().c_str());
    return 1;
  }
  if (!f->quiet) {
    int detections = 0;
    int rich = 0;
    for (const auto& truths : sequence.detections) {
      detections += static_cast<int>(truths.size());
    }
    for (const bool r : sequence.rich) rich += r ? 1 : 0;
    std::printf(
        "symba simulate: scene %s, seed %u: %zu keyframes (%d rich), %zu "
        "objects, %d detections, %zu map points -> %s\n",
        sequence.scene.c_str(),
        static_cast<unsigned>(sequence.seed),
        sequence.keyframes.size(),
        rich,
        sequence.objects.size(),
        detections,
        sequence.points_w.size(),
        f->out.c_str());
  }
  return 0;
}

}  // namespace

void RegisterSimulateCommand(CLI::App* app, int* exit_code) {
  auto flags = std::make_shared<SimulateFlags>();
  CLI::App* command = AddSimulateOptions(app, flags.get());
  command->callback(
      [flags, exit_code] { *exit_code = RunSimulate(flags.get()); });
}
