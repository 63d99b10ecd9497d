// `symba replay`: replays a log v1 through the backend and writes the four
// output files atomically (docs/replay.md).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>

#include "symba/backend/backend_option_table.h"
#include "symba/common/check.h"
#include "symba/common/count_phrase.h"
#include "symba/export/refined_bop_results.h"
#include "symba/geometry/angle.h"
#include "symba/io/file_output.h"
#include "symba/io/map_file.h"
#include "symba/io/pose_graph.h"
#include "symba/pose_graph/optimize_pose_graph.h"
#include "symba/replay/replay.h"
#include "symba/replay/replay_output.h"
#include "tools/commands.h"
#include "tools/option_flags.h"

namespace {

constexpr double kDeg = symba::kPi / 180.0;

// Flags of `symba replay`, bound to their defaults.
struct ReplayFlags {
  std::string log;
  std::string out;
  std::string mode = "window";
  std::string bop_out;      // --bop-out: the refined poses as BOP results
  int bop_scene = -1;       // --bop-scene; -1: the log header's
  std::string map_in;       // --map-in: start from this map file
  std::string map_out;      // --map-out: write the map at the end here
  bool relocalize = false;  // --relocalize: the log's frame is unknown
  bool quiet = false;
  bool final_batch = false;
  bool g2o_isotropic = false;
  std::string g2o_initialization = "chordal";
  symba::BackendOptions backend;
};

// The flags `symba replay` had before they were made from the option table,
// kept so that existing scripts work: another name for the field's flag.
struct FlagAlias {
  const char* field;
  const char* flag;
};

constexpr FlagAlias kFlagAliases[] = {
    {"window_size", "--window"},
    {"window_policy", "--window-policy"},
    {"marginalize_min_margin", "--marginalize-min-margin"},
    {"marginalize_rival_distance", "--marginalize-rival-distance"},
    {"chain_prior", "--chain-prior"},
    {"max_iterations", "--max-iterations"},
    {"batch_max_iterations", "--batch-max-iterations"},
    {"num_threads", "--threads"},
    {"hypothesis_sigma_t", "--hypothesis-sigma-t"},
    {"hypothesis_sigma_r", "--hypothesis-sigma-r"},
    {"axis_sigma", "--axis-sigma"},
    {"merge_modes", "--merge-modes"},
    {"object_loss", "--loss"},
    {"object_loss_scale", "--loss-scale"},
    {"frontend_sigma_t", "--frontend-sigma-t"},
    {"frontend_sigma_r", "--frontend-sigma-r"},
    {"point_sigma_px", "--point-sigma"},
    {"point_depth_sigma_relative", "--point-depth-sigma"},
    {"gate_position", "--gate-position"},
    {"confirm_keyframes", "--confirm-keyframes"},
    {"tentative_timeout", "--tentative-timeout"},
    {"gate_sigmas", "--gate-sigmas"},
    {"estimate_noise", "--estimate-noise"},
    {"claimed_noise_tolerance", "--claimed-noise-tolerance"},
    {"uncalibrated_sigma_t", "--uncalibrated-sigma-t"},
    {"uncalibrated_sigma_r", "--uncalibrated-sigma-r"},
    {"min_support", "--min-support"},
    {"upgrade_evidence", "--upgrade-evidence"},
    {"upgrade_min_fraction", "--upgrade-min-fraction"},
    {"upgrade_confusion_rate", "--upgrade-confusion-rate"},
    {"upgrade_odds", "--upgrade-odds"},
    {"max_upgrade_order", "--max-upgrade-order"},
};

// The old angle gates, in degrees (the fields and their flags are in rad).
constexpr FlagAlias kDegreeAliases[] = {
    {"gate_axis", "--gate-axis"},
    {"gate_rotation", "--gate-rotation"},
    {"gate_angle", "--gate-angle"},
};

// "--window_size,--window": the field's flag and its old names.
std::string FlagNames(const std::string& field) {
  std::string names = symba::tools::FlagName(field);
  for (const FlagAlias& alias : kFlagAliases) {
    if (field == alias.field) names += std::string(",") + alias.flag;
  }
  return names;
}

const symba::OptionField<symba::BackendOptions>& TableField(
    const std::string& name) {
  const symba::OptionField<symba::BackendOptions>* field =
      symba::FindOption(symba::BackendOptionTable(), name);
  SYMBA_CHECK(field != nullptr) << "no option " << name;
  return *field;
}

// "--gate-axis 20": the field in degrees.
void AddDegreeAlias(CLI::App* cmd, const FlagAlias& alias, ReplayFlags* f) {
  const symba::OptionField<symba::BackendOptions>* field =
      &TableField(alias.field);
  symba::BackendOptions* options = &f->backend;
  const double default_deg = std::get<double>(field->get(*options)) / kDeg;
  char shown[32];
  std::snprintf(shown, sizeof shown, "%.6g", default_deg);
  cmd->add_option_function<double>(
         alias.flag,
         [field, options](const double& degrees) {
           field->set(degrees * kDeg, options);
         },
         "the same as --" + field->name + " in degrees")
      ->check(symba::tools::RangeValidator(
          symba::tools::ScaledRange(field->range, kDeg)))
      ->default_str(shown);
}

// Every backend option from the table, then the old flags that are not
// just another name (the gates in degrees, --null-hypothesis).
void AddBackendFlags(CLI::App* cmd, ReplayFlags* f) {
  // An alias that names no field aborts every start (any test catches it).
  for (const FlagAlias& alias : kFlagAliases) TableField(alias.field);
  for (const auto& field : symba::BackendOptionTable()) {
    symba::tools::AddOptionFlag(cmd, FlagNames(field.name), field, &f->backend);
  }
  for (const FlagAlias& alias : kDegreeAliases) AddDegreeAlias(cmd, alias, f);
  cmd->add_flag("--null-hypothesis",
                f->backend.mixture.use_null_hypothesis,
                "the same as --mixture.use_null_hypothesis true");
}

CLI::App* AddReplayOptions(CLI::App* app, ReplayFlags* f) {
  CLI::App* cmd = app->add_subcommand(
      "replay",
      "Replay a log v1 (or optimise a .g2o pose graph) and write "
      "trajectory.tum, objects.json, associations.csv and summary.json");
  cmd->add_option(
         "LOG", f->log, "log v1 file (JSON Lines), or a .g2o 3-D pose graph")
      ->required();
  cmd->add_option("--out",
                  f->out,
                  "output directory (replaced atomically, parent must exist)")
      ->required();
  cmd->add_option("--mode",
                  f->mode,
                  "window: optimise the window after each keyframe; batch: "
                  "one solve at the end")
      ->check(CLI::IsMember({"window", "batch"}))
      ->capture_default_str();
  cmd->add_flag("--final-batch",
                f->final_batch,
                "window mode: one batch solve over every factor after the "
                "last keyframe");
  AddBackendFlags(cmd, f);
  cmd->add_flag("--g2o-isotropic",
                f->g2o_isotropic,
                "g2o input: replace each edge's information by SE-Sync's "
                "isotropic one (needed for files with indefinite information)");
  cmd->add_option("--g2o-initialization",
                  f->g2o_initialization,
                  "g2o input: where the solver starts: chordal (rotations "
                  "by chordal relaxation, then translations, from the "
                  "measurements alone) or given (the file's vertices)")
      ->check(CLI::IsMember({"chordal", "given"}))
      ->capture_default_str();
  cmd->add_option("--bop-out",
                  f->bop_out,
                  "also write the refined object poses per keyframe image "
                  "as BOP results (scene_id,im_id,obj_id,score,R,t,time; "
                  "written atomically)");
  cmd->add_option("--bop-scene",
                  f->bop_scene,
                  "--bop-out: the BOP scene id (default: the log header's "
                  "bop.scene_id, written by symba import bop)")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber());
  cmd->add_option("--map-in",
                  f->map_in,
                  "start from this map (a map file written by --map-out; "
                  "docs/map-format.md): its objects with their ids and "
                  "covariances, its classes' noise; the log's poses are in "
                  "the map's frame");
  cmd->add_flag("--relocalize",
                f->relocalize,
                "--map-in: the log's poses are not in the map's frame; find "
                "where the log is from the objects it maps, then go on in "
                "the map's frame (docs/relocalization.md)");
  cmd->add_option("--map-out",
                  f->map_out,
                  "also write the map at the end as a map file (written "
                  "atomically; docs/map-format.md)");
  cmd->add_flag(
      "--quiet", f->quiet, "no progress and no summary line on stderr");
  return cmd;
}

