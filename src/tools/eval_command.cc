// `symba eval`: compares the outputs of a replay with ground truth and prints
// a markdown report (docs/evaluation.md); --json also writes it as JSON.
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "symba/evaluation/evaluate.h"
#include "tools/commands.h"

namespace {

struct EvalFlags {
  std::string gt;
  std::string result;
  std::string json;
};

int RunEval(const EvalFlags& f) {
  symba::Evaluation evaluation;
  const symba::Status status = symba::Evaluate(f.gt, f.result, &evaluation);
  if (!status.ok()) {
    std::fprintf(stderr, "symba eval: %s\n", status.message().c_str());
    return 1;
  }
  std::fputs(symba::FormatEvaluationTable(evaluation).c_str(), stdout);
  if (!f.json.empty()) {
    std::ofstream out(f.json, std::ios::binary);
    out << symba::FormatEvaluationJson(evaluation);
    out.close();
    if (!out) {
      std::fprintf(stderr, "symba eval: %s: cannot write\n", f.json.c_str());
      return 1;
    }
  }
  return 0;
}

}  // namespace

void RegisterEvalCommand(CLI::App* app, int* exit_code) {
  auto flags = std::make_shared<EvalFlags>();
  CLI::App* cmd = app->add_subcommand(
      "eval",
      "Compare a replay's outputs with ground truth: keyframe RMSE, map "
      "objects per ground-truth object, axis errors, categorisation");
  cmd->add_option("--gt",
                  flags->gt,
                  "ground-truth directory (gt_trajectory.tum, gt_objects.json)")
      ->required();
  cmd->add_option("--result",
                  flags->result,
                  "replay output directory (trajectory.tum, objects.json, "
                  "associations.csv)")
      ->required();
  cmd->add_option("--json", flags->json, "also write the report as JSON here");
  cmd->callback([flags, exit_code] { *exit_code = RunEval(*flags); });
}
