// The colour camera (render/camera_render.h) on one core: a 780x580 frame of the golden scene's
// ten robots and ball (tests/data/golden/ssl-frame.toml, its camera seeing a wider image), as
// frames per second (items_per_second). BM_Scene: geometry, distortion and blur (RenderScene);
// BM_Sensor: exposure, RGGB noise, demosaicing and UYVY on an already rendered frame;
// BM_CameraFrame: both; BM_CameraWindow: a 64x64 window around one robot (what patlab camtrack
// renders per frame).
#include <benchmark/benchmark.h>

#include <string>

#include "patlab/formats/scene_file.h"
#include "patlab/render/camera_render.h"

namespace {

using namespace patlab;

const patlab::formats::SceneFile& Scene() {
  static const patlab::formats::SceneFile file = [] {
    patlab::formats::SceneFile f = patlab::formats::LoadSceneFile(
        std::string(PATLAB_SOURCE_DIR) + "/tests/data/golden/ssl-frame.toml");
    f.scene.options.width_px = 780;
    f.scene.options.height_px = 580;
    return f;
  }();
  return file;
}

void BM_Scene(benchmark::State& state) {
  patlab::render::FieldScene scene = Scene().scene;
  scene.options.noise_sigma_levels = 0.0;
  for (auto _ : state)
    benchmark::DoNotOptimize(
        patlab::render::RenderScene(scene, Scene().calibration.camera).data.data());
  state.SetItemsProcessed(state.iterations());
}

void BM_Sensor(benchmark::State& state) {
  patlab::render::FieldScene scene = Scene().scene;
  scene.options.noise_sigma_levels = 0.0;
  const patlab::camera::Image radiance =
      patlab::render::RenderScene(scene, Scene().calibration.camera);
  uint64_t frame = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        patlab::render::SimulateSensor(radiance, patlab::render::CameraSensorOptions{}, frame++)
            .data.data());
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_CameraFrame(benchmark::State& state) {
  uint64_t frame = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        patlab::render::RenderCameraFrame(Scene().scene, Scene().calibration.camera,
                                          patlab::render::CameraSensorOptions{}, frame++)
            .data.data());
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_CameraWindow(benchmark::State& state) {
  uint64_t frame = 0;
  const patlab::render::PixelWindow window{100, 60, 64, 64};  // the golden scene's first robot
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        patlab::render::RenderCameraWindow(Scene().scene, Scene().calibration.camera,
                                           patlab::render::CameraSensorOptions{}, frame++, window)
            .data.data());
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_Scene)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Sensor)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CameraFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CameraWindow)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