// "symba replay: MESSAGE" on stderr; the exit status 1.
int Fail(const std::string& message) {
  std::fprintf(stderr, "symba replay: %s\n", message.c_str());
  return 1;
}

// The directory a file is to be written into must exist (checked before
// anything is written).
symba::Status CheckParentExists(const std::string& path) {
  std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) parent = ".";
  std::error_code error;
  if (!std::filesystem::is_directory(parent, error)) {
    return symba::Status::Error(path + ": parent directory " + parent.string() +
                                " does not exist");
  }
  return symba::Status::Ok();
}

// Whether two paths name the same place (neither needs to exist).
bool SamePath(const std::string& a, const std::string& b) {
  std::error_code error_a;
  std::error_code error_b;
  const std::filesystem::path path_a =
      std::filesystem::weakly_canonical(a, error_a);
  const std::filesystem::path path_b =
      std::filesystem::weakly_canonical(b, error_b);
  return !error_a && !error_b && path_a == path_b;
}

// --bop-out's rows (none without it), computed before any output is
// written, so that an unmapped class or a missing scene id leaves no file.
symba::Status RefinedBopRows(const ReplayFlags& f,
                             const symba::ReplayResult& result,
                             std::vector<symba::BopResult>* rows) {
  if (f.bop_out.empty()) return symba::Status::Ok();
  symba::Status status = CheckParentExists(f.bop_out);
  if (status.ok()) status = symba::CheckFileTarget(f.bop_out);
  if (status.ok()) status = symba::CheckOutputSparesInputs(f.bop_out, {f.log});
  if (status.ok() && SamePath(f.bop_out, f.out)) {
    status = symba::Status::Error(f.bop_out + ": is also --out");
  }
  if (!status.ok()) return status;
  symba::RefinedBopResultsOptions options;
  if (f.bop_scene >= 0) options.scene_id = f.bop_scene;
  status = symba::RefinedBopResultsFromLog(f.log, result, options, rows);
  if (!status.ok())
    return symba::Status::Error("--bop-out: " + status.message());
  return symba::Status::Ok();
}

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A .g2o file is a pose graph: optimise it and write trajectory.tum and
// summary.json.
int RunPoseGraphReplay(const ReplayFlags& f) {
  symba::PoseGraph graph;
  symba::PoseGraphSolveSummary summary;
  symba::PoseGraphSolveOptions options;
  options.num_threads = f.backend.num_threads;
  options.initialization = f.g2o_initialization == "given"
                               ? symba::PoseGraphInitialization::kGiven
                               : symba::PoseGraphInitialization::kChordal;
  symba::G2oReadOptions read_options;
  read_options.isotropic_information = f.g2o_isotropic;
  symba::Status status = symba::CheckOutputSparesInputs(f.out, {f.log});
  if (status.ok())
    status = symba::ReadG2oPoseGraph(f.log, &graph, read_options);
  if (status.ok()) status = symba::OptimizePoseGraph(options, &graph, &summary);
  if (status.ok()) {
    status = symba::WriteDirectoryAtomically(
        f.out, symba::PoseGraphOutputFiles(f.log, graph, summary));
  }
  if (!status.ok()) return Fail(status.message());
  if (!f.quiet) {
    std::fprintf(stderr,
                 "symba replay: wrote %s: %d poses, %d edges in %.2f s\n",
                 f.out.c_str(),
                 summary.num_vertices,
                 summary.num_edges,
                 summary.seconds);
  }
  return 0;
}

