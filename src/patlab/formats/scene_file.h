// Scene files: the robots, ball, colours and render options of one frame of render/scene_render.h,
// with the camera calibration they are seen through (patlab render, the golden frame).
#pragma once

#include <string>
#include <string_view>

#include "patlab/camera/camera.h"
#include "patlab/render/scene_render.h"

namespace patlab::formats {

// A scene file (format: docs/render.md, example tests/data/golden/ssl-frame.toml) with the
// calibration it names; the image size comes from the calibration's image_size_px.
struct SceneFile {
  render::FieldScene scene;
  camera::Calibration calibration;
};
// Reads a scene file; relative paths in it are relative to its folder. Throws InputError
// "file:line: what is wrong; expected what" for the first problem.
SceneFile LoadSceneFile(const std::string& path);
// The same from text; `source_name` stands for the file in messages, `base_dir` resolves paths.
SceneFile ParseSceneFile(std::string_view text, const std::string& source_name,
                         const std::string& base_dir);

}  // namespace patlab::formats
