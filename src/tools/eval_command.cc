// `symba eval`: compares the outputs of a replay with ground truth and prints
// a markdown report (docs/evaluation.md); --json also writes it as JSON.
// Two kinds of ground truth: the simulator's directory (--gt) or a camera
// trajectory at any rate with an optional object list (--gt-trajectory).
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "symba/evaluation/evaluate.h"
#include "symba/evaluation/evaluate_trajectory.h"
#include "symba/io/file_output.h"
#include "tools/commands.h"

namespace {

struct EvalFlags {
  std::string gt;
  std::string result;
  std::string json;
  std::string align = "first";
  symba::TrajectoryEvalInputs trajectory;  // --gt-trajectory and its options
};

int Fail(const std::string& message) {
  std::fprintf(stderr, "symba eval: %s\n", message.c_str());
  return 1;
}

// Prints the table, then writes --json (atomically) if given.
int Report(const EvalFlags& f,
           const std::string& table,
           const std::string& json) {
  if (!f.json.empty()) {
    const symba::Status status = symba::WriteFileAtomically(f.json, json);
    if (!status.ok()) return Fail(status.message());
  }
  std::fputs(table.c_str(), stdout);
  return 0;
}

int RunGeneratorEval(const EvalFlags& f) {
  symba::Evaluation evaluation;
  const symba::Status status = symba::Evaluate(f.gt, f.result, &evaluation);
  if (!status.ok()) return Fail(status.message());
  return Report(f,
                symba::FormatEvaluationTable(evaluation),
                symba::FormatEvaluationJson(evaluation));
}

int RunTrajectoryEval(EvalFlags f) {
  f.trajectory.result_dir = f.result;
  symba::ParseTrajectoryAlignment(f.align, &f.trajectory.options.alignment);
  symba::GroundTruthTrajectoryEvaluation evaluation;
  const symba::Status status =
      symba::EvaluateAgainstTrajectory(f.trajectory, &evaluation);
  if (!status.ok()) return Fail(status.message());
  return Report(f,
                symba::FormatTrajectoryEvaluationTable(evaluation),
                symba::FormatTrajectoryEvaluationJson(evaluation));
}

int RunEval(const EvalFlags& f) {
  if (f.gt.empty() == f.trajectory.gt_trajectory.empty()) {
    return Fail("give the ground truth as --gt DIR or --gt-trajectory FILE");
  }
  return f.gt.empty() ? RunTrajectoryEval(f) : RunGeneratorEval(f);
}

}  // namespace

void RegisterEvalCommand(CLI::App* app, int* exit_code) {
  auto flags = std::make_shared<EvalFlags>();
  symba::TrajectoryEvalInputs& t = flags->trajectory;
  CLI::App* cmd = app->add_subcommand(
      "eval",
      "Compare a replay's outputs with ground truth: the simulator's files "
      "(--gt: keyframe RMSE, map objects per ground-truth object, axis "
      "errors, categorisation) or a camera trajectory at any rate "
      "(--gt-trajectory: ATE and RPE after alignment, the front end's, "
      "object position errors)");
  CLI::Option* gt = cmd->add_option(
      "--gt",
      flags->gt,
      "ground-truth directory of symba simulate (gt_trajectory.tum, "
      "gt_objects.json)");
  CLI::Option* gt_trajectory = cmd->add_option(
      "--gt-trajectory",
      t.gt_trajectory,
      "ground-truth camera trajectory T_wc (TUM, any rate), associated by "
      "time to the result's keyframes");
  gt->excludes(gt_trajectory);
  cmd->add_option("--result",
                  flags->result,
                  "replay output directory (trajectory.tum, objects.json, "
                  "associations.csv)")
      ->required();
  cmd->add_option("--align",
                  flags->align,
                  "--gt-trajectory: none, first (the first keyframe onto "
                  "the ground truth), se3 or sim3 (Umeyama)")
      ->check(CLI::IsMember({"none", "first", "se3", "sim3"}))
      ->needs(gt_trajectory)
      ->capture_default_str();
  cmd->add_option("--frontend",
                  t.frontend,
                  "--gt-trajectory: the front end's TUM trajectory, scored "
                  "at the same keyframes, with the ATE ratio")
      ->needs(gt_trajectory);
  cmd->add_option("--time-tolerance",
                  t.options.time_tolerance,
                  "--gt-trajectory: largest time difference (s) between a "
                  "keyframe and its nearest ground-truth pose")
      ->check(CLI::NonNegativeNumber & symba::tools::FiniteNumber())
      ->needs(gt_trajectory)
      ->capture_default_str();
  cmd->add_option("--gt-objects",
                  t.gt_objects,
                  "--gt-trajectory: ground-truth objects, one 'CLASS tx ty "
                  "tz qx qy qz qw' line (T_wo) each")
      ->needs(gt_trajectory);
  cmd->add_option("--json", flags->json, "also write the report as JSON here");
  cmd->callback([flags, exit_code] { *exit_code = RunEval(*flags); });
}
