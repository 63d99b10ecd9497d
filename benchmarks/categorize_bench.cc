// Microbenchmarks of Categorize() on one generated detection with N = 30
// hypotheses, 5 degrees of rotation noise and 10 % outliers (the issue's
// target cell). The result struct is reused across iterations, as a caller
// categorizing a stream of detections would.
#include <benchmark/benchmark.h>

#include "symba/categorization/categorize.h"
#include "symba/categorization/circular_dbscan.h"
#include "test_support/hypothesis_generator.h"

namespace symba {
namespace {

using testing::HypothesisSetSpec;

void Categorization(benchmark::State& state, SymmetryType type, int order) {
  HypothesisSetSpec spec;
  spec.type = type;
  spec.order = order;
  spec.rotation_sigma = 5.0 * testing::kDegree;
  spec.outlier_fraction = 0.1;
  spec.num_hypotheses = 30;
  testing::TestRandom random(3);
  // Cycle through a few detections so that no single lucky input is timed.
  std::vector<testing::GeneratedDetection> detections;
  for (int i = 0; i < 16; ++i) {
    detections.push_back(testing::GenerateDetection(spec, &random));
  }
  const CategorizationOptions options;
  CategorizedDetection out;
  size_t i = 0;
  for (auto _ : state) {
    const Status status = Categorize(
        detections[i++ % detections.size()].hypotheses, options, nullptr, &out);
    benchmark::DoNotOptimize(status.ok());
    benchmark::DoNotOptimize(out.type);
  }
}

void BM_CategorizeAsymmetric(benchmark::State& state) {
  Categorization(state, SymmetryType::kAsymmetric, 1);
}
BENCHMARK(BM_CategorizeAsymmetric);

void BM_CategorizeDiscreteC2(benchmark::State& state) {
  Categorization(state, SymmetryType::kDiscrete, 2);
}
BENCHMARK(BM_CategorizeDiscreteC2);

void BM_CategorizeDiscreteC6(benchmark::State& state) {
  Categorization(state, SymmetryType::kDiscrete, 6);
}
BENCHMARK(BM_CategorizeDiscreteC6);

void BM_CategorizeContinuous(benchmark::State& state) {
  Categorization(state, SymmetryType::kContinuous, 1);
}
BENCHMARK(BM_CategorizeContinuous);

void BM_CircularDbscan30(benchmark::State& state) {
  testing::TestRandom random(5);
  std::vector<double> angles;
  for (int i = 0; i < 30; ++i) {
    angles.push_back(random.Uniform(-kPi, kPi));
  }
  CircularDbscanOptions options;
  options.eps = 12.0 * testing::kDegree;
  CircularDbscanResult result;
  for (auto _ : state) {
    const Status status = CircularDbscan(angles, options, &result);
    benchmark::DoNotOptimize(status.ok());
    benchmark::DoNotOptimize(result.clusters.size());
  }
}
BENCHMARK(BM_CircularDbscan30);

}  // namespace
}  // namespace symba
