// symba-log-read-bench: how fast LogReader reads a log (docs/performance.md,
// "Log reading").
//
// Writes a log of at least --mb megabytes (default 64) to a temporary file
// with LogWriter: keyframes with a pose, odometry, 5 detections of 30
// hypotheses each and 100 point observations, every number a full-precision
// double (the slowest case to parse). Then reads it --runs times (default 3)
// and prints the best throughput of:
//   reader       LogReader::Open + Next until the end (what a replay pays);
//   fast parse   the JSON parse alone, fast scanner (no validation);
//   nlohmann     the JSON parse alone with nlohmann's SAX parser, which the
//                reader falls back to (for reference);
//   nlohmann DOM nlohmann::json::parse of each line (for reference).
//
//   symba-log-read-bench [--mb N] [--runs N]
#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "io/json_tree.h"
#include "symba/io/log_format.h"

namespace {

using Clock = std::chrono::steady_clock;

symba::Rigid3d RandomPose(std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(*rng), normal(*rng), normal(*rng), normal(*rng));
  q.normalize();
  return symba::Rigid3d(
      q, Eigen::Vector3d(normal(*rng), normal(*rng), 2.0 + normal(*rng)));
}

// Writes the log; returns its size in bytes (0 on failure).
long WriteLog(const std::string& path, long min_bytes, int* keyframes) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  symba::LogHeader header;
  header.camera = symba::PinholeIntrinsics{525.0, 525.0, 319.5, 239.5};
  std::unique_ptr<symba::LogWriter> writer;
  symba::Status status = symba::LogWriter::Open(path, header, &writer);
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.message().c_str());
    return 0;
  }
  symba::KeyframeInput keyframe;
  keyframe.detections.resize(5);
  keyframe.points.resize(100);
  long bytes = 0;
  for (int k = 0; bytes < min_bytes; ++k) {
    keyframe.id = k;
    keyframe.timestamp = 1700000000.0 + 0.1 * k;
    keyframe.T_wc = RandomPose(&rng);
    keyframe.odometry = symba::Odometry{RandomPose(&rng), 0.01, 0.005};
    for (int d = 0; d < 5; ++d) {
      symba::DetectionInput& detection = keyframe.detections[d];
      detection.id = std::to_string(k) + "/" + std::to_string(d);
      detection.class_name = "table";
      detection.score = uniform(rng);
      detection.hypotheses.resize(30);
      for (symba::PoseHypothesis& hypothesis : detection.hypotheses) {
        hypothesis.T_co = RandomPose(&rng);
        hypothesis.weight = 0.01 + uniform(rng);
      }
    }
    for (int p = 0; p < 100; ++p) {
      symba::PointObservation& point = keyframe.points[p];
      point.id = 100 * k + p;
      point.uv = Eigen::Vector2d(640.0 * uniform(rng), 480.0 * uniform(rng));
      point.depth = 0.5 + 5.0 * uniform(rng);
    }
    status = writer->Write(keyframe);
    if (!status.ok()) {
      std::fprintf(stderr, "%s\n", status.message().c_str());
      return 0;
    }
    *keyframes = k + 1;
    // The size so far, roughly (the exact size is taken from the file).
    if (k % 64 == 0) bytes = std::ifstream(path, std::ios::ate).tellg();
  }
  status = writer->Close();
  if (!status.ok()) {
    std::fprintf(stderr, "%s\n", status.message().c_str());
    return 0;
  }
  return static_cast<long>(std::ifstream(path, std::ios::ate).tellg());
}

double Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Runs `read` `runs` times; returns the best time.
template <typename Read>
double Best(int runs, Read read) {
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    const Clock::time_point start = Clock::now();
    if (!read()) std::exit(1);
    best = std::min(best, Seconds(start));
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  long mb = 64;
  int runs = 3;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--mb") == 0 && i + 1 < argc) {
      mb = std::atol(argv[++i]);
    } else if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc) {
      runs = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: %s [--mb N] [--runs N]\n", argv[0]);
      return 2;
    }
  }
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp != nullptr ? tmp : "/tmp") +
                           "/symba-log-read-bench-" + std::to_string(getpid()) +
                           ".jsonl";
  int keyframes = 0;
  const Clock::time_point write_start = Clock::now();
  const long bytes = WriteLog(path, mb * 1000000, &keyframes);
  const double write_seconds = Seconds(write_start);
  if (bytes <= 0) return 1;
  const double megabytes = static_cast<double>(bytes) / 1e6;
  std::printf(
      "log: %.1f MB, %d keyframes (%.0f bytes each), written in %.2f s"
      " (%.0f MB/s)\n",
      megabytes,
      keyframes,
      static_cast<double>(bytes) / keyframes,
      write_seconds,
      megabytes / write_seconds);

  const double reader = Best(runs, [&] {
    std::unique_ptr<symba::LogReader> log;
    symba::Status status = symba::LogReader::Open(path, &log);
    symba::KeyframeInput keyframe;
    int count = 0;
    bool end = false;
    while (status.ok()) {
      status = log->Next(&keyframe, &end);
      if (end) break;
      ++count;
    }
    if (!status.ok() || count != keyframes) {
      std::fprintf(stderr, "read failed: %s\n", status.message().c_str());
      return false;
    }
    return true;
  });

  auto parse_lines = [&](auto parse) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    while (std::getline(in, line)) {
      if (!parse(line)) {
        std::fprintf(stderr, "parse failed\n");
        return false;
      }
    }
    return true;
  };
  symba::io_internal::JsonTree tree;
  const double fast = Best(runs, [&] {
    return parse_lines([&](const std::string& line) {
      return symba::io_internal::ParseJsonFast(line, &tree);
    });
  });
  const double sax = Best(runs, [&] {
    return parse_lines([&](const std::string& line) {
      symba::io_internal::JsonError error;
      return symba::io_internal::ParseJsonNlohmann(line, &tree, &error);
    });
  });
  const double dom = Best(runs, [&] {
    return parse_lines([&](const std::string& line) {
      return !nlohmann::json::parse(line, nullptr, false).is_discarded();
    });
  });
  std::remove(path.c_str());

  std::printf("best of %d runs, one thread:\n", runs);
  std::printf("  reader (LogReader::Next)  %7.1f MB/s  %7.0f keyframes/s\n",
              megabytes / reader,
              keyframes / reader);
  std::printf("  fast parse only           %7.1f MB/s\n", megabytes / fast);
  std::printf("  nlohmann SAX parse only   %7.1f MB/s\n", megabytes / sax);
  std::printf("  nlohmann DOM parse only   %7.1f MB/s\n", megabytes / dom);
  return 0;
}
