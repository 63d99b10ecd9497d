// Microbenchmarks of the SE(3) primitives every cost function is built from.
#include <benchmark/benchmark.h>

#include "symba/geometry/se3.h"
#include "test_support/random.h"

namespace symba {
namespace {

void BM_LogSE3(benchmark::State& state) {
  testing::TestRandom random(7);
  const Rigid3d T(random.Rotation(), random.NormalVector(1.0));
  for (auto _ : state) {
    benchmark::DoNotOptimize(LogSE3(T));
  }
}
BENCHMARK(BM_LogSE3);

void BM_ExpSE3(benchmark::State& state) {
  testing::TestRandom random(7);
  Vector6<double> xi;
  xi << random.NormalVector(1.0), random.NormalVector(0.5);
  for (auto _ : state) {
    benchmark::DoNotOptimize(ExpSE3(xi));
  }
}
BENCHMARK(BM_ExpSE3);

}  // namespace
}  // namespace symba
