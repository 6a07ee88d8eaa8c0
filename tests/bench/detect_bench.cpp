// Detection speed: full detection of a 10-robot SSL frame (5 per team, distinct IDs, a ball)
// with 20 false blobs, on one core. Target: >= 50,000 frames/s.
//
//   build/bench/detect_bench --benchmark_min_time=2
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "patlab/detect/detector.h"
#include "patlab/sim/scene.h"

namespace patlab::detect {
namespace {

// The SSL standard pattern (frames/README.md), built in code so the benchmark needs no files.
Pattern SslPattern() {
  Pattern p;
  p.name = "ssl-standard";
  p.patches = {{Vec2(0, 0), 25.0, PatchRole::kKey, ""},
               {Vec2(35, 54.772), 20.0, PatchRole::kId, ""},
               {Vec2(35, -54.772), 20.0, PatchRole::kId, ""},
               {Vec2(-54.772, 35), 20.0, PatchRole::kId, ""},
               {Vec2(-54.772, -35), 20.0, PatchRole::kId, ""}};
  p.key_index = 0;
  p.orientation_pairs = DefaultOrientationPairs(p.patches, 0);
  return p;
}

DetectorConfig SslConfig(estimate::Estimator estimator) {
  DetectorConfig config;
  config.palette = {"blue", "yellow", "pink", "green", "orange", "cyan", "red", "white"};
  config.options.estimator = estimator;
  DetectorPattern dp;
  dp.pattern = SslPattern();
  dp.codebook = GenerateCodebook(dp.pattern, FindSymmetry(dp.pattern, 10.0), {"pink", "green"});
  dp.key_colours = {"blue", "yellow"};
  config.patterns.push_back(dp);
  return config;
}

// Frames of 10 robots + ball with exactly 20 false blobs each (uniform over the field, uniform
// palette colour, radius 10-30 mm), patch noise 0.5 mm.
std::vector<sim::Scene> MakeFrames(const Detector& detector, int count) {
  std::vector<sim::Scene> frames;
  sim::SceneOptions options;
  for (int f = 0; f < count; ++f) {
    RandomStream rng(2003, 4, f);
    sim::Scene scene = sim::GenerateScene(detector, options, sim::PatchNoise{0.5, {}}, rng);
    for (int i = 0; i < 20; ++i) {
      const double r = rng.Uniform(10.0, 30.0);
      scene.blobs.push_back({Vec2(rng.Uniform(-3025, 3025), rng.Uniform(-2025, 2025)),
                             static_cast<int>(rng.Below(8)), std::numbers::pi * r * r});
    }
    frames.push_back(std::move(scene));
  }
  return frames;
}

// `cycle` frames in turn: 256 (the frames' blobs come from memory, the branch predictor meets new
// data), or 8 (fast_warm: caches and branch history warm; the difference is what a loaded
// machine's memory and mispredictions cost).
void BM_DetectFrame(benchmark::State& state, estimate::Estimator estimator, size_t cycle = 256) {
  Detector detector(SslConfig(estimator));
  const std::vector<sim::Scene> frames = MakeFrames(detector, 256);
  std::vector<Detection> detections;
  size_t f = 0;
  long found = 0, blobs = 0;
  for (auto _ : state) {
    const sim::Scene& scene = frames[f++ % cycle];
    detector.Detect(scene.blobs, &detections);
    benchmark::DoNotOptimize(detections.data());
    found += static_cast<long>(detections.size());
    blobs += static_cast<long>(scene.blobs.size());
  }
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["detections/frame"] =
      static_cast<double>(found) / static_cast<double>(state.iterations());
  state.counters["blobs/frame"] =
      static_cast<double>(blobs) / static_cast<double>(state.iterations());
  // The stage counters over the 256 frames (untimed), per frame: where the work is.
  DetectStats total;
  for (const sim::Scene& scene : frames) {
    DetectStats one;
    detector.Detect(scene.blobs, &detections, &one);
    total += one;
  }
  state.counters["keys/frame"] = static_cast<double>(total.key_candidates) / 256.0;
  state.counters["neighbours/frame"] = static_cast<double>(total.neighbours) / 256.0;
  state.counters["rotations/frame"] = static_cast<double>(total.correspondences) / 256.0;
}
BENCHMARK_CAPTURE(BM_DetectFrame, fast, estimate::Estimator::kFast);
BENCHMARK_CAPTURE(BM_DetectFrame, ml, estimate::Estimator::kMl);
BENCHMARK_CAPTURE(BM_DetectFrame, fast_warm, estimate::Estimator::kFast, 8);

// Scene generation alone, for scale.
void BM_GenerateScene(benchmark::State& state) {
  Detector detector(SslConfig(estimate::Estimator::kFast));
  sim::SceneOptions options;
  options.false_blob_rate_per_m2 = 20.0 / (6.05 * 4.05);
  uint64_t frame = 0;
  for (auto _ : state) {
    RandomStream rng(1, 0, frame++);
    sim::Scene scene = sim::GenerateScene(detector, options, sim::PatchNoise{0.5, {}}, rng);
    benchmark::DoNotOptimize(scene.blobs.data());
  }
  state.counters["frames/s"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_GenerateScene);

}  // namespace
}  // namespace patlab::detect

BENCHMARK_MAIN();
