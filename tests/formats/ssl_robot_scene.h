// Rendered SSL scenes for the tests of patlab setup (camera_setup_test.cpp,
// camera_setup_refusal_test.cpp, camera_setup_colours_test.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "../test_util.h"
#include "patlab/camera/camera.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/scene_file.h"
#include "patlab/render/camera_render.h"

namespace patlab::formats {

// A rendered scene of SSL standard-pattern robots 140 mm high on `model`'s field, seen through
// `camera_toml` (written into `dir`), in the scene's `colours` (a [colours] table's lines).
struct SceneRobot {
  const char* team;
  int id;
  double x, y, theta;
};
inline SceneFile SslRobotScene(const testing::TempDir& dir, const char* camera_toml,
                               const char* model, const char* colours,
                               const std::vector<SceneRobot>& robots) {
  dir.Write("camera.toml", camera_toml);
  std::string text = std::string(R"(calibration = "camera.toml"
field = ")" PATLAB_SOURCE_DIR "/experiments/fields/") +
                     model + R"(.toml"
pattern = ")" PATLAB_SOURCE_DIR R"(/patterns/ssl-standard.toml"
codebook = ")" PATLAB_SOURCE_DIR R"(/patterns/ssl-standard.codebook.toml"
[render]
robot_height_mm = 140.0
[colours]
)" + colours;
  for (const auto& b : robots) {
    text += "[[robot]]\nteam = \"" + std::string(b.team) + "\"\nid = " + std::to_string(b.id) +
            "\nx_mm = " + std::to_string(b.x) + "\ny_mm = " + std::to_string(b.y) +
            "\ntheta_rad = " + std::to_string(b.theta) + "\n";
  }
  return ParseSceneFile(text, "scene.toml", dir.Path());
}

// Setup's options for the shipped SSL settings and these field models of experiments/fields.
inline SetupOptions SslModels(std::initializer_list<const char*> models) {
  SetupOptions o;
  for (const char* model : models)
    o.fields.push_back(
        LoadField(PATLAB_SOURCE_DIR "/experiments/fields/" + std::string(model) + ".toml"));
  o.settings_path = PATLAB_SOURCE_DIR "/settings/ssl-frame.detector.toml";
  return o;
}

// How far (mm) the fitted camera maps the frame's centre from where the true one does, the field's
// half-turn symmetry allowed.
inline double FloorOffsetMm(const camera::CameraModel& truth, const camera::PinholeCamera& fitted) {
  const Vec2 centre(390.0, 290.0);
  const auto t = truth.PixelToWorld(centre, 0.0);
  const auto f = camera::CameraModel::Pinhole(fitted).PixelToWorld(centre, 0.0);
  if (!t || !f) return INFINITY;
  return std::min((*t - *f).norm(), (*t + *f).norm());
}

struct RenderedView {
  SceneFile scene;
  camera::Image frame;
};

// The scene rendered as scripts/setup_few_lines.py and scripts/setup_rendered.py render it: the
// colour camera's sensor, its noise seeded by the view (the seed), at the exposure and read noise
// the view drew (setup_few_lines.py keeps the sensor's defaults).
inline RenderedView RenderedAsTheScriptDoes(SceneFile scene, int view, double exposure_gain = 1.0,
                                            double read_noise_levels = 2.0) {
  render::CameraSensorOptions sensor;
  sensor.seed = static_cast<uint64_t>(view);
  sensor.exposure_gain = exposure_gain;
  sensor.read_noise_levels = read_noise_levels;
  camera::Image frame =
      camera::ToRgb(render::RenderCameraFrame(scene.scene, scene.calibration.camera, sensor, 0));
  return {std::move(scene), std::move(frame)};
}

}  // namespace patlab::formats
