// symba-window-bench: the cost of a window update against the keyframe
// index, under the window policies, on the long simulated scene
// (docs/performance.md "Window policies on the long scene").
//
// The scene is simulated once. Each policy then replays it in a child
// process of its own, so that the peak resident memory wait4 reports is
// that policy's alone: the child feeds the keyframes to a Backend one by
// one, timing AddKeyframe + OptimizeWindow (steady clock), and records the
// residual and parameter blocks of every window solve, the keyframe
// position RMSE and how many map objects each simulated object's
// detections went to. condition replays a prefix only: its cost grows with
// the run.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench_report.h"
#include "symba/backend/backend.h"
#include "symba/backend/backend_options.h"
#include "symba/simulation/scene.h"
#include "symba/simulation/simulator.h"
#include "top_down_svg.h"

namespace {

namespace fs = std::filesystem;
using symba::Status;
using symba::WindowPolicy;
using symba::bench::Fixed;

constexpr const char* kHeading = "## Window policies on the long scene\n";

struct Flags {
  int keyframes = 10000;
  int condition_keyframes = 3000;
  int accuracy_keyframes = 3000;
  int seed = 1;
  double yaw_bias_deg = -1.0;  // < 0: the simulator's default
  int window = 10;
  int table_bin = 500;
  int picture_bin = 100;
  std::string out_dir = SYMBA_WINDOW_BENCH_DEFAULT_OUT_DIR;
  std::string performance_md;
  std::string picture;
  std::string picture_link;
  std::string top_down;
  std::string top_down_link;
  int top_down_stride = 5;  // every how many keyframes the picture draws
  bool quiet = false;
};

// One policy's replay.
struct PolicyRun {
  WindowPolicy policy = WindowPolicy::kMarginalize;
  int keyframes = 0;       // replayed
  std::vector<double> ms;  // per keyframe: AddKeyframe + OptimizeWindow
  std::vector<int> residual_blocks;  // per keyframe: the window solve's
  std::vector<int> parameter_blocks;
  // per keyframe: its loop closures (the objects' or a host's) and their
  // seconds, part of ms
  std::vector<int> loop_closures;
  std::vector<double> loop_seconds;
  double rmse_prefix = 0.0;  // m, over the first accuracy_keyframes
  double rmse_all = 0.0;     // m, over every replayed keyframe
  int map_objects = 0;       // that detections of the first keyframes went to
  double fragmentation_mean = 0.0;  // map objects per simulated object
  int fragmentation_max = 0;
  long peak_rss_kb = 0;  // the child's
};

std::string RunPath(const Flags& flags, WindowPolicy policy) {
  return (fs::path(flags.out_dir) /
          (std::string("window-") + symba::WindowPolicyName(policy) + ".txt"))
      .string();
}

// The top-down picture of a finished replay: every top_down_stride-th
// keyframe of the truth and of the estimate, the map, the loop closures.
std::string TopDown(const Flags& flags,
                    const symba::SimulatedSequence& sequence,
                    const symba::Backend& backend,
                    double rmse) {
  symba::GroundTruth gt;
  gt.objects = symba::GroundTruthObjects(sequence);
  symba::ReplayOutputs outputs;
  const std::vector<symba::KeyframeEstimate> keyframes = backend.Keyframes();
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    if (k % flags.top_down_stride != 0 && k + 1 != keyframes.size()) continue;
    const symba::KeyframeEstimate& kf = keyframes[k];
    outputs.keyframes.push_back({kf.timestamp, kf.T_wc, 0});
    gt.keyframes.push_back({kf.timestamp, sequence.T_wc_true[kf.id], 0});
  }
  outputs.objects = backend.Objects();
  const std::vector<symba::bench::LoopClosureLine> loops =
      symba::bench::LoopClosureLines(keyframes, backend.LoopClosures());
  const std::string title =
      "long scene, seed " + std::to_string(flags.seed) + ", " +
      std::to_string(keyframes.size()) + " keyframes: RMSE " + Fixed(rmse, 3) +
      " m, " +
      symba::bench::Count(static_cast<int>(outputs.objects.size()),
                          "map object") +
      ", " +
      symba::bench::Count(static_cast<int>(loops.size()), "loop closure");
  return symba::bench::TopDownSvg(gt, outputs, title, "#1f77b4", {}, loops);
}

