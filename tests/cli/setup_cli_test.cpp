// patlab setup end to end: a frame rendered with a known camera (settings/ssl-half-field.toml,
// robots on an SSL 2009 field with its painted lines) -> setup -> detect --setup finds every
// robot with its team and ID and no other; the calibration maps the floor within 5 mm of the true
// camera. Bad input is exit 2 with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <sstream>
#include <string>

#include "../test_util.h"
#include "patlab/camera/camera.h"
#include "patlab/formats/calibration_file.h"

namespace patlab::cli {
namespace {

using testing::kPatlab;
using testing::RunCommand;

const std::string kScene = std::string(PATLAB_SOURCE_DIR) + "/settings/ssl-half-field.toml";

// RMS (mm) between two cameras' floor points over the pixels (5 px grid) where the true camera
// sees the field within its lines.
double FloorRmsMm(const camera::CameraModel& truth, const camera::CameraModel& fitted, int w,
                  int h) {
  double sum = 0.0;
  int n = 0;
  for (int y = 2; y < h; y += 5)
    for (int x = 2; x < w; x += 5) {
      const auto qa = truth.PixelToWorld(Vec2(x, y), 0.0);
      if (!qa || std::abs(qa->x()) > 3025 || std::abs(qa->y()) > 2025) continue;
      const auto qb = fitted.PixelToWorld(Vec2(x, y), 0.0);
      sum += qb ? (*qa - *qb).squaredNorm() : 1e12;
      ++n;
    }
  return std::sqrt(sum / std::max(1, n));
}

// "team,id" -> (x, y) of a CSV with columns team, id, x_mm, y_mm at the given positions.
std::map<std::string, Vec2> Robots(const std::string& csv, int team, int id, int x) {
  std::map<std::string, Vec2> out;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() <= static_cast<size_t>(x + 1)) continue;
    out[cells[static_cast<size_t>(team)] + "," + cells[static_cast<size_t>(id)]] = Vec2(
        std::stod(cells[static_cast<size_t>(x)]), std::stod(cells[static_cast<size_t>(x + 1)]));
  }
  return out;
}

TEST(SetupCli, RenderedFrameToDetectionsWithEveryRobotAndTheFloorWithin5Mm) {
  testing::TempDir dir;
  const auto render = RunCommand(kPatlab + " render " + kScene + " -o " + dir.Path("r"));
  ASSERT_EQ(render.exit_code, 0) << render.err;
  const std::string frame = dir.Path("r") + "/frame.png";
  const auto setup =
      RunCommand(kPatlab + " setup " + frame +
                 " --field ssl-2009 --settings ssl-frame.detector -o " + dir.Path("cam"));
  ASSERT_EQ(setup.exit_code, 0) << setup.err << setup.out;
  EXPECT_NE(setup.out.find("field model: ssl-2009"), std::string::npos) << setup.out;
  EXPECT_NE(setup.out.find("mapping error: "), std::string::npos) << setup.out;
  EXPECT_NE(setup.out.find("robots in frame.png: 10"), std::string::npos) << setup.out;
  for (const char* f : {"setup.toml", "calibration.toml", "thresholds.toml", "settings.toml"})
    EXPECT_TRUE(std::filesystem::exists(dir.Path("cam") + "/" + f)) << f;
  // The calibration against the known camera.
  const camera::Calibration truth = formats::LoadCalibration(
      std::string(PATLAB_SOURCE_DIR) + "/settings/ssl-half-field.calibration.toml");
  const camera::Calibration fitted =
      formats::LoadCalibration(dir.Path("cam") + "/calibration.toml");
  const double rms = FloorRmsMm(truth.camera, fitted.camera, 780, 580);
  std::printf("setup's calibration: %.2f mm RMS from the true camera over the visible field\n",
              rms);
  EXPECT_LT(rms, 5.0);
  // detect --setup: every robot, right team and ID, within 20 mm; nothing else.
  const auto detect =
      RunCommand(kPatlab + " detect " + frame + " --setup " + dir.Path("cam") + " --format csv");
  ASSERT_EQ(detect.exit_code, 0) << detect.err;
  const auto found = Robots(detect.out, 2, 3, 5);
  const auto expected = Robots(testing::ReadFile(dir.Path("r") + "/truth.csv"), 0, 1, 2);
  ASSERT_EQ(expected.size(), 10u);
  EXPECT_EQ(found.size(), expected.size()) << detect.out;
  for (const auto& [key, at] : expected) {
    const auto it = found.find(key);
    ASSERT_NE(it, found.end()) << key << " not found:\n" << detect.out;
    EXPECT_LT((it->second - at).norm(), 20.0) << key;
  }
}

