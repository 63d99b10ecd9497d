// `symba export bop`: a log v1 as the files `symba import bop` reads (a
// BOP results CSV, scene_camera.json, models_info.json) plus the front end
// as a TUM trajectory with the image times, written atomically as one
// directory (docs/import.md "Export").
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "symba/export/bop_export.h"
#include "symba/io/file_output.h"
#include "tools/commands.h"

namespace {

struct ExportBopFlags {
  std::string log;
  std::string out;
  std::string gt_objects;
  bool quiet = false;
  symba::BopExportOptions options;
};

// "symba export bop: MESSAGE" on stderr; the exit status 1.
int Fail(const std::string& message) {
  std::fprintf(stderr, "symba export bop: %s\n", message.c_str());
  return 1;
}

int RunExportBop(ExportBopFlags f) {
  if (!f.gt_objects.empty()) {
    symba::Status status =
        symba::CheckOutputSparesInputs(f.out, {f.gt_objects});
    if (status.ok()) {
      status = symba::ClassSymmetriesFromGroundTruth(f.gt_objects,
                                                     &f.options.symmetries);
    }
    if (!status.ok()) return Fail(status.message());
  }
  symba::BopExportReport report;
  const symba::Status status =
      symba::ExportLogToBopDirectory(f.log, f.options, f.out, &report);
  if (!status.ok()) return Fail(status.message());
  if (!f.quiet) {
    for (const std::string& note : report.notes) {
      std::fprintf(stderr, "symba export bop: note: %s\n", note.c_str());
    }
    std::fprintf(stderr,
                 "symba export bop: wrote %s: %d images, %d rows, %zu "
                 "classes\n",
                 f.out.c_str(),
                 report.images,
                 report.rows,
                 report.obj_ids.size());
  }
  return 0;
}

}  // namespace

void RegisterExportCommand(CLI::App* app, int* exit_code) {
  CLI::App* command =
      app->add_subcommand("export", "Export a log v1 to another format (bop)");
  command->require_subcommand(1);
  auto flags = std::make_shared<ExportBopFlags>();
  CLI::App* bop = command->add_subcommand(
      "bop",
      "A log v1 as BOP files: results.csv (every hypothesis a row), "
      "scene_camera.json, models_info.json, image_times.txt, frontend.tum, "
      "class_names.txt");
  bop->add_option("LOG", flags->log, "the log v1 to export")->required();
  bop->add_option("--out",
                  flags->out,
                  "output directory (replaced atomically, parent must exist)")
      ->required();
  bop->add_option("--gt-objects",
                  flags->gt_objects,
                  "a simulation's gt_objects.json: the classes' symmetries "
                  "for models_info.json (default: the log header's class "
                  "priors)");
  bop->add_option("--scene-id", flags->options.scene_id, "the BOP scene_id")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  bop->add_option("--diameter",
                  flags->options.diameter,
                  "every object's models_info diameter (m); the importer's "
                  "gate is half of it")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  bop->add_flag("--quiet", flags->quiet, "no summary on stderr");
  bop->callback([flags, exit_code] { *exit_code = RunExportBop(*flags); });
}