// The child's work: replays, writes RunPath (a "key value" line each for
// the summary, then one "keyframe ms residual_blocks parameter_blocks
// loop_closures loop_seconds" line per keyframe).
Status Replay(const Flags& flags,
              const symba::SimulatedSequence& sequence,
              WindowPolicy policy,
              int keyframes) {
  symba::BackendOptions options;
  options.window_policy = policy;
  options.window_size = flags.window;
  std::unique_ptr<symba::Backend> backend;
  Status status = symba::Backend::Create(
      options, sequence.header.camera, sequence.header.classes, &backend);
  if (!status.ok()) return status;
  PolicyRun run;
  for (int k = 0; k < keyframes; ++k) {
    const symba::BackendStatistics before = backend->Statistics();
    const auto start = std::chrono::steady_clock::now();
    status = backend->AddKeyframe(sequence.keyframes[k]);
    symba::SolveReport report;
    if (status.ok()) status = backend->OptimizeWindow(&report);
    const auto end = std::chrono::steady_clock::now();
    if (!status.ok()) {
      return Status::Error("keyframe " + std::to_string(k) + ": " +
                           status.message());
    }
    run.ms.push_back(
        std::chrono::duration<double, std::milli>(end - start).count());
    run.residual_blocks.push_back(report.residual_blocks);
    run.parameter_blocks.push_back(report.parameter_blocks);
    const symba::BackendStatistics after = backend->Statistics();
    run.loop_closures.push_back(after.loop_closures - before.loop_closures);
    run.loop_seconds.push_back(after.loop_closure_seconds -
                               before.loop_closure_seconds);
  }
  double sum_prefix = 0.0;
  double sum_all = 0.0;
  int n_prefix = 0;
  for (const symba::KeyframeEstimate& kf : backend->Keyframes()) {
    const double e2 = (kf.T_wc.t - sequence.T_wc_true[kf.id].t).squaredNorm();
    sum_all += e2;
    if (kf.id < flags.accuracy_keyframes) {
      sum_prefix += e2;
      ++n_prefix;
    }
  }
  // Detection id -> simulated object; map objects of each simulated object.
  std::map<std::string, int> truth;
  for (int k = 0; k < std::min(keyframes, flags.accuracy_keyframes); ++k) {
    for (const symba::SimulatedDetectionTruth& d : sequence.detections[k]) {
      truth[d.id] = d.object;
    }
  }
  std::set<int> in_map;
  for (const symba::MapObjectEstimate& o : backend->Objects()) {
    in_map.insert(o.id);
  }
  std::map<int, std::set<int>> objects_of;
  for (const symba::DetectionAssignment& a : backend->Assignments()) {
    if (in_map.count(a.object) == 0) continue;
    const auto it = truth.find(a.detection);
    if (it != truth.end() && it->second >= 0) {
      objects_of[it->second].insert(a.object);
    }
  }
  int total = 0;
  int most = 0;
  std::set<int> in_map_used;
  for (const auto& [object, map_objects] : objects_of) {
    in_map_used.insert(map_objects.begin(), map_objects.end());
    total += static_cast<int>(map_objects.size());
    most = std::max(most, static_cast<int>(map_objects.size()));
  }
  std::ofstream out(RunPath(flags, policy));
  out.precision(9);
  out << "keyframes " << keyframes << "\n"
      << "rmse_prefix " << std::sqrt(sum_prefix / std::max(1, n_prefix)) << "\n"
      << "rmse_all " << std::sqrt(sum_all / std::max(1, keyframes)) << "\n"
      << "map_objects " << in_map_used.size() << "\n"
      << "fragmentation_mean "
      << (objects_of.empty() ? 0.0
                             : static_cast<double>(total) / objects_of.size())
      << "\n"
      << "fragmentation_max " << most << "\n";
  for (int k = 0; k < keyframes; ++k) {
    out << k << " " << run.ms[k] << " " << run.residual_blocks[k] << " "
        << run.parameter_blocks[k] << " " << run.loop_closures[k] << " "
        << run.loop_seconds[k] << "\n";
  }
  out.close();
  if (!out) return Status::Error(RunPath(flags, policy) + ": cannot write");
  if (flags.top_down.empty() || policy != WindowPolicy::kMarginalize) {
    return Status::Ok();
  }
  return symba::bench::WriteText(
      flags.top_down,
      TopDown(flags,
              sequence,
              *backend,
              std::sqrt(sum_all / std::max(1, keyframes))));
}

