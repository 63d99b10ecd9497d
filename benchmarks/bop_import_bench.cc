// symba-bop-import-bench: the throughput of symba import bop on a large
// synthetic results CSV (docs/performance.md "BOP import"). Writes a
// scene_camera.json of --images images and a results CSV of about --mb
// megabytes (rows of --objects objects per image, random rotations,
// millimetre translations, six decimals as detectors print them), then
// times, best of --repeats: reading the CSV alone, the whole import in
// memory (ImportBop), and the import with the log written (ImportBopToLog).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>

#include "import/bop_files.h"
#include "symba/import/bop_import.h"

namespace {

namespace fs = std::filesystem;

struct Flags {
  double mb = 100.0;
  int images = 5000;
  int objects = 21;
  int repeats = 3;
  std::string dir = SYMBA_BOP_BENCH_DEFAULT_DIR;
};

void WriteInputs(const Flags& flags, std::size_t* csv_bytes) {
  fs::create_directories(flags.dir);
  std::ofstream camera(fs::path(flags.dir) / "scene_camera.json");
  camera << "{\n";
  for (int i = 0; i < flags.images; ++i) {
    camera << (i ? ",\n" : "") << "\"" << i
           << "\": {\"cam_K\": [600, 0, 320, 0, 600, 240, 0, 0, 1], "
              "\"cam_R_w2c\": [1, 0, 0, 0, 1, 0, 0, 0, 1], \"cam_t_w2c\": "
              "[0, 0, "
           << i << "]}";
  }
  camera << "\n}\n";
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  std::ofstream csv(fs::path(flags.dir) / "results.csv");
  csv << "scene_id,im_id,obj_id,score,R,t,time\n";
  const std::size_t target = static_cast<std::size_t>(flags.mb * 1e6);
  std::size_t bytes = 0;
  char line[512];
  for (int row = 0; bytes < target; ++row) {
    const int image = (row / flags.objects) % flags.images;
    const int object = row % flags.objects + 1;
    const Eigen::Matrix3d R =
        Eigen::Quaterniond(
            Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng))
                .normalized())
            .toRotationMatrix();
    const int n = std::snprintf(
        line,
        sizeof(line),
        "1,%d,%d,%.6f,%.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f %.6f,"
        "%.6f %.6f %.6f,%.6f\n",
        image,
        object,
        0.5 + 0.01 * (row % 50),
        R(0, 0),
        R(0, 1),
        R(0, 2),
        R(1, 0),
        R(1, 1),
        R(1, 2),
        R(2, 0),
        R(2, 1),
        R(2, 2),
        100.0 * normal(rng),
        100.0 * normal(rng),
        1500.0 + 100.0 * normal(rng),
        0.05);
    csv.write(line, n);
    bytes += static_cast<std::size_t>(n);
  }
  *csv_bytes = bytes;
}

// /proc/loadavg's three load averages, "?" where unreadable: the machine
// may be shared, and the times mean little without it.
std::string LoadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  if (!(in >> one >> five >> fifteen)) return "?";
  return one + " " + five + " " + fifteen;
}

// The best wall and CPU (user + system, this process) seconds of a step:
// on a shared machine the CPU time says what the step costs when the wall
// time also counts waiting for a core.
struct Best {
  double wall = 1e300;
  double cpu = 1e300;
};

template <typename F>
Best BestSeconds(int repeats, F run) {
  Best best;
  for (int r = 0; r < repeats; ++r) {
    const std::clock_t cpu_start = std::clock();
    const auto start = std::chrono::steady_clock::now();
    if (!run()) return {-1.0, -1.0};
    best.wall = std::min(
        best.wall,
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
            .count());
    best.cpu = std::min(
        best.cpu,
        static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
  }
  return best;
}

void PrintRow(const char* step, const Best& best, double mb) {
  std::printf("| %s | %.3f | %.0f | %.3f |\n",
              step,
              best.wall,
              mb / best.wall,
              best.cpu);
}

}  // namespace

int main(int argc, char** argv) {
  Flags flags;
  CLI::App app{"symba-bop-import-bench: symba import bop's throughput"};
  app.add_option("--mb", flags.mb, "size of the results CSV (MB)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--images", flags.images, "images in scene_camera.json")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--objects", flags.objects, "rows per image and round")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--repeats", flags.repeats, "best of this many runs")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--dir", flags.dir, "where the inputs are written")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const std::string load_before = LoadAverage();
  std::size_t bytes = 0;
  WriteInputs(flags, &bytes);
  symba::BopImportOptions options;
  options.results = (fs::path(flags.dir) / "results.csv").string();
  options.scene_camera = (fs::path(flags.dir) / "scene_camera.json").string();
  options.gate = 0.01;
  const std::string log = (fs::path(flags.dir) / "out.jsonl").string();
  std::string error;
  auto check = [&](const symba::Status& status) {
    if (!status.ok()) error = status.message();
    return status.ok();
  };
  std::vector<symba::import_internal::BopResultRow> rows;
  const Best read = BestSeconds(flags.repeats, [&] {
    return check(symba::import_internal::ReadBopResults(
        options.results, std::nullopt, &rows));
  });
  symba::BopImportReport report;
  const Best import = BestSeconds(flags.repeats, [&] {
    symba::LogHeader header;
    std::vector<symba::KeyframeInput> keyframes;
    return check(symba::ImportBop(options, &header, &keyframes, &report));
  });
  const Best to_log = BestSeconds(flags.repeats, [&] {
    return check(symba::ImportBopToLog(options, log, &report));
  });
  if (!error.empty()) {
    std::fprintf(stderr, "symba-bop-import-bench: %s\n", error.c_str());
    return 1;
  }
  const double mb = static_cast<double>(bytes) / 1e6;
  std::printf("results CSV: %.1f MB, %d rows, %d keyframes, %d detections\n",
              mb,
              report.rows,
              report.keyframes,
              report.detections);
  std::printf(
      "| step | seconds (best of %d) | MB/s | CPU seconds (best) |\n"
      "|---|---:|---:|---:|\n",
      flags.repeats);
  PrintRow("read the CSV", read, mb);
  PrintRow("import in memory (ImportBop)", import, mb);
  PrintRow("import and write the log (ImportBopToLog)", to_log, mb);
  std::printf("load average (1, 5, 15 min): %s before, %s after\n",
              load_before.c_str(),
              LoadAverage().c_str());
  fs::remove(log);
  return 0;
}
