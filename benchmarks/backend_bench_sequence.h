// The keyframes of the backend benchmark (issue 4's workload), shared by
// symba-microbench (backend_bench.cc) and symba-python-overhead-bench: the
// camera circles five objects (a 2-fold, a 4-fold, two round tables, a
// chair; radius 4 m, one keyframe every 7.5 degrees), every keyframe sees
// all five with 30 hypotheses each and up to 100 points of a wall of radius
// 6 m with depth. Deterministic (std::mt19937 seeded with 5).
#ifndef SYMBA_BENCHMARKS_BACKEND_BENCH_SEQUENCE_H_
#define SYMBA_BENCHMARKS_BACKEND_BENCH_SEQUENCE_H_

#include <vector>

#include "symba/backend/keyframe_input.h"
#include "symba/geometry/pinhole_intrinsics.h"

namespace symba {

// The first keyframes fill the window untimed; the next ones are timed.
inline constexpr int kBackendBenchWarmupKeyframes = 10;
inline constexpr int kBackendBenchTimedKeyframes = 30;

// kBackendBenchWarmupKeyframes + kBackendBenchTimedKeyframes keyframes and
// the camera's intrinsics.
std::vector<KeyframeInput> MakeBackendBenchSequence(
    PinholeIntrinsics* intrinsics);

}  // namespace symba

#endif  // SYMBA_BENCHMARKS_BACKEND_BENCH_SEQUENCE_H_
