// Our vision stages on a rendered 780x580 field (Google Benchmark). The OpenCV comparison is
// build-*/bench/vision_opencv_bench (src/vision/bench, built when OpenCV is installed).
#include <benchmark/benchmark.h>

#include "vision/render.h"
#include "vision/segment.h"

namespace {

using namespace patlab;
using namespace patlab::vision;

Image Field(int width, int height) {
  std::vector<Disc> discs;
  for (int i = 0; i < 10; ++i) {
    const Vec2 c(width * (0.1 + 0.08 * i), height * (0.2 + 0.06 * ((i * 7) % 10)));
    discs.push_back({c, 18, {20, 20, 25}});
    discs.push_back({c, 5, {50, 75, 160}});
    for (int k = 0; k < 4; ++k)
      discs.push_back({c + 13.0 * Vec2(std::cos(1.6 * k), std::sin(1.6 * k)), 4, {248, 140, 135}});
  }
  return RenderDiscs(width, height, {40, 66, 21}, discs, 4);
}

const Thresholds& Classes() {
  static const Thresholds t = ParseCmvisionColors(
      "[Colors]\n(255,128,0) 0.5 1 orange\n(255,255,0) 0.6 5 yellow\n(0,0,255) 0.6 5 blue\n"
      "(255,0,255) 0.6 10 pink\n(0,255,128) 0.6 10 green\n[Thresholds]\n"
      "(60:160,60:115,160:200)\n(100:255,0:95,135:175)\n(30:160,150:255,60:125)\n"
      "(150:255,90:135,165:255)\n(70:180,105:150,0:100)\n",
      "bench");
  return t;
}

void BM_Stages2To4(benchmark::State& state) {
  const Image frame =
      state.range(2)
          ? ToUyvy(Field(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))))
          : Field(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  Segmenter segmenter(Classes(), SegmenterOptions{});
  for (auto _ : state) {
    segmenter.Process(frame);
    benchmark::DoNotOptimize(segmenter.regions().data());
  }
  state.counters["regions"] = static_cast<double>(segmenter.regions().size());
  state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(1));
}
BENCHMARK(BM_Stages2To4)
    ->ArgNames({"w", "h", "uyvy"})
    ->Args({640, 480, 0})
    ->Args({780, 580, 0})
    ->Args({780, 580, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
