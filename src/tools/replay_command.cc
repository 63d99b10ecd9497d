// `symba replay`: replays a log v1 through the backend and writes the four
// output files atomically (docs/replay.md).
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "symba/export/refined_bop_results.h"
#include "symba/geometry/angle.h"
#include "symba/io/file_output.h"
#include "symba/io/pose_graph.h"
#include "symba/pose_graph/optimize_pose_graph.h"
#include "symba/replay/replay.h"
#include "symba/replay/replay_output.h"
#include "tools/commands.h"

namespace {

constexpr double kDeg = symba::kPi / 180.0;

// Flags of `symba replay`, bound to their defaults.
struct ReplayFlags {
  std::string log;
  std::string out;
  std::string method = "symba";
  std::string window_policy = "marginalize";
  std::string chain_prior = "conditional";
  std::string mode = "window";
  std::string loss;
  std::string bop_out;  // --bop-out: the refined poses as BOP results
  int bop_scene = -1;   // --bop-scene; -1: the log header's
  bool quiet = false;
  bool final_batch = false;
  bool g2o_isotropic = false;
  double gate_axis_deg = 0.0;
  double gate_rotation_deg = 0.0;
  double gate_angle_deg = 0.0;
  symba::BackendOptions backend;

  ReplayFlags() {
    loss = symba::LossName(backend.object_loss);
    gate_axis_deg = backend.gate_axis / kDeg;
    gate_rotation_deg = backend.gate_rotation / kDeg;
    gate_angle_deg = backend.gate_angle / kDeg;
  }
};

CLI::App* AddReplayOptions(CLI::App* app, ReplayFlags* f) {
  CLI::App* cmd = app->add_subcommand(
      "replay",
      "Replay a log v1 (or optimise a .g2o pose graph) and write "
      "trajectory.tum, objects.json, associations.csv and summary.json");
  symba::BackendOptions& b = f->backend;
  cmd->add_option(
         "LOG", f->log, "log v1 file (JSON Lines), or a .g2o 3-D pose graph")
      ->required();
  cmd->add_option("--out",
                  f->out,
                  "output directory (replaced atomically, parent must exist)")
      ->required();
  cmd->add_option("--method", f->method, "symba, mh or sh")
      ->check(CLI::IsMember({"symba", "mh", "sh"}))
      ->capture_default_str();
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
  cmd->add_option("--window", b.window_size, "keyframes free in a window")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--window-policy",
                  f->window_policy,
                  "keyframes leaving the window: marginalize (into priors; "
                  "bounded work), condition (held constant with all their "
                  "factors) or drop")
      ->check(CLI::IsMember({"marginalize", "condition", "drop"}))
      ->capture_default_str();
  cmd->add_option("--chain-prior",
                  f->chain_prior,
                  "marginalize: a leaving keyframe's pose is held at its "
                  "estimate (conditional) or eliminated by the Schur "
                  "complement (marginal)")
      ->check(CLI::IsMember({"conditional", "marginal"}))
      ->capture_default_str();
  cmd->add_option("--marginalize-min-margin",
                  b.marginalize_min_margin,
                  "marginalize: least cost lead (nats) of a max-mixture's "
                  "winner over every rival for the edge to enter a prior")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--marginalize-rival-distance",
                  b.marginalize_rival_distance,
                  "marginalize: whitened residual distance beyond which a "
                  "component is the winner's rival")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--threads", b.num_threads, "Ceres threads")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option(
         "--max-iterations", b.max_iterations, "solver iterations per window")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option("--batch-max-iterations",
                  b.batch_max_iterations,
                  "solver iterations of a batch solve")
      ->check(CLI::PositiveNumber & symba::tools::FiniteNumber())
      ->capture_default_str();
  cmd->add_option(
         "--hypothesis-sigma-t",
         b.hypothesis_sigma_t,
         "hypothesis translation noise when a detection gives none (m)")
      ->capture_default_str();
  cmd->add_option("--hypothesis-sigma-r",
                  b.hypothesis_sigma_r,
                  "hypothesis rotation noise when a detection gives none (rad)")
      ->capture_default_str();
  cmd->add_option("--gamma", b.gamma, "weight of the continuous axis term")
      ->capture_default_str();
  cmd->add_option("--axis-sigma", b.axis_sigma, "measured axis noise (rad)")
      ->capture_default_str();
  cmd->add_option("--loss", f->loss, "robust loss on object edges")
      ->check(CLI::IsMember({"none", "huber", "cauchy"}))
      ->capture_default_str();
  cmd->add_option("--loss-scale",
                  b.object_loss_scale,
                  "object loss scale (whitened units)")
      ->capture_default_str();
  cmd->add_option("--merge-modes",
                  b.merge_modes,
                  "symba: one component per mode at its mean (true) or one "
                  "per hypothesis (false, the paper)")
      ->capture_default_str();
  cmd->add_flag("--null-hypothesis",
                b.mixture.use_null_hypothesis,
                "add a null-hypothesis component to every mixture");
  cmd->add_option("--frontend-sigma-t",
                  b.frontend_sigma_t,
                  "front-end relative motion noise (m)")
      ->capture_default_str();
  cmd->add_option("--frontend-sigma-r",
                  b.frontend_sigma_r,
                  "front-end relative motion noise (rad)")
      ->capture_default_str();
  cmd->add_option(
         "--point-sigma", b.point_sigma_px, "reprojection noise (pixels)")
      ->capture_default_str();
  cmd->add_option("--point-depth-sigma",
                  b.point_depth_sigma_relative,
                  "depth noise as a fraction of the depth (0: ignore depth)")
      ->capture_default_str();
  cmd->add_option(
         "--gate-position", b.gate_position, "association gate on position (m)")
      ->capture_default_str();
  cmd->add_option("--gate-axis",
                  f->gate_axis_deg,
                  "association gate on the axis (degrees)")
      ->capture_default_str();
  cmd->add_option("--gate-rotation",
                  f->gate_rotation_deg,
                  "6-DoF association gate on rotation (degrees)")
      ->capture_default_str();
  cmd->add_option("--gate-angle",
                  f->gate_angle_deg,
                  "discrete angle association gate (degrees)")
      ->capture_default_str();
  cmd->add_option("--confirm-keyframes",
                  b.confirm_keyframes,
                  "keyframes with a detection before a new object enters the "
                  "map (1: at once)")
      ->capture_default_str();
  cmd->add_option("--tentative-timeout",
                  b.tentative_timeout,
                  "keyframes without a detection after which a tentative "
                  "object is dropped")
      ->capture_default_str();
  cmd->add_option("--gate-sigmas",
                  b.gate_sigmas,
                  "position gate in the detection's noise (0: gate-position "
                  "only)")
      ->capture_default_str();
  cmd->add_option("--estimate-noise",
                  b.estimate_noise,
                  "estimate each class's detection noise from the data")
      ->capture_default_str();
  cmd->add_option("--uncalibrated-sigma-t",
                  b.uncalibrated_sigma_t,
                  "with --estimate-noise: the least noise a detection without "
                  "a sigma is weighed with (m)")
      ->capture_default_str();
  cmd->add_option("--uncalibrated-sigma-r",
                  b.uncalibrated_sigma_r,
                  "the same for rotation (rad)")
      ->capture_default_str();
  cmd->add_option("--min-support",
                  b.min_support,
                  "drop a confirmed object detected in fewer than this "
                  "fraction of the keyframes it was in view (0: never)")
      ->capture_default_str();
  cmd->add_option("--upgrade-evidence",
                  b.upgrade_evidence,
                  "symba: agreeing flips before an asymmetric object becomes "
                  "discrete")
      ->capture_default_str();
  cmd->add_option("--upgrade-min-fraction",
                  b.upgrade_min_fraction,
                  "symba: the agreeing flips' least share of the keyframes "
                  "that detected the object")
      ->capture_default_str();
  cmd->add_option("--max-upgrade-order",
                  b.max_upgrade_order,
                  "symba: the largest symmetry order a flip may show")
      ->capture_default_str();
  cmd->add_flag("--g2o-isotropic",
                f->g2o_isotropic,
                "g2o input: replace each edge's information by SE-Sync's "
                "isotropic one (needed for files with indefinite information)");
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
  std::fprintf(stderr,
               "symba replay: wrote %s: %d keyframes, %d detections, %d map "
               "objects in %.2f s",
               f.out.c_str(),
               static_cast<int>(result.keyframes.size()),
               result.statistics.detections,
               static_cast<int>(result.objects.size()),
               result.seconds);
  if (!f.bop_out.empty())
    std::fprintf(stderr, "; BOP results %s", f.bop_out.c_str());
  std::fprintf(stderr, "\n");
}

