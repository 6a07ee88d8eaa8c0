#include "patlab/formats/scene_file.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/formats/toml_values_internal.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

namespace {

namespace fs = std::filesystem;

// A table of the root, or an empty one when absent; InputError when the key is not a table.
const toml::table& OptionalTable(const io::TomlReader& root, std::string_view key) {
  static const toml::table kEmpty;
  const toml::node* node = root.table().get(key);
  if (node == nullptr) return kEmpty;
  if (!node->is_table()) {
    root.Fail(key, std::string(key) + " is " + io::TypeName(*node) + "; expected a table");
  }
  return *node->as_table();
}

render::Rgb ReadRgb(const io::TomlReader& r, std::string_view key) {
  const toml::node* node = r.table().get(key);
  const toml::array* a = node->as_array();
  render::Rgb rgb{};
  bool ok = a != nullptr && a->size() == 3;
  for (size_t k = 0; ok && k < 3; ++k) {
    const auto* v = (*a)[k].as_integer();
    ok = v != nullptr && v->get() >= 0 && v->get() <= 255;
    if (ok) rgb[k] = static_cast<uint8_t>(v->get());
  }
  if (!ok) r.Fail(key, r.Describe(key) + " is not [R, G, B]; expected three integers in 0..255");
  return rgb;
}

void ReadRenderOptions(const io::TomlReader& r, render::RenderOptions* o) {
  r.CheckKeys({"supersampling", "robot_height_mm", "robot_radius_mm", "ball_radius_mm",
               "blur_sigma_px", "noise_sigma_levels", "seed"});
  const auto clamp_int = [](int64_t v) {
    return static_cast<int>(std::clamp<int64_t>(v, -1000000, 1000000));
  };
  if (auto v = r.OptionalInteger("supersampling")) o->supersampling = clamp_int(*v);
  o->robot_height_mm = r.OptionalNumber("robot_height_mm").value_or(o->robot_height_mm);
  o->robot_radius_mm = r.OptionalNumber("robot_radius_mm").value_or(o->robot_radius_mm);
  o->ball_radius_mm = r.OptionalNumber("ball_radius_mm").value_or(o->ball_radius_mm);
  o->blur_sigma_px = r.OptionalNumber("blur_sigma_px").value_or(o->blur_sigma_px);
  o->noise_sigma_levels = r.OptionalNumber("noise_sigma_levels").value_or(o->noise_sigma_levels);
  if (auto v = r.OptionalInteger("seed")) {
    if (*v < 0) r.Fail("seed", "seed is " + std::to_string(*v) + "; expected an integer >= 0");
    o->seed = static_cast<uint64_t>(*v);
  }
  const std::vector<OptionsProblem> problems = Check(*o);
  if (!problems.empty()) r.Fail(problems.front().field, problems.front().message);
}

// The path of the file that `key` names, relative to the scene's folder; InputError at the key's
// line when it cannot be read (the loaders would report the missing file without that line).
std::string ExistingFile(const io::TomlReader& top, std::string_view key,
                         const std::string& base_dir) {
  const std::string path = internal::ResolveBeside(base_dir, top.String(key));
  if (!std::ifstream(path)) {
    top.Fail(key,
             std::string(key) + " file \"" + path + "\" cannot be read; expected a readable file");
  }
  return path;
}

// The calibration the scene names: a pinhole camera with an image size.
camera::Calibration ReadCalibration(const io::TomlReader& top, const std::string& base_dir) {
  camera::Calibration calibration = LoadCalibration(ExistingFile(top, "calibration", base_dir));
  if (!calibration.camera.is_pinhole()) {
    top.Fail("calibration", "calibration " + calibration.source +
                                " is a homography; expected a pinhole camera to render with");
  }
  if (calibration.image_width_px == 0) {
    top.Fail("calibration", "calibration " + calibration.source +
                                " has no image_size_px; expected the size of the frame to render");
  }
  return calibration;
}

// A robot whose top the camera cannot see (outside the frame, behind the camera, beyond the
// distortion's fold) would render as nothing: refused at its x_mm.
void CheckRobotInView(const io::TomlReader& r, const render::RobotPlacement& robot,
                      const camera::Calibration& calibration, const render::FieldScene& scene) {
  const auto& options = scene.options;
  const Vec2 at(robot.pose.x_mm, robot.pose.y_mm);
  std::optional<Vec2> pixel;
  if (calibration.camera.SupportsHeight(options.robot_height_mm)) {
    pixel = calibration.camera.WorldToPixel(at, options.robot_height_mm);
  }
  if (pixel && pixel->x() >= 0 && pixel->y() >= 0 && pixel->x() <= options.width_px &&
      pixel->y() <= options.height_px) {
    return;
  }
  std::string message =
      "robot at (" + FormatNumber(robot.pose.x_mm) + ", " + FormatNumber(robot.pose.y_mm) + ") mm";
  message.append(" is outside the field the camera sees (")
      .append(pixel ? "pixel (" + std::to_string(std::lround(pixel->x())) + ", " +
                          std::to_string(std::lround(pixel->y())) + ")"
                    : std::string("not in front of the camera"))
      .append(", the frame is " + std::to_string(options.width_px) + "x" +
              std::to_string(options.height_px) + ")")
      .append("; expected a robot whose centre is inside the rendered frame");
  r.Fail("x_mm", message);
}

render::RobotPlacement ReadRobot(const io::TomlReader& r, const render::FieldScene& scene) {
  r.CheckKeys({"team", "id", "x_mm", "y_mm", "theta_rad"});
  render::RobotPlacement robot;
  robot.team = r.String("team");
  const std::optional<int64_t> id = r.OptionalInteger("id");
  if (!id) r.Fail("id", "missing " + r.Describe("id") + "; expected an integer");
  robot.id = static_cast<int>(std::clamp<int64_t>(*id, -1, 1 << 30));
  robot.pose = {r.Number("x_mm"), r.Number("y_mm"), r.Number("theta_rad")};
  if (scene.colours.count(robot.team) == 0) {
    r.Fail("team",
           "team \"" + robot.team + "\" has no RGB in [colours]; expected a colour listed there");
  }
  std::vector<std::string> names;
  try {
    names = render::PatchColours(scene.pattern, scene.codebook, robot.team, robot.id);
  } catch (const InputError& e) {
    r.Fail("id", e.what());
  }
  for (const std::string& name : names) {
    if (scene.colours.count(name) == 0) {
      r.Fail("id",
             "ID colour \"" + name + "\" has no RGB in [colours]; expected a colour listed there");
    }
  }
  return robot;
}

void ReadBall(const io::TomlReader& r, render::FieldScene* scene) {
  r.CheckKeys({"x_mm", "y_mm", "colour"});
  scene->ball_mm = Vec2(r.Number("x_mm"), r.Number("y_mm"));
  scene->ball_colour = r.OptionalString("colour").value_or(scene->ball_colour);
  if (scene->colours.count(scene->ball_colour) == 0) {
    r.Fail(r.Has("colour") ? "colour" : "x_mm",
           "ball colour \"" + scene->ball_colour +
               "\" has no RGB in [colours]; expected a colour listed there");
  }
}

void ReadColours(const io::TomlReader& top, render::FieldScene* scene) {
  if (!top.Has("colours"))
    top.Fail("colours", "missing [colours]; expected name = [R, G, B] per colour");
  const io::TomlReader r(OptionalTable(top, "colours"), top.file(), "[colours]");
  for (const auto& [key, node] : r.table())
    scene->colours[std::string(key.str())] = ReadRgb(r, key.str());
  for (const char* required : {"field", "body"}) {
    if (scene->colours.count(required) == 0) {
      r.Fail(required, "[colours] has no \"" + std::string(required) +
                           "\"; expected the RGB of the field and of the robots' top covers");
    }
  }
}

}  // namespace

