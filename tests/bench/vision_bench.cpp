// Our vision stages on a rendered 780x580 field (Google Benchmark). The OpenCV comparison is
// build-*/bench/vision_opencv_bench (tests/bench, built when OpenCV is installed).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/render.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/pipeline.h"
#include "patlab/vision/segment.h"

namespace {

using namespace patlab;
using namespace patlab::vision;

patlab::camera::Image Field(int width, int height) {
  std::vector<patlab::render::Disc> discs;
  for (int i = 0; i < 10; ++i) {
    const Vec2 c(width * (0.1 + 0.08 * i), height * (0.2 + 0.06 * ((i * 7) % 10)));
    discs.push_back({c, 18, {20, 20, 25}});
    discs.push_back({c, 5, {50, 75, 160}});
    for (int k = 0; k < 4; ++k)
      discs.push_back({c + 13.0 * Vec2(std::cos(1.6 * k), std::sin(1.6 * k)), 4, {248, 140, 135}});
  }
  return patlab::render::RenderDiscs(width, height, {40, 66, 21}, discs, 4);
}

const Thresholds& Classes() {
  static const Thresholds t = patlab::formats::ParseCmvisionColors(
      "[Colors]\n(255,128,0) 0.5 1 orange\n(255,255,0) 0.6 5 yellow\n(0,0,255) 0.6 5 blue\n"
      "(255,0,255) 0.6 10 pink\n(0,255,128) 0.6 10 green\n[Thresholds]\n"
      "(60:160,60:115,160:200)\n(100:255,0:95,135:175)\n(30:160,150:255,60:125)\n"
      "(150:255,90:135,165:255)\n(70:180,105:150,0:100)\n",
      "bench");
  return t;
}

void BM_Stages2To4(benchmark::State& state) {
  const patlab::camera::Image frame =
      state.range(2) ? patlab::camera::ToUyvy(Field(static_cast<int>(state.range(0)),
                                                    static_cast<int>(state.range(1))))
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

// Decoded pixels to detections (stages 2-6, as patlab detect runs them per frame) on the shared
// real frames with the settings of tests/data/vision; skipped when ../shared/frames is absent.
// Arg 0: ssl-field-2008.jpg (780x580 RGB, 7 YUV classes); 1: the same frame as UYVY;
// 2: vss-test-frame.png (765x613 RGB).
void BM_RealFrameStages2To6(benchmark::State& state) {
  const std::string frames = std::string(PATLAB_SOURCE_DIR) + "/../shared/frames/";
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  if (!std::filesystem::exists(frames)) {
    state.SkipWithError("no ../shared/frames");
    return;
  }
  const bool vss = state.range(0) == 2;
  VisionPipeline pipeline(
      patlab::formats::LoadThresholds(data + (vss ? "vss.colors.txt" : "ssl-2008.thresholds.toml")),
      patlab::formats::LoadCalibration(
          data + (vss ? "vss.calibration.toml" : "ssl-2008.calibration.toml")),
      SegmenterOptions{});
  detect::Detector detector(
      formats::LoadDetectorSettings(data + (vss ? "vss.detector.toml" : "ssl-2008.detector.toml")));
  std::vector<int> palette_label;
  for (const ColorClass& c : pipeline.thresholds().classes)
    palette_label.push_back(detector.ColourLabel(c.name));
  patlab::camera::Image image =
      ReadFrame(frames + (vss ? "vss-test-frame.png" : "ssl-field-2008.jpg"));
  if (state.range(0) == 1) image = patlab::camera::ToUyvy(image);
  std::vector<detect::Blob> blobs, palette_blobs;
  std::vector<detect::Detection> detections;
  for (auto _ : state) {
    pipeline.Process(image, &blobs);
    palette_blobs.clear();
    for (const detect::Blob& b : blobs) {
      const int label = palette_label[static_cast<size_t>(b.colour)];
      if (label >= 0) palette_blobs.push_back(detect::Blob{b.position_mm, label, b.area_mm2});
    }
    detector.Detect(palette_blobs, &detections);
    benchmark::DoNotOptimize(detections.data());
  }
  state.counters["blobs"] = static_cast<double>(blobs.size());
  state.counters["detections"] = static_cast<double>(detections.size());
}
BENCHMARK(BM_RealFrameStages2To6)
    ->ArgName("frame")
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