// The closing line on stderr, as `symba import` ends: what was replayed, how
// long it took and where it went.
void PrintReplaySummary(const ReplayFlags& f,
                        const symba::ReplayResult& result) {
  const std::string counts =
      symba::CountPhrase(static_cast<long long>(result.keyframes.size()),
                         "keyframe") +
      ", " + symba::CountPhrase(result.statistics.detections, "detection") +
      ", " +
      symba::CountPhrase(static_cast<long long>(result.objects.size()),
                         "map object");
  std::fprintf(stderr,
               "symba replay: wrote %s: %s in %.2f s",
               f.out.c_str(),
               counts.c_str(),
               result.seconds);
  if (!f.bop_out.empty())
    std::fprintf(stderr, "; BOP results %s", f.bop_out.c_str());
  if (!f.map_out.empty()) std::fprintf(stderr, "; map %s", f.map_out.c_str());
  if (result.relocalization) {
    const symba::RelocalizationReport& r = *result.relocalization;
    if (r.keyframe) {
      std::fprintf(stderr,
                   "; relocalised at keyframe %lld on %zu objects",
                   static_cast<long long>(*r.keyframe),
                   r.correspondences.size());
    } else {
      std::fprintf(stderr,
                   "; not relocalised (%s after %d keyframes: %s)",
                   symba::ToString(r.state),
                   r.keyframes,
                   r.last_outcome.c_str());
    }
  }
  std::fprintf(stderr, "\n");
}

