// Windowed solve time per keyframe of the backend (issue 4's workload): a
// window of 10 keyframes, every keyframe sees 5 objects with 30 hypotheses
// each and 100 map points. The camera circles the objects (radius 2.5 m) and
// sees points on a wall of radius 6 m. The first 10 keyframes fill the window
// untimed; the next 30 are timed, each AddKeyframe + OptimizeWindow.
// Reported: keyframes per second (items_per_second) and ms per keyframe.
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "backend_bench_sequence.h"
#include "symba/backend/backend.h"

namespace symba {
namespace {

constexpr int kWarmupKeyframes = kBackendBenchWarmupKeyframes;
constexpr int kTimedKeyframes = kBackendBenchTimedKeyframes;

void BM_BackendWindowedSolvePerKeyframe(benchmark::State& state) {
  PinholeIntrinsics intrinsics;
  const std::vector<KeyframeInput> keyframes =
      MakeBackendBenchSequence(&intrinsics);
  BackendOptions options;
  options.method = static_cast<Method>(state.range(0));
  options.window_size = 10;
  int points = 0;
  for (auto _ : state) {
    state.PauseTiming();
    std::unique_ptr<Backend> backend;
    if (!Backend::Create(options, intrinsics, {}, &backend).ok()) {
      state.SkipWithError("Backend::Create failed");
      break;
    }
    for (int k = 0; k < kWarmupKeyframes; ++k) {
      if (!backend->AddKeyframe(keyframes[k]).ok() ||
          !backend->OptimizeWindow().ok()) {
        state.SkipWithError("warm-up failed");
        break;
      }
    }
    state.ResumeTiming();
    for (int k = kWarmupKeyframes; k < kWarmupKeyframes + kTimedKeyframes;
         ++k) {
      if (!backend->AddKeyframe(keyframes[k]).ok() ||
          !backend->OptimizeWindow().ok()) {
        state.SkipWithError("solve failed");
        break;
      }
    }
    points = static_cast<int>(keyframes.back().points.size());
  }
  state.SetItemsProcessed(state.iterations() * kTimedKeyframes);
  state.counters["points_per_keyframe"] = points;
  state.counters["ms_per_keyframe"] =
      benchmark::Counter(kTimedKeyframes * 1e-3,
                         benchmark::Counter::kIsIterationInvariantRate |
                             benchmark::Counter::kInvert);
  state.SetLabel(MethodName(options.method));
}
BENCHMARK(BM_BackendWindowedSolvePerKeyframe)
    ->Arg(static_cast<int>(Method::kSymba))
    ->Arg(static_cast<int>(Method::kMultiHypothesis))
    ->Arg(static_cast<int>(Method::kSingleHypothesis))
    ->ArgName("method")
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);

}  // namespace
}  // namespace symba