SceneFile ParseSceneFile(std::string_view text, const std::string& source_name,
                         const std::string& base_dir) {
  const toml::table root = io::ParseTomlText(text, source_name);
  const io::TomlReader top(root, source_name);
  top.CheckKeys(
      {"calibration", "pattern", "codebook", "field", "render", "colours", "robot", "ball"});
  SceneFile file;
  file.calibration = ReadCalibration(top, base_dir);
  render::FieldScene& scene = file.scene;
  scene.options.width_px = file.calibration.image_width_px;
  scene.options.height_px = file.calibration.image_height_px;
  ReadRenderOptions(io::TomlReader(OptionalTable(top, "render"), source_name, "[render]"),
                    &scene.options);
  // The pattern and its codebook, checked against each other as the detector settings do.
  detect::DetectorPattern worn =
      formats::MakeDetectorPattern(formats::LoadPatternFile(ExistingFile(top, "pattern", base_dir)),
                                   {}, ExistingFile(top, "codebook", base_dir), {});
  scene.pattern = std::move(worn.pattern);
  scene.codebook = std::move(worn.codebook);
  ReadColours(top, &scene);
  if (root.contains("field"))
    scene.field = formats::LoadField(ExistingFile(top, "field", base_dir));
  if (const toml::node* robots = root.get("robot")) {
    const toml::array* list = robots->as_array();
    if (list == nullptr || !list->is_array_of_tables()) {
      top.Fail("robot", "robot is " + io::TypeName(*robots) + "; expected [[robot]] tables");
    }
    for (size_t i = 0; i < list->size(); ++i) {
      const io::TomlReader r(*list->get(i)->as_table(), source_name,
                             "[[robot]] " + std::to_string(i + 1));
      scene.robots.push_back(ReadRobot(r, scene));
      CheckRobotInView(r, scene.robots.back(), file.calibration, scene);
    }
  }
  if (top.Has("ball")) {
    ReadBall(io::TomlReader(OptionalTable(top, "ball"), source_name, "[ball]"), &scene);
  }
  return file;
}

SceneFile LoadSceneFile(const std::string& path) {
  return ParseSceneFile(io::ReadTextFile(path, "scene TOML file"), path,
                        fs::path(path).parent_path().string());
}

}  // namespace patlab::formats