Status ReadRun(const std::string& path, int keyframes, PolicyRun* run) {
  std::ifstream in(path);
  if (!in) return Status::Error(path + ": cannot read");
  const char* keys[6] = {"keyframes",
                         "rmse_prefix",
                         "rmse_all",
                         "map_objects",
                         "fragmentation_mean",
                         "fragmentation_max"};
  std::string key;
  for (int i = 0; i < 6; ++i) {
    in >> key;
    if (!in || key != keys[i]) {
      return Status::Error(path + ": expected " + keys[i]);
    }
    switch (i) {
      case 0:
        in >> run->keyframes;
        break;
      case 1:
        in >> run->rmse_prefix;
        break;
      case 2:
        in >> run->rmse_all;
        break;
      case 3:
        in >> run->map_objects;
        break;
      case 4:
        in >> run->fragmentation_mean;
        break;
      default:
        in >> run->fragmentation_max;
        break;
    }
  }
  if (!in || run->keyframes != keyframes) {
    return Status::Error(path + ": not the " + std::to_string(keyframes) +
                         " keyframes replayed");
  }
  for (int k = 0; k < run->keyframes; ++k) {
    int index = -1;
    double ms = 0.0;
    int residual_blocks = 0;
    int parameter_blocks = 0;
    int loop_closures = 0;
    double loop_seconds = 0.0;
    in >> index >> ms >> residual_blocks >> parameter_blocks >> loop_closures >>
        loop_seconds;
    if (!in || index != k) {
      return Status::Error(path + ": keyframe " + std::to_string(k) +
                           ": missing or malformed");
    }
    run->ms.push_back(ms);
    run->residual_blocks.push_back(residual_blocks);
    run->parameter_blocks.push_back(parameter_blocks);
    run->loop_closures.push_back(loop_closures);
    run->loop_seconds.push_back(loop_seconds);
  }
  return Status::Ok();
}

// Runs Replay in a child process; fills `run` from its file and rusage.
Status RunPolicy(const Flags& flags,
                 const symba::SimulatedSequence& sequence,
                 WindowPolicy policy,
                 int keyframes,
                 PolicyRun* run) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return Status::Error("fork failed");
  if (pid == 0) {
    const Status status = Replay(flags, sequence, policy, keyframes);
    if (!status.ok()) {
      std::fprintf(stderr,
                   "symba-window-bench: %s: %s\n",
                   symba::WindowPolicyName(policy),
                   status.message().c_str());
    }
    std::fflush(nullptr);
    std::_Exit(status.ok() ? 0 : 1);
  }
  int wait_status = 0;
  struct rusage usage {};
  pid_t waited = -1;
  do {
    waited = wait4(pid, &wait_status, 0, &usage);
  } while (waited < 0 && errno == EINTR);
  if (waited != pid || !WIFEXITED(wait_status) ||
      WEXITSTATUS(wait_status) != 0) {
    return Status::Error(std::string(symba::WindowPolicyName(policy)) +
                         ": the replay failed");
  }
  run->policy = policy;
  run->peak_rss_kb = usage.ru_maxrss;
  return ReadRun(RunPath(flags, policy), keyframes, run);
}

// Mean of v[begin, end) clipped to v's size; NaN when empty.
double MeanOver(const std::vector<double>& v, int begin, int end) {
  begin = std::max(begin, 0);
  end = std::min<int>(end, static_cast<int>(v.size()));
  if (begin >= end) return std::nan("");
  double sum = 0.0;
  for (int i = begin; i < end; ++i) sum += v[i];
  return sum / (end - begin);
}

// The mean of run.ms over [begin, end), keyframes with a loop closure left
// out (their time is the closure's, reported apart).
double MeanWithoutClosures(const PolicyRun& run, int begin, int end) {
  begin = std::max(begin, 0);
  end = std::min<int>(end, static_cast<int>(run.ms.size()));
  double sum = 0.0;
  int count = 0;
  for (int i = begin; i < end; ++i) {
    if (run.loop_closures[i] > 0) continue;
    sum += run.ms[i];
    ++count;
  }
  return count > 0 ? sum / count : std::nan("");
}