// --map-out must be a file that can be replaced, next to no input, and not
// the --map-in (a map is only read before the replay; the file is written
// after it).
symba::Status CheckMapOut(const ReplayFlags& f) {
  symba::Status status = symba::CheckFileTarget(f.map_out);
  if (status.ok()) status = CheckParentExists(f.map_out);
  if (status.ok()) status = symba::CheckOutputSparesInputs(f.map_out, {f.log});
  return status;
}

int RunReplay(const ReplayFlags& f) {
  if (EndsWith(f.log, ".g2o")) {
    if (!f.bop_out.empty()) {
      return Fail("--bop-out: a pose graph (.g2o) has no objects");
    }
    if (!f.map_in.empty() || !f.map_out.empty() || f.relocalize) {
      return Fail(
          "--map-in, --map-out, --relocalize: a pose graph (.g2o) has no "
          "objects");
    }
    return RunPoseGraphReplay(f);
  }
  symba::ReplayOptions options;
  options.backend = f.backend;
  symba::ParseReplayMode(f.mode, &options.mode);
  options.final_batch = f.final_batch;
  const bool show_progress = !f.quiet && ::isatty(STDERR_FILENO);
  if (show_progress) {
    options.progress = [](int keyframes) {
      if (keyframes % 10 == 0) {
        std::fprintf(stderr, "\rsymba replay: %d keyframes", keyframes);
      }
    };
  }
  symba::ReplayResult result;
  symba::Status status =
      symba::CheckOutputSparesInputs(f.out, {f.log, f.map_in});
  if (status.ok() && !f.map_out.empty()) status = CheckMapOut(f);
  if (status.ok() && !f.map_in.empty()) {
    options.map_in.emplace();
    status = symba::ReadMapFile(f.map_in, &*options.map_in);
    if (!status.ok()) status = symba::Status::Error(status.message());
  }
  if (status.ok() && f.relocalize) {
    if (f.map_in.empty()) {
      status = symba::Status::Error("--relocalize needs --map-in");
    }
    options.relocalize.emplace();
  }
  options.save_map = !f.map_out.empty();
  if (status.ok()) status = symba::ReplayLog(f.log, options, &result);
  if (show_progress) std::fprintf(stderr, "\n");
  std::vector<symba::BopResult> bop_rows;
  if (status.ok()) status = RefinedBopRows(f, result, &bop_rows);
  if (status.ok()) {
    status = symba::WriteDirectoryAtomically(
        f.out, symba::ReplayOutputFiles(f.log, options, result));
  }
  if (status.ok() && !f.bop_out.empty()) {
    status = symba::WriteBopResultsCsv(f.bop_out, bop_rows);
  }
  if (status.ok() && result.map) {
    status = symba::WriteFileAtomically(f.map_out,
                                        symba::FormatMapFile(*result.map));
  }
  if (!status.ok()) return Fail(status.message());
  if (!f.quiet) PrintReplaySummary(f, result);
  return 0;
}

}  // namespace

void RegisterReplayCommand(CLI::App* app, int* exit_code) {
  auto flags = std::make_shared<ReplayFlags>();
  CLI::App* command = AddReplayOptions(app, flags.get());
  command->callback([flags, exit_code] { *exit_code = RunReplay(*flags); });
}
