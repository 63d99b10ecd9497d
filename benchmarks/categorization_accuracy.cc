// symba-categorization-bench: accuracy of Categorize() on generated
// detections (tests/test_support/hypothesis_generator.h), swept over symmetry
// types, orders, visible modes, rotation noise and outlier fractions. Prints
// one row per cell and the confusion matrix; docs/categorization.md records
// the output. Deterministic for a given seed.
//
//   symba-categorization-bench [--detections=1000] [--seed=1] [--n=30]
//                              [--noise=angle|per-axis]
//                              [--set=<option>=<value>]... [--stats]
//
// --noise says what "a rotation noise of s degrees" means: `angle` (the
// default) makes s the RMS angle of each hypothesis' rotation error, i.e.
// s / sqrt(3) per axis, the way detectors report rotation error; `per-axis`
// draws s per axis (RMS angle s sqrt(3)), the harsher reading.
//
// --set overrides one CategorizationOptions field (angles in degrees, the
// translation gate in metres), to measure the sensitivity of a threshold.
// --stats adds, per cell, percentiles of the statistics the decision rule
// thresholds (docs/categorization.md uses them to defend the defaults).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "symba/categorization/categorize.h"
#include "test_support/hypothesis_generator.h"

namespace symba {
namespace {

using testing::GeneratedDetection;
using testing::HypothesisSetSpec;
using testing::kDegree;

struct Shape {
  std::string name;
  SymmetryType type;
  int order;
  std::vector<int> visible;
};

struct DecisionStats {
  std::vector<double> empty;       // empty fraction
  std::vector<double> extent;      // max cluster extent, deg
  std::vector<double> separation;  // min cluster separation, deg (>= 2)
  std::vector<double> noise;       // DBSCAN noise / axis inliers
};

struct CellStats {
  int count = 0;
  int predicted[3] = {0, 0, 0};
  std::vector<double> axis_c_error;  // deg, correctly typed symmetric
  std::vector<double> axis_o_error;  // deg
  std::vector<double> angle_error;   // deg, non-reference clusters
  int modes_checked = 0;
  int all_modes_found = 0;  // every visible mode is a cluster, no extras
  int outliers = 0;
  int outliers_kept = 0;
  int inliers = 0;
  int inliers_kept = 0;
};

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const double pos = p * (v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

double AxisErrorDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::min(1.0, std::abs(a.normalized().dot(b.normalized())));
  return std::acos(c) / kDegree;
}

void Score(const GeneratedDetection& d,
           const CategorizedDetection& c,
           int order,
           CellStats* stats) {
  ++stats->count;
  ++stats->predicted[static_cast<int>(c.type)];
  const int n = static_cast<int>(d.hypotheses.size());
  std::vector<char> kept(n, 0);
  for (int j : c.inliers) kept[j] = 1;
  for (int j = 0; j < n; ++j) {
    if (d.mode[j] < 0) {
      ++stats->outliers;
      stats->outliers_kept += kept[j];
    } else {
      ++stats->inliers;
      stats->inliers_kept += kept[j];
    }
  }
  if (c.type != d.expected_type) return;
  if (c.type == SymmetryType::kAsymmetric) return;
  stats->axis_c_error.push_back(AxisErrorDeg(c.axis_c, d.axis_c));
  stats->axis_o_error.push_back(AxisErrorDeg(c.axis_o, d.axis_o));
  if (c.type != SymmetryType::kDiscrete) return;
  // Each cluster's true mode: the majority of its members' modes.
  const double sign = c.axis_o.dot(d.axis_o) < 0.0 ? -1.0 : 1.0;
  std::vector<int> cluster_mode;
  for (const AngleCluster& cluster : c.clusters) {
    std::map<int, int> votes;
    for (int j : cluster.members) {
      if (d.mode[j] >= 0) ++votes[d.mode[j]];
    }
    int best = -1;
    int best_votes = 0;
    for (const auto& [mode, v] : votes) {
      if (v > best_votes) {
        best = mode;
        best_votes = v;
      }
    }
    cluster_mode.push_back(best);
  }
  for (size_t i = 1; i < c.clusters.size(); ++i) {
    if (cluster_mode[i] < 0 || cluster_mode[0] < 0) continue;
    const double truth = kTwoPi * (cluster_mode[i] - cluster_mode[0]) / order;
    stats->angle_error.push_back(
        std::abs(WrapToPi(sign * c.clusters[i].theta - truth)) / kDegree);
  }
  std::vector<int> found = cluster_mode;
  std::sort(found.begin(), found.end());
  std::vector<int> visible = d.visible_modes;
  std::sort(visible.begin(), visible.end());
  ++stats->modes_checked;
  stats->all_modes_found += found == visible;
}

void PrintDecisionStats(const std::string& cell, const DecisionStats& s) {
  auto row = [](const char* name, const std::vector<double>& v) {
    if (v.empty()) return;
    std::printf(
        "    %-22s p0.1 %7.3f  p1 %7.3f  p50 %7.3f  p99 %7.3f  "
        "p99.9 %7.3f\n",
        name,
        Percentile(v, 0.001),
        Percentile(v, 0.01),
        Percentile(v, 0.5),
        Percentile(v, 0.99),
        Percentile(v, 0.999));
  };
  if (s.empty.empty()) return;
  std::printf("  %s\n", cell.c_str());
  row("empty fraction", s.empty);
  row("max extent (deg)", s.extent);
  row("min separation (deg)", s.separation);
  row("noise fraction", s.noise);
}

int Run(int detections,
        unsigned seed,
        int num_hypotheses,
        bool noise_per_axis,
        const CategorizationOptions& options,
        bool print_stats) {
  const std::vector<Shape> shapes = {
      {"asymmetric", SymmetryType::kAsymmetric, 1, {}},
      {"continuous", SymmetryType::kContinuous, 1, {}},
      {"C2 all", SymmetryType::kDiscrete, 2, {}},
      {"C3 all", SymmetryType::kDiscrete, 3, {}},
      {"C4 all", SymmetryType::kDiscrete, 4, {}},
      {"C6 all", SymmetryType::kDiscrete, 6, {}},
      {"C3 {0,1}", SymmetryType::kDiscrete, 3, {0, 1}},
      {"C4 {0,1}", SymmetryType::kDiscrete, 4, {0, 1}},
      {"C4 {0,2}", SymmetryType::kDiscrete, 4, {0, 2}},
      {"C6 {0,1}", SymmetryType::kDiscrete, 6, {0, 1}},
      {"C6 {0,1,2}", SymmetryType::kDiscrete, 6, {0, 1, 2}},
      {"C6 {0,2,4}", SymmetryType::kDiscrete, 6, {0, 2, 4}},
      {"C2 {0}", SymmetryType::kDiscrete, 2, {0}},
      {"C4 {0}", SymmetryType::kDiscrete, 4, {0}},
      {"C6 {0}", SymmetryType::kDiscrete, 6, {0}},
  };
  const double noises[] = {2.0, 5.0};
  const double outlier_fractions[] = {0.0, 0.1, 0.2};
  int confusion[3][3] = {{0}};
  std::vector<std::pair<std::string, DecisionStats>> all_decision_stats;
  double seconds = 0.0;
  long total = 0;

  std::printf(
      "symba-categorization-bench: %d detections per cell, N = %d, seed %u\n"
      "noise: %s\n"
      "axis errors in the camera frame (axis_c) and object frame (axis_o), "
      "cluster angle errors, in degrees (median / p95)\n\n",
      detections,
      num_hypotheses,
      seed,
      noise_per_axis ? "per axis (RMS rotation angle = noise x sqrt(3))"
                     : "RMS rotation angle (noise / sqrt(3) per axis)");
  std::printf(
      "%-11s %5s %4s | %6s %6s %6s | %7s | %-11s | %-11s | %-11s | %6s | %6s "
      "%6s\n",
      "cell",
      "noise",
      "out%",
      "asym%",
      "disc%",
      "cont%",
      "correct",
      "axis_c",
      "axis_o",
      "angle",
      "modes%",
      "outin%",
      "inin%");
  unsigned cell_seed = seed;
  for (const Shape& shape : shapes) {
    for (double noise : noises) {
      for (double outliers : outlier_fractions) {
        HypothesisSetSpec spec;
        spec.type = shape.type;
        spec.order = shape.order;
        spec.visible_modes = shape.visible;
        spec.rotation_sigma =
            noise * kDegree / (noise_per_axis ? 1.0 : std::sqrt(3.0));
        spec.outlier_fraction = outliers;
        spec.num_hypotheses = num_hypotheses;
        testing::TestRandom random(cell_seed++);
        CellStats stats;
        DecisionStats decision;
        CategorizedDetection result;
        int expected = 0;
        for (int i = 0; i < detections; ++i) {
          const GeneratedDetection d = GenerateDetection(spec, &random);
          const auto start = std::chrono::steady_clock::now();
          const Status status =
              Categorize(d.hypotheses, options, nullptr, &result);
          seconds += std::chrono::duration<double>(
                         std::chrono::steady_clock::now() - start)
                         .count();
          ++total;
          if (!status.ok()) {
            std::fprintf(stderr, "error: %s\n", status.message().c_str());
            return 1;
          }
          Score(d, result, shape.order, &stats);
          const CategorizationDiagnostics& g = result.diagnostics;
          if (g.num_axis_inliers > 0 && g.num_raw_clusters > 0) {
            decision.empty.push_back(g.empty_fraction);
            decision.extent.push_back(g.max_cluster_extent / kDegree);
            if (g.min_cluster_separation > 0) {
              decision.separation.push_back(g.min_cluster_separation / kDegree);
            }
            decision.noise.push_back(static_cast<double>(g.num_noise) /
                                     g.num_axis_inliers);
          }
          expected = static_cast<int>(d.expected_type);
          ++confusion[expected][static_cast<int>(result.type)];
        }
        auto pct = [&](int k) { return 100.0 * k / stats.count; };
        auto pair = [](const std::vector<double>& v) {
          char buf[32];
          if (v.empty()) {
            std::snprintf(buf, sizeof(buf), "-");
          } else {
            std::snprintf(buf,
                          sizeof(buf),
                          "%.2f / %.2f",
                          Percentile(v, 0.5),
                          Percentile(v, 0.95));
          }
          return std::string(buf);
        };
        char modes[16] = "-";
        if (stats.modes_checked > 0) {
          std::snprintf(modes,
                        sizeof(modes),
                        "%.1f",
                        100.0 * stats.all_modes_found / stats.modes_checked);
        }
        char outin[16] = "-";
        if (stats.outliers > 0) {
          std::snprintf(outin,
                        sizeof(outin),
                        "%.1f",
                        100.0 * stats.outliers_kept / stats.outliers);
        }
        std::printf(
            "%-11s %5.0f %4.0f | %6.1f %6.1f %6.1f | %6.1f%% | %-11s | %-11s "
            "| %-11s | %6s | %6s %6.1f\n",
            shape.name.c_str(),
            noise,
            100 * outliers,
            pct(stats.predicted[0]),
            pct(stats.predicted[1]),
            pct(stats.predicted[2]),
            pct(stats.predicted[expected]),
            pair(stats.axis_c_error).c_str(),
            pair(stats.axis_o_error).c_str(),
            pair(stats.angle_error).c_str(),
            modes,
            outin,
            100.0 * stats.inliers_kept / stats.inliers);
        if (print_stats) {
          char name[64];
          std::snprintf(name,
                        sizeof(name),
                        "%s, noise %.0f deg, %.0f %% outliers",
                        shape.name.c_str(),
                        noise,
                        100 * outliers);
          all_decision_stats.emplace_back(name, std::move(decision));
        }
      }
    }
  }
  if (print_stats) {
    std::printf(
        "\ndecision statistics of the final pass, per cell (detections that "
        "reached the twist clustering)\n");
    for (const auto& [name, decision] : all_decision_stats) {
      PrintDecisionStats(name, decision);
    }
  }
  std::printf(
      "\nconfusion matrix over all cells (rows: expected, columns: "
      "categorized)\n%-12s %10s %10s %10s\n",
      "",
      "asymmetric",
      "discrete",
      "continuous");
  const char* names[] = {"asymmetric", "discrete", "continuous"};
  for (int e = 0; e < 3; ++e) {
    std::printf("%-12s %10d %10d %10d\n",
                names[e],
                confusion[e][0],
                confusion[e][1],
                confusion[e][2]);
  }
  std::printf("\nmean time per categorization: %.2f us (%ld detections)\n",
              1e6 * seconds / total,
              total);
  std::printf(
      "columns: correct = expected type; modes%% = discrete detections whose "
      "clusters are exactly the visible modes; outin%% = outlier hypotheses "
      "kept as inliers; inin%% = true inliers kept\n");
  return 0;
}

}  // namespace
}  // namespace symba

