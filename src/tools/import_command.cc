// `symba import tum`: converts a front end's TUM trajectory and per-object
// TUM files of detector poses into a log v1, written atomically
// (docs/import.md).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "symba/import/bop_import.h"
#include "symba/import/class_prior_spec.h"
#include "symba/import/tum_import.h"
#include "tools/commands.h"

namespace {

// "symba import FORMAT: MESSAGE" on stderr; the exit status 1.
int Fail(const char* format, const std::string& message) {
  std::fprintf(stderr, "symba import %s: %s\n", format, message.c_str());
  return 1;
}

// --detection-sigma-t/-r, shared by every importer: written on every
// detection when given.
struct DetectionSigmaFlags {
  double t = 0.0;  // 0: not given
  double r = 0.0;

  void Register(CLI::App* cmd) {
    cmd->add_option("--detection-sigma-t",
                    t,
                    "detection translation noise (m), written on every "
                    "detection (default: none, the backend's)")
        ->check(CLI::PositiveNumber & symba::tools::FiniteNumber());
    cmd->add_option("--detection-sigma-r",
                    r,
                    "detection rotation noise (rad), written on every "
                    "detection (default: none, the backend's)")
        ->check(CLI::PositiveNumber & symba::tools::FiniteNumber());
  }
  void Apply(std::optional<double>* sigma_t,
             std::optional<double>* sigma_r) const {
    if (t > 0.0) *sigma_t = t;
    if (r > 0.0) *sigma_r = r;
  }
};

struct ImportTumFlags {
  std::string out;
  std::vector<std::string> objects;       // NAME=FILE
  std::vector<std::string> class_priors;  // NAME=SPEC
  DetectionSigmaFlags sigma;
  bool quiet = false;
  symba::TumImportOptions options;
};

int RunImportTum(ImportTumFlags f) {
  for (const std::string& object : f.objects) {
    const std::size_t equals = object.find('=');
    if (equals == std::string::npos || equals == 0 ||
        equals + 1 == object.size()) {
      return Fail("tum", "--object \"" + object + "\": expected NAME=FILE");
    }
    f.options.objects.push_back(
        {object.substr(0, equals), object.substr(equals + 1)});
  }
  for (const std::string& spec : f.class_priors) {
    std::string name;
    symba::ClassPrior prior;
    const symba::Status status =
        symba::ParseClassPriorSpec(spec, &name, &prior);
    if (!status.ok()) return Fail("tum", status.message());
    f.options.classes[name] = prior;
  }
  f.sigma.Apply(&f.options.detection_sigma_t, &f.options.detection_sigma_r);
  symba::TumImportCounts counts;
  const symba::Status status = symba::ImportTumToLog(f.options, f.out, &counts);
  if (!status.ok()) return Fail("tum", status.message());
  for (const std::string& warning : counts.warnings) {
    std::fprintf(stderr, "symba import tum: warning: %s\n", warning.c_str());
  }
  if (!f.quiet) {
    for (const std::string& note : counts.notes) {
      std::fprintf(stderr, "symba import tum: note: %s\n", note.c_str());
    }
    std::fprintf(stderr,
                 "symba import tum: wrote %s: %d keyframes, %d detections\n",
                 f.out.c_str(),
                 counts.keyframes,
                 counts.detections);
  }
  return 0;
}

struct ImportBopFlags {
  std::string out;
  std::string class_names;  // obj_id=name,...
  int scene = -1;           // -1: not given
  double gate = 0.0;        // 0: not given
  DetectionSigmaFlags sigma;
  bool quiet = false;
  symba::BopImportOptions options;
};

int RunImportBop(ImportBopFlags f) {
  if (!f.class_names.empty()) {
    const symba::Status status =
        symba::ParseBopClassNames(f.class_names, &f.options.class_names);
    if (!status.ok()) return Fail("bop", status.message());
  }
  if (f.scene >= 0) f.options.scene = f.scene;
  if (f.gate > 0.0) f.options.gate = f.gate;
  f.sigma.Apply(&f.options.detection_sigma_t, &f.options.detection_sigma_r);
  symba::BopImportReport report;
  const symba::Status status = symba::ImportBopToLog(f.options, f.out, &report);
  if (!status.ok()) return Fail("bop", status.message());
  if (!f.quiet) {
    for (const std::string& note : report.symmetry_notes) {
      std::fprintf(stderr, "symba import bop: %s\n", note.c_str());
    }
    std::fprintf(stderr,
                 "symba import bop: wrote %s: %d keyframes, %d detections "
                 "from %d rows",
                 f.out.c_str(),
                 report.keyframes,
                 report.detections,
                 report.rows);
    if (report.skipped_images > 0) {
      std::fprintf(stderr,
                   "; skipped %d images without a pose and their %d rows",
                   report.skipped_images,
                   report.skipped_rows);
    }
    if (report.other_scene_rows > 0) {
      std::fprintf(
          stderr, "; skipped %d rows of other scenes", report.other_scene_rows);
    }
    std::fprintf(stderr, "\n");
  }
  return 0;
}

void RegisterImportBop(CLI::App* import, int* exit_code) {
  auto f = std::make_shared<ImportBopFlags>();
  symba::BopImportOptions& o = f->options;
  CLI::App* cmd = import->add_subcommand(
      "bop",
      "A detector's BOP results CSV, the dataset's scene_camera.json (and "
      "models_info.json), with the camera poses of scene_camera.json or a "
      "front end's TUM trajectory -> a log v1: a keyframe per image, the "
      "rows of one object near each other in one image as one detection's "
      "hypotheses");
  cmd->add_option("--results", o.results, "the BOP results CSV")->required();
  cmd->add_option("--scene-camera", o.scene_camera, "scene_camera.json")
      ->required();
  cmd->add_option("--models-info",
                  o.models_info,
                  "models_info.json: diameters (the default gate) and "
                  "symmetries (class priors)");
  cmd->add_option("--trajectory",
                  o.trajectory,
                  "a front end's TUM trajectory T_wc (instead of "
                  "scene_camera.json's cam_R_w2c, cam_t_w2c)");
  cmd->add_option("--image-times",
                  o.image_times,
                  "\"im_id timestamp\" lines or TUM's rgb.txt; the "
                  "keyframes' timestamps (required with --trajectory)");
  cmd->add_option("--time-tolerance",
                  o.time_tolerance,
                  "largest image-to-trajectory time difference (s)")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_flag("--skip-images-without-pose",
                o.skip_images_without_pose,
                "skip (and count) images without a pose instead of failing");
  cmd->add_option("--scene",
                  f->scene,
                  "the scene_id to import (default: the CSV's only scene)")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber());
  cmd->add_option(
      "--class-names", f->class_names, "obj_id=name,... (default: obj_<id>)");
  cmd->add_option("--gate",
                  f->gate,
                  "rows of one object in one image within this distance (m) "
                  "are one detection (default: half the diameter from "
                  "models_info, else 0.05)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber());
  f->sigma.Register(cmd);
  cmd->add_option("--out", f->out, "the log to write (replaced atomically)")
      ->required();
  cmd->add_flag("--quiet", f->quiet, "no summary on stderr");
  cmd->callback([f, exit_code] { *exit_code = RunImportBop(*f); });
}

}  // namespace

