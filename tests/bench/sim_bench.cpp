// Monte-Carlo kernel throughput (noise generation included), the numbers docs/performance.md
// reports:
//   build/bench/sim_bench --benchmark_filter=Kernel
// items_per_second is trials per second over all threads (real time).
#include <benchmark/benchmark.h>

#include <vector>

#include "patlab/formats/pattern_file.h"
#include "patlab/sim/batch.h"

namespace {

using patlab::sim::BatchOutput;
using patlab::sim::kBatchSize;
using patlab::sim::PointSetup;
namespace estimate = patlab::estimate;

const estimate::Model& Butterfly() {
  static const estimate::Model model = estimate::Model::FromPattern(
      patlab::formats::LoadPatternFile(PATLAB_SOURCE_DIR "/patterns/butterfly.toml"));
  return model;
}

void Kernel(benchmark::State& state, std::vector<estimate::Estimator> estimators) {
  PointSetup setup;
  setup.model = &Butterfly();
  setup.sigma_mm = 1.0;
  setup.field_length_mm = 2800.0;
  setup.field_width_mm = 2300.0;
  setup.seed = 7;
  for (auto e : estimators) setup.run[static_cast<int>(e)] = true;
  std::vector<double> buffers[4][3];
  std::vector<uint8_t> iterations(kBatchSize), termination(kBatchSize);
  BatchOutput out;
  for (auto e : estimators) {
    auto& b = buffers[static_cast<int>(e)];
    for (auto& v : b) v.resize(kBatchSize);
    out.errors[static_cast<int>(e)] = {b[0].data(), b[1].data(), b[2].data()};
  }
  out.ml_iterations = iterations.data();
  out.ml_termination = termination.data();
  uint64_t first = static_cast<uint64_t>(state.thread_index()) << 40;
  for (auto _ : state) {
    patlab::sim::RunBatch(setup, first, kBatchSize, out);
    first += kBatchSize;
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kBatchSize);
}

// The floor: true poses and noisy patch positions only (Philox, Box-Muller, the rigid motion),
// no estimator.
BENCHMARK_CAPTURE(Kernel, butterfly_inputs_only, {})->Threads(1)->Threads(2)->UseRealTime();
BENCHMARK_CAPTURE(Kernel, butterfly_fast, {estimate::Estimator::kFast})
    ->Threads(1)
    ->Threads(2)
    ->UseRealTime();
BENCHMARK_CAPTURE(Kernel, butterfly_ml, {estimate::Estimator::kMl})
    ->Threads(1)
    ->Threads(2)
    ->UseRealTime();
BENCHMARK_CAPTURE(Kernel, butterfly_fast_and_ml,
                  {estimate::Estimator::kFast, estimate::Estimator::kMl})
    ->Threads(1)
    ->Threads(2)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