// --camera-height: the calibration is fitted with the given height (2.5 m, where the known camera
// is 3.8 m up: the user's word over the lines' and the robots') and the report says it was given.
TEST(SetupCli, TheGivenCameraHeightIsTheCalibrations) {
  testing::TempDir dir;
  const auto render = RunCommand(kPatlab + " render " + kScene + " -o " + dir.Path("r"));
  ASSERT_EQ(render.exit_code, 0) << render.err;
  const std::string frame = dir.Path("r") + "/frame.png";
  for (const double given : {2500.0}) {
    const std::string cam = dir.Path("cam");
    const auto setup = RunCommand(kPatlab + " setup " + frame +
                                  " --field ssl-2009 --settings ssl-frame.detector -o " + cam +
                                  " --camera-height " + std::to_string(given));
    ASSERT_EQ(setup.exit_code, 0) << setup.err << setup.out;
    EXPECT_NE(setup.out.find("(given: --camera-height;"), std::string::npos) << setup.out;
    const camera::Calibration fitted = formats::LoadCalibration(cam + "/calibration.toml");
    const camera::PinholeCamera& c = fitted.camera.pinhole();
    const double height = (-c.rotation.transpose() * c.translation_mm).z();
    EXPECT_NEAR(height, given, 30.0);
  }
}

TEST(SetupCli, BadInputIsExit2WithNothingWritten) {
  testing::TempDir dir;
  const std::string frame = std::string(PATLAB_SOURCE_DIR) + "/settings/ssl-frame.png";
  const std::string out = " -o " + dir.Path("cam");
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {frame + " --field ssl-2009" + out, "missing --settings"},
      {frame + " --settings ssl-frame.detector" + out, "missing --field"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector", "missing --out DIR"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector --landmark centre=1" + out,
       "--landmark 'centre=1'; expected NAME=X,Y"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector --landmark centre=1,2" + out,
       "--landmark given 1 times; expected at least 4"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector --robot-height -5" + out,
       "--robot-height is -5 mm; expected 0 to 1000"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector --camera-height -5" + out,
       "--camera-height: negative; expected mm above the floor"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector --camera-height 100" + out,
       "--camera-height is 100 mm; expected above the robots' height (140 mm)"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector --camera-height high" + out,
       "for option '--camera-height' is invalid"},
      // The golden frame shows no field lines.
      {frame + " --field ssl-2009 --settings ssl-frame.detector" + out,
       "give four --landmark NAME=X,Y"},
  };
  for (const Case& c : cases) {
    const auto r = RunCommand(kPatlab + " setup " + c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.Path("cam")));
  const auto detect = RunCommand(kPatlab + " detect " + frame + " --setup " + dir.Path("none"));
  EXPECT_EQ(detect.exit_code, 2);
  EXPECT_NE(detect.err.find("no setup.toml in it"), std::string::npos) << detect.err;
}

TEST(SetupCli, ListsTheLandmarksOfAField) {
  const auto r = RunCommand(kPatlab + " setup --list-landmarks ssl-2009");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("  centre 0 0\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  corner_pos_left 3025 2025\n"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace patlab::cli
