// patlab setup end to end: a frame rendered with a known camera (settings/ssl-half-field.toml,
// robots on an SSL 2009 field with its painted lines) -> setup -> detect --setup finds every
// robot with its team and ID and no other; the calibration maps the floor within 5 mm of the true
// camera. Bad input is exit 2 with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
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

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

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

// detect --setup on the rendered frame: every robot of its truth, right team and ID, within
// 20 mm; nothing else.
void ExpectEveryRobot(const std::string& frame, const std::string& setup,
                      const std::string& truth_csv) {
  const auto detect =
      RunCommand(kPatlab + " detect " + frame + " --setup " + setup + " --format csv");
  ASSERT_EQ(detect.exit_code, 0) << detect.err;
  const auto found = Robots(detect.out, 2, 3, 5);
  const auto expected = Robots(testing::ReadFile(truth_csv), 0, 1, 2);
  ASSERT_EQ(expected.size(), 10u);
  EXPECT_EQ(found.size(), expected.size()) << detect.out;
  for (const auto& [key, at] : expected) {
    const auto it = found.find(key);
    ASSERT_NE(it, found.end()) << key << " not found:\n" << detect.out;
    EXPECT_LT((it->second - at).norm(), 20.0) << key;
  }
}

// Renders `scene` into DIR/r and sets its frame up with ssl-2009 and the shipped settings into
// DIR/cam: setup's run (a failed render is a failed test).
testing::CommandResult RenderAndSetUp(const testing::TempDir& dir, const std::string& scene) {
  const auto render = RunCommand(kPatlab + " render " + scene + " -o " + dir.Path("r"));
  EXPECT_EQ(render.exit_code, 0) << render.err;
  return RunCommand(kPatlab + " setup " + dir.Path("r") +
                    "/frame.png --field ssl-2009 --settings ssl-frame.detector -o " +
                    dir.Path("cam"));
}

TEST(SetupCli, RenderedFrameToDetectionsWithEveryRobotAndTheFloorWithin5Mm) {
  testing::TempDir dir;
  const testing::CommandResult setup = RenderAndSetUp(dir, kScene);
  ASSERT_EQ(setup.exit_code, 0) << setup.err << setup.out;
  const std::string frame = dir.Path("r") + "/frame.png";
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
  ExpectEveryRobot(frame, dir.Path("cam"), dir.Path("r") + "/truth.csv");
}

// A camera of twice the resolution (1560 x 1160 px, the known camera resized): setup bins its
// frame 2 x 2 and says so, writes the calibration of the frame's own pixels (within 5 mm of the
// truth) and settings that bin alike, and detect --setup finds every robot.
TEST(SetupCli, FramesOverAThousandPixelsAreBinnedAndDetectedAlike) {
  testing::TempDir dir;
  const camera::Calibration known = formats::LoadCalibration(
      std::string(PATLAB_SOURCE_DIR) + "/settings/ssl-half-field.calibration.toml");
  const camera::Calibration truth = known.Resized(2.0, 1560, 1160);
  const camera::PinholeCamera& c = truth.camera.pinhole();
  char calibration[1024];
  std::snprintf(calibration, sizeof calibration,
                "model = \"pinhole\"\nimage_size_px = [1560, 1160]\n[pinhole]\nfx_px = %.9g\n"
                "fy_px = %.9g\ncx_px = %.9g\ncy_px = %.9g\nk1 = %.9g\nk2 = 0\n"
                "rotation_rodrigues = [3.1, 0.04, -0.03]\n"
                "translation_mm = [-1435.596971, 418.963873, 3813.598118]\n[heights]\n"
                "default_mm = 140\norange = 21.5\n",
                c.fx_px, c.fy_px, c.cx_px, c.cy_px, c.k1);
  WriteText(dir.Path("camera.toml"), calibration);
  // The shipped scene with this camera, its paths made absolute, 2 x 2 sub-samples.
  std::string scene = testing::ReadFile(kScene);
  const auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = scene.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    scene.replace(at, from.size(), to);
  };
  replace("\"ssl-half-field.calibration.toml\"", "\"" + dir.Path("camera.toml") + "\"");
  replace("\"../", "\"" + std::string(PATLAB_SOURCE_DIR) + "/");
  replace("\"../", "\"" + std::string(PATLAB_SOURCE_DIR) + "/");
  replace("\"../", "\"" + std::string(PATLAB_SOURCE_DIR) + "/");
  replace("supersampling = 4", "supersampling = 2");
  WriteText(dir.Path("scene.toml"), scene);
  const testing::CommandResult setup = RenderAndSetUp(dir, dir.Path("scene.toml"));
  ASSERT_EQ(setup.exit_code, 0) << setup.err << setup.out;
  const std::string frame = dir.Path("r") + "/frame.png";
  EXPECT_NE(setup.out.find("frames binned 2 x 2: 1560 x 1160 px worked on at 780 x 580"),
            std::string::npos)
      << setup.out;
  EXPECT_NE(setup.out.find("robots in frame.png: 10"), std::string::npos) << setup.out;
  EXPECT_NE(testing::ReadFile(dir.Path("cam") + "/settings.toml").find("\nbinning = 2 "),
            std::string::npos);
  const camera::Calibration fitted =
      formats::LoadCalibration(dir.Path("cam") + "/calibration.toml");
  EXPECT_EQ(fitted.image_width_px, 1560);
  EXPECT_EQ(fitted.image_height_px, 1160);
  const double rms = FloorRmsMm(truth.camera, fitted.camera, 1560, 1160);
  std::printf("setup's calibration of the 1560 x 1160 frame: %.2f mm RMS from the truth\n", rms);
  EXPECT_LT(rms, 5.0);
  ExpectEveryRobot(frame, dir.Path("cam"), dir.Path("r") + "/truth.csv");
  // Binned 3 x 3 when asked (520 x 386 px), and a factor out of range refused.
  const auto by3 = RunCommand(kPatlab + " setup " + frame +
                              " --field ssl-2009 --settings ssl-frame.detector --binning 3 -o " +
                              dir.Path("cam3"));
  EXPECT_NE(by3.out.find("frames binned 3 x 3: 1560 x 1160 px worked on at 520 x 386"),
            std::string::npos)
      << by3.out << by3.err;
  const auto bad = RunCommand(kPatlab + " setup " + frame +
                              " --field ssl-2009 --settings ssl-frame.detector --binning 9 -o " +
                              dir.Path("bad"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--binning is 9; expected 0 (chosen from the frames' size) to 8"),
            std::string::npos)
      << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir.Path("bad")));
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
      // Frames of one camera have one size; one too small to find a field in is refused.
      {frame + " " + PATLAB_SOURCE_DIR + "/results/vision/vss-test-frame.png" +
           " --field ssl-2009 --settings ssl-frame.detector" + out,
       "vss-test-frame.png: image is 765x613; expected the first frame's size, 640x480"},
      {frame + " --field ssl-2009 --settings ssl-frame.detector --binning 8" + out,
       "ssl-frame.png: image is 640x480, binned 8 x 8 too small to find a field in"},
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