namespace {

// Sets one option from "--set=<name>=<value>"; angles are given in degrees.
bool SetOption(const std::string& assignment,
               symba::CategorizationOptions* options) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos) return false;
  const std::string name = assignment.substr(0, eq);
  char* end = nullptr;
  const double value = std::strtod(assignment.c_str() + eq + 1, &end);
  if (end == assignment.c_str() + eq + 1 || *end != '\0') return false;
  constexpr double kDeg = symba::testing::kDegree;
  const std::pair<const char*, double*> angles[] = {
      {"min_axis_angle", &options->min_axis_angle},
      {"axis_vote_angle", &options->axis_vote_angle},
      {"swing_tolerance", &options->swing_tolerance},
      {"cluster_eps", &options->cluster_eps},
      {"max_cluster_extent", &options->max_cluster_extent},
      {"min_cluster_separation", &options->min_cluster_separation},
      {"empty_gap_angle", &options->empty_gap_angle},
      {"asymmetric_inlier_angle", &options->asymmetric_inlier_angle},
      {"prior_snap_angle", &options->prior_snap_angle}};
  for (const auto& [key, field] : angles) {
    if (name == key) {
      *field = value * kDeg;
      return true;
    }
  }
  const std::pair<const char*, double*> plain[] = {
      {"separation_ratio", &options->separation_ratio},
      {"max_noise_fraction", &options->max_noise_fraction},
      {"min_empty_fraction", &options->min_empty_fraction},
      {"translation_gate", &options->translation_gate}};
  for (const auto& [key, field] : plain) {
    if (name == key) {
      *field = value;
      return true;
    }
  }
  if (name == "min_points") {
    options->min_points = static_cast<int>(value);
  } else if (name == "rescue_min_points") {
    options->rescue_min_points = static_cast<int>(value);
  } else if (name == "merge_close_clusters") {
    options->merge_close_clusters = value != 0.0;
  } else {
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  int detections = 1000;
  unsigned seed = 1;
  int n = 30;
  bool stats = false;
  bool noise_per_axis = false;
  symba::CategorizationOptions options;
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    if (std::strncmp(arg, "--detections=", 13) == 0) {
      detections = std::atoi(arg + 13);
    } else if (std::strncmp(arg, "--seed=", 7) == 0) {
      seed = static_cast<unsigned>(std::strtoul(arg + 7, nullptr, 10));
    } else if (std::strncmp(arg, "--n=", 4) == 0) {
      n = std::atoi(arg + 4);
    } else if (std::strcmp(arg, "--noise=angle") == 0) {
      noise_per_axis = false;
    } else if (std::strcmp(arg, "--noise=per-axis") == 0) {
      noise_per_axis = true;
    } else if (std::strcmp(arg, "--stats") == 0) {
      stats = true;
    } else if (std::strncmp(arg, "--set=", 6) == 0 &&
               SetOption(arg + 6, &options)) {
      std::printf("option %s\n", arg + 6);
    } else {
      std::fprintf(stderr,
                   "usage: %s [--detections=1000] [--seed=1] [--n=30] "
                   "[--noise=angle|per-axis] [--set=<option>=<value>]... "
                   "[--stats]\n",
                   argv[0]);
      return 2;
    }
  }
  if (detections < 1 || n < 1) {
    std::fprintf(stderr, "--detections and --n must be positive\n");
    return 2;
  }
  const symba::Status status = options.Validate();
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.message().c_str());
    return 2;
  }
  return symba::Run(detections, seed, n, noise_per_axis, options, stats);
}
