// symba-python-overhead-bench: the C++ half of benchmarks/python_overhead.py
// (docs/performance.md, "Python binding overhead").
//
//   symba-python-overhead-bench --write-log PATH
//       writes the backend benchmark's keyframes (backend_bench_sequence.h)
//       as a log v1, so that Python replays exactly the same input;
//   symba-python-overhead-bench --time LOG [--repetitions R] [--copy]
//       per repetition: a fresh Backend (default options, the log's
//       camera), every keyframe AddKeyframe + OptimizeWindow; prints one
//       line per repetition with the wall and thread-CPU seconds spent in
//       AddKeyframe over the timed keyframes (after the warm-up ones).
//       --copy times a copy of the KeyframeInput plus AddKeyframe on the
//       copy: what a C++ front end that builds each keyframe pays at least,
//       the C++ counterpart of Python's building the keyframe from arrays.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "backend_bench_sequence.h"
#include "symba/backend/backend.h"
#include "symba/io/log_format.h"

namespace {

double ThreadCpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int Fail(const std::string& message) {
  std::fprintf(stderr, "symba-python-overhead-bench: %s\n", message.c_str());
  return 1;
}

int WriteLog(const std::string& path) {
  symba::LogHeader header;
  symba::PinholeIntrinsics intrinsics;
  const std::vector<symba::KeyframeInput> keyframes =
      symba::MakeBackendBenchSequence(&intrinsics);
  header.camera = intrinsics;
  std::unique_ptr<symba::LogWriter> writer;
  symba::Status status = symba::LogWriter::Open(path, header, &writer);
  for (size_t k = 0; status.ok() && k < keyframes.size(); ++k) {
    status = writer->Write(keyframes[k]);
  }
  if (status.ok()) status = writer->Close();
  return status.ok() ? 0 : Fail(status.message());
}

int Time(const std::string& path, int repetitions, bool copy) {
  std::unique_ptr<symba::LogReader> reader;
  symba::Status status = symba::LogReader::Open(path, &reader);
  std::vector<symba::KeyframeInput> keyframes;
  while (status.ok()) {
    symba::KeyframeInput keyframe;
    bool end = false;
    status = reader->Next(&keyframe, &end);
    if (end) break;
    keyframes.push_back(std::move(keyframe));
  }
  if (!status.ok()) return Fail(status.message());
  for (int r = 0; r < repetitions; ++r) {
    std::unique_ptr<symba::Backend> backend;
    status = symba::Backend::Create(
        symba::BackendOptions(), reader->header().camera, {}, &backend);
    if (!status.ok()) return Fail(status.message());
    double wall = 0.0;
    double cpu = 0.0;
    for (size_t k = 0; k < keyframes.size(); ++k) {
      std::vector<symba::DetectionAssignment> assignments;
      const auto wall_start = std::chrono::steady_clock::now();
      const double cpu_start = ThreadCpuSeconds();
      if (copy) {
        const symba::KeyframeInput built = keyframes[k];
        status = backend->AddKeyframe(built, &assignments);
      } else {
        status = backend->AddKeyframe(keyframes[k], &assignments);
      }
      const double cpu_end = ThreadCpuSeconds();
      const auto wall_end = std::chrono::steady_clock::now();
      if (status.ok()) status = backend->OptimizeWindow();
      if (!status.ok()) return Fail(status.message());
      if (static_cast<int>(k) >= symba::kBackendBenchWarmupKeyframes) {
        wall += std::chrono::duration<double>(wall_end - wall_start).count();
        cpu += cpu_end - cpu_start;
      }
    }
    std::printf(
        "add_keyframe_wall_s %.9f add_keyframe_cpu_s %.9f keyframes %d\n",
        wall,
        cpu,
        static_cast<int>(keyframes.size()) -
            symba::kBackendBenchWarmupKeyframes);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 2 && args[0] == "--write-log") return WriteLog(args[1]);
  if (args.size() >= 2 && args[0] == "--time") {
    int repetitions = 1;
    bool copy = false;
    for (size_t i = 2; i < args.size(); ++i) {
      if (args[i] == "--copy") {
        copy = true;
      } else if (args[i] == "--repetitions" && i + 1 < args.size()) {
        repetitions = std::atoi(args[++i].c_str());
        if (repetitions < 1) return Fail("--repetitions must be >= 1");
      } else {
        return Fail("unknown option " + args[i]);
      }
    }
    return Time(args[1], repetitions, copy);
  }
  return Fail(
      "usage: symba-python-overhead-bench --write-log PATH | --time LOG "
      "[--repetitions R] [--copy]");
}
