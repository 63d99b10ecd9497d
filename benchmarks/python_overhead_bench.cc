// symba-python-overhead-bench: the C++ half of benchmarks/python_overhead.py
// (docs/performance.md, "Python binding overhead").
//
//   symba-python-overhead-bench --write-log PATH
//       writes the backend benchmark's keyframes (backend_bench_sequence.h)
//       as a log v1, so that Python replays exactly the same input;
//   symba-python-overhead-bench --time LOG [--repetitions R] [--copy|--empty]
//       per repetition: a fresh Backend (default options, the log's
//       camera), every keyframe AddKeyframe + OptimizeWindow; prints one
//       line per repetition with the wall and thread-CPU seconds spent in
//       AddKeyframe over the timed keyframes (after the warm-up ones).
//       --copy times a copy of the KeyframeInput plus AddKeyframe on the
//       copy: what a C++ front end that builds each keyframe pays at least,
//       the C++ counterpart of Python's building the keyframe from arrays;
//       --empty times nothing (AddKeyframe follows the clock reads): the
//       floor the clock reads put under the other two;
//   symba-python-overhead-bench --serve LOG
//       the same, one repetition per line of stdin ("add", "copy" or
//       "empty"), each answered with its line on stdout: the script
//       alternates C++ and Python run by run with one C++ process.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <utility>
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

// What --time times around each keyframe.
enum class Timed { kAdd, kCopyAndAdd, kNothing };

// AddKeyframe(keyframe); `wall` and `cpu` get the seconds spent in
// `timed`, which includes freeing the assignments (as the Python rows
// include dropping the returned list).
symba::Status TimedAdd(symba::Backend& backend,
                       const symba::KeyframeInput& keyframe,
                       Timed timed,
                       double* wall,
                       double* cpu) {
  symba::Status status;
  const auto wall_start = std::chrono::steady_clock::now();
  const double cpu_start = ThreadCpuSeconds();
  if (timed == Timed::kCopyAndAdd) {
    const symba::KeyframeInput built = keyframe;
    std::vector<symba::DetectionAssignment> assignments;
    status = backend.AddKeyframe(built, &assignments);
  } else if (timed == Timed::kAdd) {
    std::vector<symba::DetectionAssignment> assignments;
    status = backend.AddKeyframe(keyframe, &assignments);
  }
  const double cpu_end = ThreadCpuSeconds();
  const auto wall_end = std::chrono::steady_clock::now();
  if (timed == Timed::kNothing) {
    std::vector<symba::DetectionAssignment> assignments;
    status = backend.AddKeyframe(keyframe, &assignments);
  }
  *wall = std::chrono::duration<double>(wall_end - wall_start).count();
  *cpu = cpu_end - cpu_start;
  return status;
}

symba::Status ReadKeyframes(const std::string& path,
                            symba::LogHeader* header,
                            std::vector<symba::KeyframeInput>* keyframes) {
  std::unique_ptr<symba::LogReader> reader;
  symba::Status status = symba::LogReader::Open(path, &reader);
  while (status.ok()) {
    symba::KeyframeInput keyframe;
    bool end = false;
    status = reader->Next(&keyframe, &end);
    if (end) break;
    keyframes->push_back(std::move(keyframe));
  }
  if (status.ok()) *header = reader->header();
  return status;
}

// One repetition: a fresh Backend, every keyframe added and the window
// optimised; prints the seconds of `timed` over the keyframes after the
// warm-up ones.
symba::Status Repetition(const symba::LogHeader& header,
                         const std::vector<symba::KeyframeInput>& keyframes,
                         Timed timed) {
  std::unique_ptr<symba::Backend> backend;
  symba::Status status = symba::Backend::Create(
      symba::BackendOptions(), header.camera, {}, &backend);
  double wall = 0.0;
  double cpu = 0.0;
  for (size_t k = 0; status.ok() && k < keyframes.size(); ++k) {
    double keyframe_wall = 0.0;
    double keyframe_cpu = 0.0;
    status =
        TimedAdd(*backend, keyframes[k], timed, &keyframe_wall, &keyframe_cpu);
    if (status.ok()) status = backend->OptimizeWindow();
    if (static_cast<int>(k) >= symba::kBackendBenchWarmupKeyframes) {
      wall += keyframe_wall;
      cpu += keyframe_cpu;
    }
  }
  if (!status.ok()) return status;
  std::printf(
      "add_keyframe_wall_s %.9f add_keyframe_cpu_s %.9f keyframes %d\n",
      wall,
      cpu,
      static_cast<int>(keyframes.size()) - symba::kBackendBenchWarmupKeyframes);
  std::fflush(stdout);
  return status;
}

bool ParseTimed(const std::string& text, Timed* timed) {
  if (text == "add") {
    *timed = Timed::kAdd;
  } else if (text == "copy") {
    *timed = Timed::kCopyAndAdd;
  } else if (text == "empty") {
    *timed = Timed::kNothing;
  } else {
    return false;
  }
  return true;
}

// --time: `repetitions` repetitions of one kind; --serve: one repetition
// per line of stdin naming its kind, until the end of stdin.
int Time(const std::string& path, int repetitions, Timed timed, bool serve) {
  symba::LogHeader header;
  std::vector<symba::KeyframeInput> keyframes;
  symba::Status status = ReadKeyframes(path, &header, &keyframes);
  for (int r = 0; status.ok() && !serve && r < repetitions; ++r) {
    status = Repetition(header, keyframes, timed);
  }
  char line[64];
  while (status.ok() && serve && std::fgets(line, sizeof(line), stdin)) {
    std::string text(line);
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) {
      text.pop_back();
    }
    if (!ParseTimed(text, &timed)) return Fail("unknown kind " + text);
    status = Repetition(header, keyframes, timed);
  }
  return status.ok() ? 0 : Fail(status.message());
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() == 2 && args[0] == "--write-log") return WriteLog(args[1]);
  if (args.size() == 2 && args[0] == "--serve") {
    return Time(args[1], 0, Timed::kAdd, true);
  }
  if (args.size() >= 2 && args[0] == "--time") {
    int repetitions = 1;
    Timed timed = Timed::kAdd;
    for (size_t i = 2; i < args.size(); ++i) {
      if (args[i] == "--copy") {
        timed = Timed::kCopyAndAdd;
      } else if (args[i] == "--empty") {
        timed = Timed::kNothing;
      } else if (args[i] == "--repetitions" && i + 1 < args.size()) {
        repetitions = std::atoi(args[++i].c_str());
        if (repetitions < 1) return Fail("--repetitions must be >= 1");
      } else {
        return Fail("unknown option " + args[i]);
      }
    }
    return Time(args[1], repetitions, timed, false);
  }
  return Fail(
      "usage: symba-python-overhead-bench --write-log PATH | --time LOG "
      "[--repetitions R] [--copy|--empty] | --serve LOG");
}