// How many loop closures the run made.
int LoopClosureCount(const PolicyRun& run) {
  int count = 0;
  for (int n : run.loop_closures) count += n;
  return count;
}

// "count | median / max [s]" of the run's loop closures (per keyframe that
// had any: their seconds together).
std::string LoopClosureCells(const PolicyRun& run) {
  std::vector<double> seconds;
  for (size_t k = 0; k < run.loop_closures.size(); ++k) {
    if (run.loop_closures[k] > 0) seconds.push_back(run.loop_seconds[k]);
  }
  const int count = LoopClosureCount(run);
  if (seconds.empty()) return "0 | —";
  std::sort(seconds.begin(), seconds.end());
  const double median =
      0.5 * (seconds[(seconds.size() - 1) / 2] + seconds[seconds.size() / 2]);
  return std::to_string(count) + " | " + Fixed(median, 3) + " / " +
         Fixed(seconds.back(), 3);
}

int MaxOver(const std::vector<int>& v, int begin, int end) {
  begin = std::max(begin, 0);
  end = std::min<int>(end, static_cast<int>(v.size()));
  int most = 0;
  for (int i = begin; i < end; ++i) most = std::max(most, v[i]);
  return most;
}

double Mb(long kb) { return static_cast<double>(kb) / 1024.0; }

