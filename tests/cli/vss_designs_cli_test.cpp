// The shipped VSS designs on rendered frames: for each pattern of the family settings
// (settings/vss.detector.toml), a scene with every ID of both teams on a VSS field with its
// painted lines (experiments/fields/vss.toml), seen by a camera 2.6 m up (patlab render), detected
//  - with the shipped family settings by name (`-s vss.detector`), the scene's own camera and
//    thresholds boxed around the rendered colours (the known-calibration path), and
//  - through `patlab setup FRAME --field vss --settings <design>.detector` (calibration from the
//    lines, colour thresholds fitted, tolerances chosen) and `patlab detect --setup`.
// Every robot must come out once with its design, team and ID within 5 mm (10 mm through setup's
// fitted camera), and nothing else.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/formats/detector_settings.h"

namespace patlab::cli {
namespace {

using testing::kPatlab;
using testing::kSource;
using testing::RunCommand;

// RGB of the rendered colours; the thresholds are these +- 15 levels (as
// settings/ssl-frame.thresholds.toml), and no box holds another colour or a mixture of a patch
// colour with the body or the field.
const std::map<std::string, std::array<int, 3>> kColours = {
    {"blue", {35, 75, 210}},  {"yellow", {235, 215, 45}}, {"pink", {240, 95, 185}},
    {"green", {70, 215, 95}}, {"red", {220, 40, 40}},     {"cyan", {40, 220, 230}},
    {"teal", {20, 150, 110}}, {"purple", {140, 60, 200}}, {"orange", {250, 125, 25}}};

// A camera 2.6 m over the field (3.06 mm per px on the robot tops), 640 x 480 px: the whole VSS
// field in view.
constexpr const char* kCalibration = R"(model = "pinhole"
image_size_px = [640, 480]

[pinhole]
fx_px = 800.0
fy_px = 800.0
cx_px = 319.5
cy_px = 239.5
k1 = -0.05
k2 = 0.0
rotation_rodrigues = [-3.0706075205, -0.0420684613, -0.0521943790]
translation_mm = [-10.593924, 19.972848, 2600.0]

[heights]
default_mm = 140
)";

std::string Thresholds() {
  std::string text = "space = \"rgb\"\n";
  for (const auto& [name, rgb] : kColours) {
    text += "\n[[class]]\nname = \"" + name + "\"\ndisplay = [" + std::to_string(rgb[0]) + ", " +
            std::to_string(rgb[1]) + ", " + std::to_string(rgb[2]) + "]\n";
    const char* channel[] = {"r", "g", "b"};
    for (int c = 0; c < 3; ++c) {
      text += std::string(channel[c]) + " = [" + std::to_string(std::max(0, rgb[c] - 15)) + ", " +
              std::to_string(std::min(255, rgb[c] + 15)) + "]\n";
    }
  }
  return text;
}

struct Robot {
  std::string team;
  int id;
  double x_mm, y_mm, theta_rad;
};

std::string Scene(const std::string& design, const std::vector<Robot>& robots) {
  std::string text = "calibration = \"camera.toml\"\nfield = \"" + kSource +
                     "/experiments/fields/vss.toml\"\npattern = \"" + kSource + "/patterns/" +
                     design + ".toml\"\ncodebook = \"" + kSource + "/patterns/" + design +
                     ".codebook.toml\"\n\n[render]\nsupersampling = 4\nrobot_height_mm = 140.0\n"
                     "robot_radius_mm = 45.0\nblur_sigma_px = 0.7\nnoise_sigma_levels = 3.0\n"
                     "seed = 7\n\n[colours]\nfield = [40, 40, 45]\nbody = [30, 30, 34]\n"
                     "line = [235, 235, 235]\n";
  for (const auto& [name, rgb] : kColours) {
    text += name + " = [" + std::to_string(rgb[0]) + ", " + std::to_string(rgb[1]) + ", " +
            std::to_string(rgb[2]) + "]\n";
  }
  for (const Robot& r : robots) {
    std::ostringstream robot;
    robot << "\n[[robot]]\nteam = \"" << r.team << "\"\nid = " << r.id << "\nx_mm = " << r.x_mm
          << "\ny_mm = " << r.y_mm << "\ntheta_rad = " << r.theta_rad << "\n";
    text += robot.str();
  }
  return text;
}

// Every row of a detections CSV is one robot of the scene (design, team, ID, within tolerance_mm)
// and every robot is found.
void ExpectRobots(const std::string& csv, const std::string& design,
                  const std::vector<Robot>& robots, double tolerance_mm) {
  std::istringstream rows(csv);
  std::string line;
  std::getline(rows, line);  // header
  int found = 0;
  while (std::getline(rows, line)) {
    std::vector<std::string> cell;
    std::stringstream row(line);
    for (std::string c; std::getline(row, c, ',');) cell.push_back(c);
    ASSERT_EQ(cell.size(), 10u) << line;
    bool match = false;
    for (const Robot& r : robots) {
      match |= cell[1] == design && cell[2] == r.team && cell[3] == std::to_string(r.id) &&
               std::hypot(std::stod(cell[5]) - r.x_mm, std::stod(cell[6]) - r.y_mm) < tolerance_mm;
    }
    found += static_cast<int>(match);
    EXPECT_TRUE(match) << "not a robot of the scene: " << line;
  }
  EXPECT_EQ(found, static_cast<int>(robots.size())) << csv;
}

TEST(VssDesignsCli, EveryShippedDesignTeamAndIdOnRenderedFrames) {
  const detect::DetectorConfig family =
      formats::LoadDetectorSettings(kSource + "/settings/vss.detector.toml");
  ASSERT_EQ(family.patterns.size(), 4u);
  for (const detect::DetectorPattern& dp : family.patterns) {
    const std::string design = dp.pattern.name;
    SCOPED_TRACE(design);
    testing::TempDir dir;
    std::ofstream(dir.Path("camera.toml")) << kCalibration;
    std::ofstream(dir.Path("thresholds.toml")) << Thresholds();
    // Every ID of both teams on a 200 x 300 mm grid, turned a different way each.
    std::vector<Robot> robots;
    int slot = 0;
    for (const detect::CodebookEntry& e : dp.codebook.entries) {
      for (const char* team : {"blue", "yellow"}) {
        robots.push_back({team, e.id, -600.0 + 200.0 * (slot % 7), -450.0 + 300.0 * (slot / 7),
                          -3.0 + 0.37 * slot});
        ++slot;
      }
    }
    ASSERT_LE(slot, 21);
    std::ofstream(dir.Path("scene.toml")) << Scene(design, robots);
    const auto render =
        RunCommand(kPatlab + " render " + dir.Path("scene.toml") + " -o " + dir.Path("r"));
    ASSERT_EQ(render.exit_code, 0) << render.err;
    const auto known = RunCommand(kPatlab + " detect " + dir.Path("r") + "/frame.png -t " +
                                  dir.Path("thresholds.toml") + " -c " + dir.Path("camera.toml") +
                                  " -s vss.detector -q");
    ASSERT_EQ(known.exit_code, 0) << known.err;
    ExpectRobots(known.out, design, robots, 5.0);
    const auto setup = RunCommand(kPatlab + " setup " + dir.Path("r") + "/frame.png --field " +
                                  kSource + "/experiments/fields/vss.toml --settings " + design +
                                  ".detector -o " + dir.Path("cam"));
    ASSERT_EQ(setup.exit_code, 0) << setup.err << setup.out;
    const auto via_setup = RunCommand(kPatlab + " detect " + dir.Path("r") + "/frame.png --setup " +
                                      dir.Path("cam") + " -q");
    ASSERT_EQ(via_setup.exit_code, 0) << via_setup.err;
    ExpectRobots(via_setup.out, design, robots, 10.0);
  }
}

}  // namespace
}  // namespace patlab::cli
