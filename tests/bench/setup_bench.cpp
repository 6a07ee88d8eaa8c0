// Setup speed: formats::SetupCamera (`patlab setup`) on one frame, in CPU seconds per frame.
// Target: <= 10 s on one core (docs/setup.md). Setup runs on the calling thread alone (no TBB;
// Ceres with num_threads = 1), so the CPU time is one core's.
//
//   build/bench/setup_bench
//
// Two frames:
//   real:     ../shared/frames/ssl-field-2008.jpg (skipped when absent) with the settings of
//             tests/data/vision/ssl-2008-sheet.detector.toml and the `ssl` family, as
//             tests/cli/setup_real_cli_test.cpp sets it up.
//   rendered: seed 58 of scripts/setup_rendered.py -- a camera 3.3 m up over ssl-2015 whose lines
//             leave four cameras open, each fitted, its colours fitted and its height scanned --
//             rendered here through the colour camera's sensor at that seed's exposure and noise,
//             with the shipped ssl-frame.detector settings and the `ssl` family.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "patlab/camera/camera.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/scene_file.h"
#include "patlab/render/camera_render.h"
#include "patlab/vision/frame_io.h"

namespace patlab::formats {
namespace {

const std::string kSource = PATLAB_SOURCE_DIR;

SetupOptions SslFamily(const std::string& settings_path) {
  SetupOptions o;
  o.fields = FieldFamily("ssl", {kSource});
  o.settings_path = settings_path;
  return o;
}

// Seed 58's scene (its camera.toml and scene.toml as the script writes them, but the ball).
SceneFile Seed58Scene(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const std::string camera = R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 620.773377
fy_px = 620.773377
cx_px = 388.258600
cy_px = 287.504088
k1 = -0.053985
rotation_rodrigues = [-1.781230243, 2.570248600, -0.008345282]
translation_mm = [768.181397, -2561.128992, 3283.150133]
[heights]
default_mm = 140.0
)";
  FILE* f = std::fopen((dir / "camera.toml").c_str(), "w");
  std::fputs(camera.c_str(), f);
  std::fclose(f);
  std::string scene = "calibration = \"camera.toml\"\nfield = \"" + kSource +
                      "/experiments/fields/ssl-2015.toml\"\npattern = \"" + kSource +
                      "/patterns/ssl-standard.toml\"\ncodebook = \"" + kSource +
                      "/patterns/ssl-standard.codebook.toml\"\n" + R"([render]
robot_height_mm = 140.0
[colours]
field = [42, 99, 43]
body = [27, 25, 25]
blue = [31, 63, 156]
yellow = [209, 182, 33]
pink = [214, 80, 137]
green = [62, 182, 70]
orange = [222, 106, 19]
)";
  struct Robot {
    const char* team;
    int id;
    double x, y, theta;
  };
  const Robot robots[] = {
      {"blue", 4, -2472.3, 210.5, -1.5025},  {"yellow", 14, -3183.6, 1804.4, 2.4167},
      {"blue", 5, -1442.5, 1522.3, 0.1683},  {"yellow", 5, -954.1, 2538.4, 2.1574},
      {"blue", 0, -1679.6, 2604.0, -2.9129}, {"yellow", 1, -1728.1, 1826.9, -2.2775},
      {"blue", 11, -1744.0, 2232.2, 2.6746}};
  for (const Robot& r : robots) {
    scene += "[[robot]]\nteam = \"" + std::string(r.team) + "\"\nid = " + std::to_string(r.id) +
             "\nx_mm = " + std::to_string(r.x) + "\ny_mm = " + std::to_string(r.y) +
             "\ntheta_rad = " + std::to_string(r.theta) + "\n";
  }
  return ParseSceneFile(scene, "scene.toml", dir.string());
}

void Run(benchmark::State& state, const camera::Image& frame, const SetupOptions& options) {
  for (auto _ : state) {
    try {
      const SetupResult r = SetupCamera({&frame}, {"frame"}, options);
      // The cameras the lines left open, each set up in full (1: the lines decided).
      state.counters["cameras"] = static_cast<double>(std::max<size_t>(1, r.undecided.size()));
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
  }
}

void BM_SetupRealSsl2008(benchmark::State& state) {
  const std::string path = kSource + "/../shared/frames/ssl-field-2008.jpg";
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("no frame at " + path).c_str());
    return;
  }
  const camera::Image frame = vision::ReadFrame(path);
  Run(state, frame, SslFamily(kSource + "/tests/data/vision/ssl-2008-sheet.detector.toml"));
}

void BM_SetupRenderedSeed58(benchmark::State& state) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "patlab_setup_bench";
  const SceneFile scene = Seed58Scene(dir);
  render::CameraSensorOptions sensor;  // the script's --exposure-gain, --read-noise-levels
  sensor.exposure_gain = 1.16;
  sensor.read_noise_levels = 1.37;
  sensor.seed = 58;
  const camera::Image frame =
      camera::ToRgb(render::RenderCameraFrame(scene.scene, scene.calibration.camera, sensor, 0));
  std::filesystem::remove_all(dir);
  Run(state, frame, SslFamily(kSource + "/settings/ssl-frame.detector.toml"));
}

// CPU time is the measure (benchmark's "CPU" column, seconds per frame); a few iterations suffice.
BENCHMARK(BM_SetupRealSsl2008)->Unit(benchmark::kSecond)->Iterations(3);
BENCHMARK(BM_SetupRenderedSeed58)->Unit(benchmark::kSecond)->Iterations(3);

}  // namespace
}  // namespace patlab::formats

BENCHMARK_MAIN();