void RegisterImportCommand(CLI::App* app, int* exit_code) {
  CLI::App* import = app->add_subcommand(
      "import", "Convert other formats into a log v1 (docs/import.md)");
  import->require_subcommand(1);
  auto f = std::make_shared<ImportTumFlags>();
  symba::TumImportOptions& o = f->options;
  CLI::App* cmd = import->add_subcommand(
      "tum",
      "A front end's TUM trajectory (T_wc) and per-object TUM files of "
      "detector poses (T_co) -> a log v1: keyframes every --stride frames, "
      "odometry between them, one single-hypothesis detection per detected "
      "object and keyframe");
  cmd->add_option("--trajectory",
                  o.trajectory,
                  "the front end's TUM trajectory T_wc; one line per frame")
      ->required();
  cmd->add_option("--out", f->out, "the log to write (replaced atomically)")
      ->required();
  cmd->add_option("--object",
                  f->objects,
                  "NAME=FILE: a TUM file of T_co poses of one object of "
                  "class NAME (all-zero row: not detected); repeatable")
      ->allow_extra_args(false);
  cmd->add_option("--stride", o.stride, "a keyframe every N frames")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--odometry-sigma-t",
                  o.odometry_sigma_t,
                  "odometry translation noise (m)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--odometry-sigma-r",
                  o.odometry_sigma_r,
                  "odometry rotation noise (rad)")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--first-pose",
                  o.first_pose,
                  "a TUM trajectory (e.g. ground truth) whose pose at the "
                  "first frame's time is the first keyframe's T_wc "
                  "(default: the front end's first pose)");
  cmd->add_option("--time-tolerance",
                  o.time_tolerance,
                  "largest time difference (s) between a row of an object "
                  "or --first-pose file and the trajectory's frame nearest "
                  "to it")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  f->sigma.Register(cmd);
  cmd->add_option("--class-prior",
                  f->class_priors,
                  "NAME=asymmetric | NAME=discrete:ORDER[:ax,ay,az] | "
                  "NAME=continuous[:ax,ay,az]; repeatable")
      ->allow_extra_args(false);
  cmd->add_flag("--quiet",
                f->quiet,
                "no notes and no summary line on stderr (warnings stay)");
  cmd->callback([f, exit_code] { *exit_code = RunImportTum(*f); });
  RegisterImportBop(import, exit_code);
}
