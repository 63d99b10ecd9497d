// `symba import tum`: converts a front end's TUM trajectory and per-object
// TUM files of detector poses into a log v1, written atomically
// (docs/import.md).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "symba/import/class_prior_spec.h"
#include "symba/import/tum_import.h"
#include "tools/commands.h"

namespace {

struct ImportTumFlags {
  std::string out;
  std::vector<std::string> objects;       // NAME=FILE
  std::vector<std::string> class_priors;  // NAME=SPEC
  double detection_sigma_t = 0.0;         // 0: not given
  double detection_sigma_r = 0.0;
  bool quiet = false;
  symba::TumImportOptions options;
};

int Fail(const std::string& message) {
  std::fprintf(stderr, "symba import tum: %s\n", message.c_str());
  return 1;
}

int RunImportTum(ImportTumFlags f) {
  for (const std::string& object : f.objects) {
    const std::size_t equals = object.find('=');
    if (equals == std::string::npos || equals == 0 ||
        equals + 1 == object.size()) {
      return Fail("--object \"" + object + "\": expected NAME=FILE");
    }
    f.options.objects.push_back(
        {object.substr(0, equals), object.substr(equals + 1)});
  }
  for (const std::string& spec : f.class_priors) {
    std::string name;
    symba::ClassPrior prior;
    const symba::Status status =
        symba::ParseClassPriorSpec(spec, &name, &prior);
    if (!status.ok()) return Fail(status.message());
    f.options.classes[name] = prior;
  }
  if (f.detection_sigma_t > 0.0) {
    f.options.detection_sigma_t = f.detection_sigma_t;
  }
  if (f.detection_sigma_r > 0.0) {
    f.options.detection_sigma_r = f.detection_sigma_r;
  }
  symba::TumImportCounts counts;
  const symba::Status status = symba::ImportTumToLog(f.options, f.out, &counts);
  if (!status.ok()) return Fail(status.message());
  if (!f.quiet) {
    std::fprintf(stderr,
                 "symba import tum: wrote %s: %d keyframes, %d detections\n",
                 f.out.c_str(),
                 counts.keyframes,
                 counts.detections);
  }
  return 0;
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
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--odometry-sigma-t",
                  o.odometry_sigma_t,
                  "odometry translation noise (m)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--odometry-sigma-r",
                  o.odometry_sigma_r,
                  "odometry rotation noise (rad)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--first-pose",
                  o.first_pose,
                  "a TUM trajectory (e.g. ground truth) whose pose at the "
                  "first frame's time is the first keyframe's T_wc "
                  "(default: the front end's first pose)");
  cmd->add_option("--detection-sigma-t",
                  f->detection_sigma_t,
                  "detection translation noise (m), written on every "
                  "detection (default: none, the backend's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--detection-sigma-r",
                  f->detection_sigma_r,
                  "detection rotation noise (rad), written on every "
                  "detection (default: none, the backend's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--class-prior",
                  f->class_priors,
                  "NAME=asymmetric | NAME=discrete:ORDER[:ax,ay,az] | "
                  "NAME=continuous[:ax,ay,az]; repeatable")
      ->allow_extra_args(false);
  cmd->add_flag("--quiet", f->quiet, "no summary line on stderr");
  cmd->callback([f, exit_code] { *exit_code = RunImportTum(*f); });
}