// Time per keyframe (mean of each bin) against the keyframe index, one
// polyline per policy; written by hand like the other benchmark pictures.
std::string Picture(const Flags& flags, const std::vector<PolicyRun>& runs) {
  const int width = 760;
  const int height = 360;
  const int left = 60;
  const int right = 20;
  const int top = 30;
  const int bottom = 50;
  const int plot_w = width - left - right;
  const int plot_h = height - top - bottom;
  int x_max = 0;
  double y_max = 0.0;
  std::vector<std::vector<std::pair<double, double>>> lines;
  for (const PolicyRun& run : runs) {
    x_max = std::max(x_max, run.keyframes);
    std::vector<std::pair<double, double>> line;
    for (int b = 0; b < run.keyframes; b += flags.picture_bin) {
      const double y = MeanWithoutClosures(run, b, b + flags.picture_bin);
      if (std::isnan(y)) continue;
      line.emplace_back(b + 0.5 * flags.picture_bin, y);
      y_max = std::max(y_max, y);
    }
    lines.push_back(line);
  }
  // A round upper bound: 1, 2 or 5 times a power of ten.
  double step = std::pow(10.0, std::floor(std::log10(std::max(y_max, 1e-3))));
  while (step * 5 < y_max) step *= 2;
  const double y_top = std::ceil(y_max / step) * step;
  auto X = [&](double x) { return left + plot_w * x / std::max(1, x_max); };
  auto Y = [&](double y) { return top + plot_h * (1.0 - y / y_top); };
  std::ostringstream svg;
  svg.precision(5);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width
      << "\" height=\"" << height << "\" font-family=\"sans-serif\" "
      << "font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << left << "\" y=\"18\">Time per keyframe [ms], mean "
      << "of " << flags.picture_bin
      << " keyframes but those that closed a loop (ticks), long scene, "
         "window "
      << flags.window << "</text>\n";
  for (double y = 0.0; y <= y_top + 1e-9; y += step) {
    svg << "<line x1=\"" << left << "\" y1=\"" << Y(y) << "\" x2=\""
        << left + plot_w << "\" y2=\"" << Y(y)
        << "\" stroke=\"#ddd\"/>\n<text x=\"" << left - 6 << "\" y=\""
        << Y(y) + 4 << "\" text-anchor=\"end\">" << y << "</text>\n";
  }
  const int x_step = x_max > 4000 ? 1000 : 500;
  for (int x = 0; x <= x_max; x += x_step) {
    svg << "<text x=\"" << X(x) << "\" y=\"" << top + plot_h + 18
        << "\" text-anchor=\"middle\">" << x << "</text>\n";
  }
  svg << "<text x=\"" << left + plot_w / 2 << "\" y=\"" << height - 10
      << "\" text-anchor=\"middle\">keyframe index</text>\n"
      << "<line x1=\"" << left << "\" y1=\"" << top + plot_h << "\" x2=\""
      << left + plot_w << "\" y2=\"" << top + plot_h
      << "\" stroke=\"black\"/>\n";
  const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c"};
  for (std::size_t i = 0; i < runs.size(); ++i) {
    svg << "<polyline fill=\"none\" stroke=\"" << colors[i % 3]
        << "\" stroke-width=\"2\" points=\"";
    for (const auto& [x, y] : lines[i]) svg << X(x) << "," << Y(y) << " ";
    svg << "\"/>\n<text x=\"" << left + 10 << "\" y=\"" << top + 16 + 16 * i
        << "\" fill=\"" << colors[i % 3] << "\">"
        << symba::WindowPolicyName(runs[i].policy) << " ("
        << symba::bench::Count(LoopClosureCount(runs[i]), "loop closure")
        << ")</text>\n";
    // A tick on the x axis at each keyframe that closed a loop.
    for (int k = 0; k < runs[i].keyframes; ++k) {
      if (runs[i].loop_closures[k] == 0) continue;
      svg << "<line class=\"loop-closure\" x1=\"" << X(k) << "\" y1=\""
          << top + plot_h - 3 * static_cast<int>(i) << "\" x2=\"" << X(k)
          << "\" y2=\"" << top + plot_h - 8 - 3 * static_cast<int>(i)
          << "\" stroke=\"" << colors[i % 3] << "\"/>\n";
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string Report(const Flags& flags,
                   const std::vector<PolicyRun>& runs,
                   long baseline_kb,
                   const std::string& command) {
  const PolicyRun& marginalize = runs[0];
  std::ostringstream out;
  out << kHeading << "\n"
      << "Generated by `symba-window-bench` (`benchmarks/window_bench.cc`); "
         "do not edit by hand, run it again.\n\n"
      << "- Command: `" << command << "`\n"
      << "- Date: " << symba::bench::UtcDate() << "\n"
      << "- Machine: " << symba::bench::Machine() << "\n"
      << "- Build: " << SYMBA_BUILD_TYPE << ", " << __VERSION__ << "\n"
      << "- Scene: `symba simulate --scene long --seed " << flags.seed
      << (flags.yaw_bias_deg >= 0.0
              ? " --yaw-bias " + Fixed(flags.yaw_bias_deg, 2)
              : std::string())
      << "` (23 objects of all three types at six places, toured lap after "
         "lap, [simulation.md](simulation.md)); window "
      << flags.window
      << ", one Ceres thread, default `BackendOptions` otherwise. Each "
         "policy replays in a process of its own"
      << (runs.size() > 1 ? "; condition replays the first " +
                                std::to_string(runs.back().keyframes) +
                                " keyframes only (its cost grows with the run)"
                          : std::string())
      << ".\n\n";
  out << "| keyframes |";
  for (const PolicyRun& run : runs) {
    out << " " << symba::WindowPolicyName(run.policy) << " [ms] |";
  }
  for (const PolicyRun& run : runs) {
    out << " " << symba::WindowPolicyName(run.policy)
        << " residual blocks, max |";
  }
  out << "\n|---|";
  for (std::size_t i = 0; i < 2 * runs.size(); ++i) out << "---:|";
  out << "\n";
  for (int b = 0; b < marginalize.keyframes; b += flags.table_bin) {
    out << "| " << b << "-" << b + flags.table_bin - 1 << " |";
    for (const PolicyRun& run : runs) {
      out << " "
          << (b < run.keyframes
                  ? Fixed(MeanOver(run.ms, b, b + flags.table_bin), 1)
                  : std::string("—"))
          << " |";
    }
    for (const PolicyRun& run : runs) {
      out << " "
          << (b < run.keyframes
                  ? std::to_string(
                        MaxOver(run.residual_blocks, b, b + flags.table_bin))
                  : std::string("—"))
          << " |";
    }
    out << "\n";
  }
  out << "\nTime per keyframe: `AddKeyframe` (categorisation, association, "
         "the leaving keyframe's marginalisation) plus `OptimizeWindow`, "
         "mean over the keyframes of the row. Residual blocks: the largest "
         "window problem of the row, the priors included.\n\n";
  if (!flags.picture_link.empty()) {
    out << "![Time per keyframe against the keyframe index]("
        << flags.picture_link
        << ")\n\nThe picture's lines leave out the keyframes that closed a "
           "loop (ticks on the x axis; their time is the loop closure's, "
           "in the table below).\n\n";
  }
  out << "| policy | keyframes | mean over the last 1000 / mean over "
         "500-1499 | residual blocks, max | parameter blocks, max | peak "
         "memory [MB] | keyframe RMSE, first "
      << flags.accuracy_keyframes
      << " [m] | keyframe RMSE, all [m] | map objects, first "
      << flags.accuracy_keyframes << " | map objects per object, first "
      << flags.accuracy_keyframes
      << ", mean / max | loop closures | time per loop closure, median / "
         "max [s] |\n"
      << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const PolicyRun& run : runs) {
    const double late =
        MeanWithoutClosures(run, run.keyframes - 1000, run.keyframes);
    const double early = MeanWithoutClosures(run, 500, 1500);
    out << "| " << symba::WindowPolicyName(run.policy) << " | " << run.keyframes
        << " | " << Fixed(late / early, 2) << " | "
        << MaxOver(run.residual_blocks, 0, run.keyframes) << " | "
        << MaxOver(run.parameter_blocks, 0, run.keyframes) << " | "
        << Fixed(Mb(run.peak_rss_kb), 0) << " | " << Fixed(run.rmse_prefix, 3)
        << " | " << Fixed(run.rmse_all, 3) << " | " << run.map_objects << " | "
        << Fixed(run.fragmentation_mean, 2) << " / " << run.fragmentation_max
        << " | " << LoopClosureCells(run) << " |\n";
  }
  out << "\nThe ratio is the issue's target (at most 1.2 for marginalize); "
         "for condition, whose run is shorter, it compares its own last "
         "1000 keyframes. Both means leave out the keyframes that closed a "
         "loop, whose time is the loop closure's (its own columns: the "
         "keyframe graph's solve, moving the past, merging the duplicates). "
         "Peak memory: the replaying process's maximum "
         "resident set (`wait4`), which includes the simulated sequence it "
         "inherits ("
      << Fixed(Mb(baseline_kb), 0)
      << " MB resident before the replays) and, with `--top-down`, the "
         "drawing of the picture (well under 1 MB). Keyframe RMSE: position "
         "error "
         "of the final estimates, no alignment; the first "
      << flags.accuracy_keyframes
      << " keyframes are in every run. Map objects: those the detections of "
         "these keyframes went to; per object: over the simulated objects, "
         "how many map objects their detections in these keyframes went to "
         "(1 is right); the scene has 23 objects. The log carries no loop "
         "closure of a host: every loop closure is one symba found from the "
         "objects ([loop-closure.md](loop-closure.md), \"Loops from the "
         "objects\"). With the scene's default featureless yaw bias the "
         "front end drifts by metres over a lap, and a place revisited that "
         "far off is mapped again until its duplicates are recognised.\n";
  if (!flags.top_down_link.empty()) {
    out << "\n![The long scene from above, marginalize's final estimate "
           "with its loop closures]("
        << flags.top_down_link
        << ")\n\nThe long scene from above (`--top-down`): the true "
           "(dashed) and marginalize's estimated keyframes, every "
        << flags.top_down_stride
        << "th, the objects and the map objects as the run ended, and each "
           "loop closure as an orange line between its two keyframes with a "
           "ring at the one that closed it, where the final estimate has "
           "them: two keyframes that saw the same objects, often from "
           "across their place.\n";
  }
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  Flags flags;
  CLI::App app{
      "symba-window-bench: time per keyframe against the keyframe index "
      "under the window policies, on the long simulated scene"};
  app.add_option(
         "--keyframes", flags.keyframes, "keyframes marginalize replays")
      ->check(CLI::Range(1500, 1000000))
      ->capture_default_str();
  app.add_option("--condition-keyframes",
                 flags.condition_keyframes,
                 "keyframes condition replays (0: skip it)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--accuracy-keyframes",
                 flags.accuracy_keyframes,
                 "the RMSE every run reports is over these first keyframes")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--seed", flags.seed, "simulation seed")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--yaw-bias",
                 flags.yaw_bias_deg,
                 "the front end's yaw bias per featureless keyframe (deg; "
                 "default: the simulator's)");
  app.add_option("--window", flags.window, "window size")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--out-dir", flags.out_dir, "per-keyframe records")
      ->capture_default_str();
  app.add_option("--performance-md",
                 flags.performance_md,
                 "also write the report as the file's last section (e.g. "
                 "docs/performance.md)");
  app.add_option("--picture",
                 flags.picture,
                 "also write the picture here (e.g. "
                 "docs/img/window-time-per-keyframe.svg)");
  app.add_option(
      "--picture-link", flags.picture_link, "how the report links the picture");
  app.add_option("--top-down",
                 flags.top_down,
                 "also draw marginalize's final estimate from above here, "
                 "with its loop closures (e.g. "
                 "docs/img/window-long-scene.svg)");
  app.add_option("--top-down-link",
                 flags.top_down_link,
                 "how the report links the top-down picture");
  app.add_option("--top-down-stride",
                 flags.top_down_stride,
                 "the top-down picture draws every this many keyframes")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_flag("--quiet", flags.quiet, "no progress on stderr");
  CLI11_PARSE(app, argc, argv);
  flags.condition_keyframes =
      std::min(flags.condition_keyframes, flags.keyframes);
  if (flags.condition_keyframes > 0 && flags.condition_keyframes < 1500) {
    // The report compares keyframes 500-1499 with the last 1000.
    std::fprintf(stderr,
                 "symba-window-bench: --condition-keyframes: 0 or at least "
                 "1500\n");
    return 1;
  }
  flags.accuracy_keyframes =
      std::min(flags.accuracy_keyframes,
               flags.condition_keyframes > 0 ? flags.condition_keyframes
                                             : flags.keyframes);

  std::error_code error;
  fs::create_directories(flags.out_dir, error);
  if (error) {
    std::fprintf(stderr,
                 "symba-window-bench: %s: %s\n",
                 flags.out_dir.c_str(),
                 error.message().c_str());
    return 1;
  }
  symba::SimulationOptions options;
  options.num_keyframes = flags.keyframes;
  if (flags.yaw_bias_deg >= 0.0) {
    options.yaw_bias = flags.yaw_bias_deg * 3.14159265358979323846 / 180.0;
  }
  symba::SimulatedSequence sequence;
  Status status = symba::Simulate(
      "long", options, static_cast<uint32_t>(flags.seed), &sequence);
  if (!status.ok()) {
    std::fprintf(stderr, "symba-window-bench: %s\n", status.message().c_str());
    return 1;
  }
  struct rusage self {};
  getrusage(RUSAGE_SELF, &self);
  std::vector<std::pair<WindowPolicy, int>> plan = {
      {WindowPolicy::kMarginalize, flags.keyframes}};
  if (flags.condition_keyframes > 0) {
    plan.emplace_back(WindowPolicy::kCondition, flags.condition_keyframes);
  }
  std::vector<PolicyRun> runs;
  for (const auto& [policy, keyframes] : plan) {
    if (!flags.quiet) {
      std::fprintf(stderr,
                   "symba-window-bench: %s, %d keyframes\n",
                   symba::WindowPolicyName(policy),
                   keyframes);
    }
    PolicyRun run;
    status = RunPolicy(flags, sequence, policy, keyframes, &run);
    if (!status.ok()) {
      std::fprintf(
          stderr, "symba-window-bench: %s\n", status.message().c_str());
      return 1;
    }
    runs.push_back(std::move(run));
  }
  const std::string report =
      Report(flags, runs, self.ru_maxrss, symba::bench::Command(argc, argv));
  std::fputs(report.c_str(), stdout);
  if (!flags.picture.empty()) {
    status = symba::bench::WriteText(flags.picture, Picture(flags, runs));
  }
  if (status.ok() && !flags.performance_md.empty()) {
    status = symba::bench::ReplaceTail(flags.performance_md, kHeading, report);
  }
  if (!status.ok()) {
    std::fprintf(stderr, "symba-window-bench: %s\n", status.message().c_str());
    return 1;
  }
  return 0;
}
