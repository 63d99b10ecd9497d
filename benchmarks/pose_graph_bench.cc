// symba-posegraph-bench: reads g2o 3-D pose graphs and optimises each with
// OptimizePoseGraph from the chordal initialisation (or, with --given, the
// file's initial guess), printing the time, iterations and the cost at the
// file's poses, where the solver started and where it ended
// (docs/performance.md, "Pose graphs").
//
//   symba-posegraph-bench [--threads N] [--max-iterations N] [--given]
//                         [--isotropic] [--g2o-half-angle] [file.g2o ...]
//
// Without files it solves parking-garage, sphere2500, cubicle and torus3D
// from the repository's data/posegraph. --isotropic reads every
// information as SE-Sync's isotropic approximation (G2oReadOptions), so the
// final cost is comparable to half the published SE-Sync optimum.
// --g2o-half-angle uses g2o's literal rotation error
// (PoseGraphRotationError::kG2oHalfAngle).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "symba/io/pose_graph.h"
#include "symba/pose_graph/optimize_pose_graph.h"

namespace {

constexpr const char* kDefaultFiles[] = {
    "parking-garage.g2o", "sphere2500.g2o", "cubicle.g2o", "torus3D.g2o"};

int Usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s [--threads N] [--max-iterations N] [--given] "
               "[--isotropic] [--g2o-half-angle] [file.g2o ...]\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  symba::PoseGraphSolveOptions options;
  symba::G2oReadOptions read_options;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--threads" || arg == "--max-iterations") && i + 1 < argc) {
      const int value = std::atoi(argv[++i]);
      (arg == "--threads" ? options.num_threads : options.max_iterations) =
          value;
    } else if (arg == "--given") {
      options.initialization = symba::PoseGraphInitialization::kGiven;
    } else if (arg == "--isotropic") {
      read_options.isotropic_information = true;
    } else if (arg == "--g2o-half-angle") {
      options.rotation_error = symba::PoseGraphRotationError::kG2oHalfAngle;
    } else if (!arg.empty() && arg[0] == '-') {
      return Usage(argv[0]);
    } else {
      files.push_back(arg);
    }
  }
  if (files.empty()) {
    for (const char* name : kDefaultFiles) {
      files.push_back(std::string(SYMBA_POSEGRAPH_DATA_DIR) + "/" + name);
    }
  }

  std::printf("%-20s %6s %6s %8s %8s %8s %8s %6s %14s %14s %14s %s\n",
              "file",
              "poses",
              "edges",
              "read_s",
              "init_s",
              "solve_s",
              "cpu_s",
              "iters",
              "given_cost",
              "initial_cost",
              "final_cost",
              "termination");
  int failures = 0;
  for (const std::string& path : files) {
    const auto start = std::chrono::steady_clock::now();
    symba::PoseGraph graph;
    symba::Status status = symba::ReadG2oPoseGraph(path, &graph, read_options);
    const double read_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count();
    if (!status.ok()) {
      std::fprintf(stderr, "%s\n", status.message().c_str());
      ++failures;
      continue;
    }
    symba::PoseGraphSolveSummary summary;
    // CPU time as well as Ceres's wall time: on a shared machine the wall
    // time includes waiting for a core.
    const std::clock_t cpu_start = std::clock();
    status = symba::OptimizePoseGraph(options, &graph, &summary);
    const double cpu_seconds =
        static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    if (!status.ok()) {
      std::fprintf(stderr, "%s\n", status.message().c_str());
      ++failures;
      continue;
    }
    const std::string name = path.substr(path.find_last_of('/') + 1);
    std::printf(
        "%-20s %6d %6d %8.3f %8.3f %8.3f %8.3f %6d %14.7e %14.7e "
        "%14.7e %s\n",
        name.c_str(),
        summary.num_vertices,
        summary.num_edges,
        read_seconds,
        summary.initialization_seconds,
        summary.seconds,
        cpu_seconds,
        summary.iterations,
        summary.given_cost,
        summary.initial_cost,
        summary.final_cost,
        summary.converged ? "CONVERGENCE" : summary.message.c_str());
  }
  return failures == 0 ? 0 : 1;
}