int RunReplay(const ReplayFlags& f) {
  if (EndsWith(f.log, ".g2o")) {
    if (!f.bop_out.empty()) {
      return Fail("--bop-out: a pose graph (.g2o) has no objects");
    }
    return RunPoseGraphReplay(f);
  }
  symba::ReplayOptions options;
  options.backend = f.backend;
  symba::ParseMethod(f.method, &options.backend.method);
  symba::ParseWindowPolicy(f.window_policy, &options.backend.window_policy);
  symba::ParseChainPrior(f.chain_prior, &options.backend.chain_prior);
  symba::ParseReplayMode(f.mode, &options.mode);
  options.final_batch = f.final_batch;
  symba::ParseLoss(f.loss, &options.backend.object_loss);
  options.backend.gate_axis = f.gate_axis_deg * kDeg;
  options.backend.gate_rotation = f.gate_rotation_deg * kDeg;
  options.backend.gate_angle = f.gate_angle_deg * kDeg;
  const bool show_progress = !f.quiet && ::isatty(STDERR_FILENO);
  if (show_progress) {
    options.progress = [](int keyframes) {
      if (keyframes % 10 == 0) {
        std::fprintf(stderr, "\rsymba replay: %d keyframes", keyframes);
      }
    };
  }
  symba::ReplayResult result;
  symba::Status status = symba::CheckOutputSparesInputs(f.out, {f.log});
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
