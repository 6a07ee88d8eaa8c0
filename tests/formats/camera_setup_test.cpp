// The pieces of patlab setup that need no frame: the tolerances chosen from the measured scale,
// mapping error and patch size (formats/camera_setup.h), the --landmark form, setup folders.
#include "patlab/formats/camera_setup.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/scene_file.h"
#include "patlab/render/scene_render.h"
#include "ssl_robot_scene.h"

namespace patlab::formats {
namespace {

// The distances (mm) between where two cameras map a grid of pixels (every `step` px from
// `first`) on the plane `height_mm` up; with `either_frame`, to the nearer of the point and its
// half turn (the field's two equivalent world frames). A pixel either leaves off the plane fails.
std::vector<double> MapDistances(const camera::CameraModel& truth,
                                 const camera::CameraModel& fitted, const camera::Image& frame,
                                 int first, int step, double height_mm, bool either_frame) {
  std::vector<double> d;
  for (int y = first; y < frame.height_px; y += step)
    for (int x = first; x < frame.width_px; x += step) {
      const auto a = truth.PixelToWorld(Vec2(x, y), height_mm);
      const auto b = fitted.PixelToWorld(Vec2(x, y), height_mm);
      EXPECT_TRUE(a && b) << "pixel (" << x << ", " << y << ")";
      if (!a || !b) continue;
      d.push_back(either_frame ? std::min((*a - *b).norm(), (*a + *b).norm()) : (*a - *b).norm());
    }
  return d;
}

TEST(SetupTolerances, FollowTheScaleTheMappingErrorAndThePatchSize) {
  const detect::DetectorOptions base;
  // A fine camera (1 mm/px), a good calibration, big patches: the floors of each bound.
  detect::DetectorOptions t = SetupTolerances(base, 1.0, 0.5, 20.0);
  EXPECT_DOUBLE_EQ(t.patch_sigma_mm, 2.0);
  EXPECT_DOUBLE_EQ(t.reach_margin_mm, 20.0);
  EXPECT_DOUBLE_EQ(t.area_ratio_min, 0.4);  // 0.5 (18.94 / 20)^2 = 0.45, capped
  // A coarse camera (10 mm/px), 8 mm mapping error, 2.5 px patches.
  t = SetupTolerances(base, 10.0, 8.0, 2.5);
  EXPECT_DOUBLE_EQ(t.patch_sigma_mm, 4.0);            // 0.4 px
  EXPECT_DOUBLE_EQ(t.reach_margin_mm, 3 * 8.0 + 20);  // 3 errors + 2 px
  EXPECT_NEAR(t.area_ratio_min, 0.5 * std::pow(1.44 / 2.5, 2), 1e-12);
  EXPECT_DOUBLE_EQ(t.area_ratio_max, 2.5);
  // A patch a pixel across: the floor of 0.1; an unknown mapping error counts as 0.
  t = SetupTolerances(base, 10.0, std::nan(""), 1.0);
  EXPECT_DOUBLE_EQ(t.area_ratio_min, 0.1);
  EXPECT_DOUBLE_EQ(t.reach_margin_mm, 20.0);
  EXPECT_EQ(t.estimator, base.estimator);  // what setup does not choose stays
}

TEST(SetupBlobAreas, FollowThePatchRadiiInPixels) {
  vision::BlobThresholdsOptions o;
  SetupBlobAreas(4.0, 5.0, &o);
  EXPECT_NEAR(o.min_blob_area_px, 0.2 * M_PI * 16.0, 1e-9);  // a patch's core, a fifth of it
  EXPECT_NEAR(o.max_blob_area_px, 3.0 * M_PI * 25.0, 1e-9);
  EXPECT_NEAR(o.min_blob_sigma_px, 1.2, 1e-12);
  SetupBlobAreas(1.0, 1.0, &o);  // tiny patches: at least 3 px, and max never below min
  EXPECT_EQ(o.min_blob_area_px, 3.0);
  EXPECT_EQ(o.max_blob_area_px, 3.0 * M_PI);
  SetupBlobAreas(1.0, 0.5, &o);
  EXPECT_EQ(o.max_blob_area_px, 3.0);
}

// Frames over kSetupWorkingPx along their longer side are binned to it or below.
TEST(SetupBinning, BringsTheLongerSideToAThousandPixelsOrBelow) {
  EXPECT_EQ(SetupBinning(780, 580), 1);
  EXPECT_EQ(SetupBinning(1024, 768), 1);
  EXPECT_EQ(SetupBinning(1025, 768), 2);
  EXPECT_EQ(SetupBinning(1280, 1024), 2);
  EXPECT_EQ(SetupBinning(1080, 1920), 2);
  EXPECT_EQ(SetupBinning(2448, 2048), 3);
  EXPECT_EQ(SetupBinning(4096, 3072), 4);
  EXPECT_EQ(SetupBinning(100000, 10), 8);  // at most detect::kMaxBinning
}

TEST(SetupLandmarks, ParseNameAndPixel) {
  const SetupLandmark l = ParseLandmark("corner_pos_left=700.5,-3e1");
  EXPECT_EQ(l.name, "corner_pos_left");
  EXPECT_DOUBLE_EQ(l.pixel.x(), 700.5);
  EXPECT_DOUBLE_EQ(l.pixel.y(), -30.0);
  for (const char* bad : {"centre", "centre=1", "centre=1,2,3", "=1,2", "centre=x,2", "c=1,nan"}) {
    EXPECT_INPUT_ERROR(ParseLandmark(bad), std::string("--landmark '") + bad +
                                               "'; expected NAME=X,Y (a landmark of the field "
                                               "and its pixel)");
  }
}

TEST(SetupFolder, NamesItsFilesRelativeToTheFolder) {
  testing::TempDir dir;
  std::ofstream(dir.Path("setup.toml"))
      << "calibration = \"c.toml\"\nthresholds = \"t.toml\"\nsettings = \"/abs/s.toml\"\n";
  const SetupFiles f = LoadSetupFiles(dir.Path(""));
  EXPECT_EQ(f.calibration, dir.Path("c.toml"));
  EXPECT_EQ(f.thresholds, dir.Path("t.toml"));
  EXPECT_EQ(f.settings, "/abs/s.toml");
  std::ofstream(dir.Path("setup.toml")) << "calibration = \"c.toml\"\n";
  EXPECT_INPUT_ERROR(LoadSetupFiles(dir.Path("")),
                     dir.Path("setup.toml") +
                         ":1: missing or non-text key 'thresholds'; expected calibration, "
                         "thresholds and settings file names");
  EXPECT_INPUT_ERROR(LoadSetupFiles(dir.Path("nowhere")),
                     "--setup " + dir.Path("nowhere") +
                         ": no setup.toml in it; expected a folder written by patlab setup");
}

// The --landmark fallback on the rendered half field (settings/ssl-half-field.toml): six landmarks
// projected through the known camera (the field's own lines not used) give a calibration within 5
// mm of it; an unknown landmark is an InputError naming the model's.
// Landmarks replace the lines; and the settings.toml setup writes replaces the settings' [detector]
// tolerances by its own but keeps their policies (here missing_patch = "fit", max_neighbours 6,
// which settings/ssl-frame.detector.toml states as "reject" and 8).
TEST(SetupCamera, LandmarksReplaceTheLines) {
  const SceneFile scene = LoadSceneFile(PATLAB_SOURCE_DIR "/settings/ssl-half-field.toml");
  const camera::Image frame = render::RenderScene(scene.scene, scene.calibration.camera);
  testing::TempDir dir;
  std::string settings = testing::ReadFile(PATLAB_SOURCE_DIR "/settings/ssl-frame.detector.toml");
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{"\"../patterns/", "\"" PATLAB_SOURCE_DIR "/patterns/"},
        {"missing_patch = \"reject\"", "missing_patch = \"fit\""},
        {"max_neighbours = 8", "max_neighbours = 6"}}) {
    for (size_t at = settings.find(from); at != std::string::npos; at = settings.find(from, at))
      settings.replace(at, from.size(), to), at += to.size();
  }
  std::ofstream(dir.Path("settings.toml")) << settings;
  SetupOptions o;
  o.fields = {formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2009.toml")};
  o.settings_path = dir.Path("settings.toml");
  for (const char* name : {"centre", "halfway_left", "centre_circle_right", "corner_pos_left",
                           "defense_front_left_pos", "defense_front_right_pos"}) {
    const auto px = scene.calibration.camera.WorldToPixel(o.fields[0].FindPoint(name)->at_mm, 0.0);
    ASSERT_TRUE(px) << name;
    o.landmarks.push_back({name, *px});
  }
  const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
  EXPECT_TRUE(r.from_landmarks);
  const camera::CameraModel fitted = camera::CameraModel::Pinhole(r.calibration_fit.camera);
  double sum = 0.0;
  const std::vector<double> d =
      MapDistances(scene.calibration.camera, fitted, frame, 5, 10, 0.0, false);
  ASSERT_FALSE(d.empty());
  for (double mm : d) sum += mm * mm;
  EXPECT_LT(std::sqrt(sum / static_cast<double>(d.size())), 5.0);
  EXPECT_EQ(r.files.size(), 4u);
  for (const auto& [name, text] : r.files) {
    if (name != "settings.toml") continue;
    const detect::DetectorConfig written = ParseDetectorSettings(text, name, dir.Path(""));
    EXPECT_EQ(written.options.missing_patch, detect::MissingPatchPolicy::kFit) << text;
    EXPECT_EQ(written.options.max_neighbours, 6) << text;
    EXPECT_DOUBLE_EQ(written.options.patch_sigma_mm, r.tolerances.patch_sigma_mm);
  }
  o.landmarks[0].name = "middle";
  EXPECT_INPUT_ERROR(
      SetupCamera({&frame}, {"frame.png"}, o),
      "--landmark middle: not a landmark of ssl-2009; expected one of " + o.fields[0].PointNames());
}

// The farthest (mm) setup's camera maps the robots' plane from where the true one does, over a
// 40 px grid of the frame (either of the field's two equivalent frames); infinite when it maps
// none of it.
double WorstRobotPlaneOffsetMm(const SceneFile& scene, const SetupResult& r,
                               const camera::Image& frame) {
  const camera::CameraModel fitted = camera::CameraModel::Pinhole(r.calibration_fit.camera);
  const std::vector<double> d =
      MapDistances(scene.calibration.camera, fitted, frame, 40, 100, 140.0, true);
  return d.empty() ? INFINITY : *std::max_element(d.begin(), d.end());
}

// A view the lines do not decide (ssl-div-a, the camera 1.6 m in from a touch line at the halfway
// line: the touch line, the halfway line and a corner of the midline; every model whose touch and
// midline are as far apart fits it at that scale, ssl-div-b at 2/3 of it). The robots decide:
// their patterns have a size in mm, and only the true scale decodes them. Rendered seed 3 of
// scripts/setup_rendered.py, its camera, lighting and robots as drawn.
SceneFile SeedThreesScene(const testing::TempDir& dir) {
  return SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 517.889681
fy_px = 517.889681
cx_px = 391.806293
cy_px = 287.178954
k1 = -0.093095
rotation_rodrigues = [-0.384322192, 3.088143454, -0.015652912]
translation_mm = [-69.599293, 3050.868156, 3846.699603]
[heights]
default_mm = 140
)",
                       "ssl-div-a", R"(field = [33, 93, 46]
body = [24, 26, 30]
blue = [27, 66, 185]
yellow = [184, 189, 40]
pink = [188, 84, 163]
green = [55, 189, 84]
orange = [196, 110, 22]
)",
                       {{"blue", 6, 922.0, -2593.9, 1.4944},
                        {"yellow", 1, -1152.6, -4173.3, 0.9333},
                        {"blue", 10, 0.7, -3844.9, -3.1322},
                        {"yellow", 10, 1176.9, -1490.4, 0.5351},
                        {"blue", 5, 593.2, -2036.2, -2.9509},
                        {"yellow", 12, 2316.5, -1995.4, 2.7110}});
}

TEST(SetupCamera, TheRobotsDecideWhereTheLinesDoNot) {
  const testing::TempDir dir;
  const SceneFile scene = SeedThreesScene(dir);
  const camera::Image frame = render::RenderScene(scene.scene, scene.calibration.camera);
  SetupOptions o;
  for (const char* model : {"ssl-div-b", "ssl-div-a"})
    o.fields.push_back(
        LoadField(PATLAB_SOURCE_DIR "/experiments/fields/" + std::string(model) + ".toml"));
  o.settings_path = PATLAB_SOURCE_DIR "/settings/ssl-frame.detector.toml";
  const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
  ASSERT_GE(r.undecided.size(), 2u);
  EXPECT_TRUE(r.robots_decided);
  EXPECT_EQ(r.undecided.front().field, r.field.name);
  EXPECT_GE(r.undecided.front().robots, 5);
  EXPECT_LT(WorstRobotPlaneOffsetMm(scene, r, frame), 60.0);
  EXPECT_NE(SetupReportText(r).find("the lines do not decide the camera; the robots do"),
            std::string::npos);
}

// Rendered seed 3 as the script renders it (through the colour camera) with ssl-div-a named alone
// (`--field ssl-div-a`): its own search and the one view lent to it fit only cameras through which
// no robot decodes, and the frame was refused. The rest of its family's views, fitted as ssl-div-a
// (formats::SetupFields' lenders), give the camera the robots decide for, as the family does.
TEST(SetupCamera, AModelNamedAloneIsFittedFromItsFamilysViews) {
  const testing::TempDir dir;
  const RenderedView view = RenderedAsTheScriptDoes(SeedThreesScene(dir), 3, 1.214, 1.62);
  const camera::Image& frame = view.frame;
  const SceneFile& scene = view.scene;
  SetupOptions o;
  const SetupFieldModels models = SetupFields("ssl-div-a", {PATLAB_SOURCE_DIR});
  o.fields = models.fields;
  o.settings_path = PATLAB_SOURCE_DIR "/settings/ssl-frame.detector.toml";
  EXPECT_INPUT_ERROR_STARTS_WITH(SetupCamera({&frame}, {"frame.png"}, o),
                                 "frame.png: neither the lines nor the robots decide the camera");
  o.lenders = models.lenders;
  const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
  EXPECT_EQ(r.field.name, "ssl-div-a");
  ASSERT_EQ(r.tried.size(), 1u);
  EXPECT_EQ(r.tried.front().screen_view_of, "ssl-2018");
  EXPECT_TRUE(r.robots_decided);
  EXPECT_GE(r.undecided.front().robots, 5);
  EXPECT_LT(WorstRobotPlaneOffsetMm(scene, r, frame), 60.0);
}

// A camera 3.04 m up looking nearly straight down at a corner of an SSL 2015 field's defence area
// and the centre circle (held-out random camera 16 of scripts/setup_rendered.py): the lines fix
// the floor's map and the focal length over the height, not each: their camera is 1.3 m up (0.88 m
// on the script's noisier frame), where the robots' plane comes out 7% too large and 150 mm off at
// the frame's edge. The robots set the height: the scan finds the heights through which they
// decode, the fit of the lines and their patches together measures it.
TEST(SetupCamera, TheRobotsSetTheCameraHeightTheLinesLeaveOpen) {
  const testing::TempDir dir;
  const SceneFile scene = SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 548.919
fy_px = 548.919
cx_px = 378.601
cy_px = 284.369
k1 = -0.029873
rotation_rodrigues = [-2.86715369, -1.17005725, 0.00297086]
translation_mm = [430.82276, 1056.95985, 3081.49222]
[heights]
default_mm = 140
)",
                                        "ssl-2015", R"(field = [39, 100, 50]
body = [29, 30, 34]
blue = [34, 74, 207]
yellow = [229, 213, 44]
pink = [234, 94, 183]
green = [68, 213, 94]
orange = [244, 124, 25]
)",
                                        {{"blue", 0, -1476, -669, 2.88},
                                         {"yellow", 1, 433, 1312, -2.11},
                                         {"blue", 4, -1612, 628, 2.86},
                                         {"yellow", 13, -1356, -94, -0.58},
                                         {"blue", 11, -2040, -154, 1.69},
                                         {"yellow", 5, -880, -38, 0.51},
                                         {"blue", 12, -49, 352, -2.21},
                                         {"yellow", 15, 771, 934, 2.53}});
  const camera::Image frame = render::RenderScene(scene.scene, scene.calibration.camera);
  SetupOptions o;
  o.fields = {LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2015.toml")};
  o.settings_path = PATLAB_SOURCE_DIR "/settings/ssl-frame.detector.toml";
  const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
  const SetupHeight& h = r.height;
  std::printf("camera height: lines %.0f mm (%d robots), kept %.0f mm (%d robots); true 3043 mm\n",
              h.lines_height_mm, h.lines_robots, h.height_mm, h.robots);
  EXPECT_LT(h.lines_height_mm, 2000.0);  // the lines alone leave it wrong
  EXPECT_EQ(h.decided_by, "robots");
  EXPECT_NEAR(h.height_mm, 3043.0, 0.15 * 3043.0);
  EXPECT_GE(h.robots, 7);
  // The robots' plane is mapped where the true camera maps it.
  const camera::CameraModel fitted = camera::CameraModel::Pinhole(r.calibration_fit.camera);
  const std::vector<double> d =
      MapDistances(scene.calibration.camera, fitted, frame, 40, 100, 140.0, true);
  ASSERT_FALSE(d.empty());
  EXPECT_LT(*std::max_element(d.begin(), d.end()), 30.0);
  EXPECT_NE(SetupReportText(r).find("(the robots decide; "), std::string::npos)
      << SetupReportText(r);
}

// Fresh random camera 41 of scripts/setup_rendered.py: 3.70 m up over an SSL 2018 field, it sees
// one corner of a defence area -- two field lines, which fit every corner of every model at any
// scale -- and ten robots in the SSL standard pattern, of known size, which measure the floor's
// scale; their positions on the field (some near the touch line) choose among the corners.
SceneFile Seed41Scene(const testing::TempDir& dir) {
  return SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 602.869135
fy_px = 602.869135
cx_px = 384.259078
cy_px = 299.484971
k1 = -0.036467
rotation_rodrigues = [0.181265108, 3.086844353, -0.060534300]
translation_mm = [2645.736401, -2703.132033, 3943.421468]
[heights]
default_mm = 140
)",
                       "ssl-2018", R"(field = [39, 96, 44]
body = [24, 23, 24]
blue = [27, 58, 148]
yellow = [184, 166, 32]
pink = [188, 73, 130]
green = [55, 166, 67]
orange = [196, 97, 18]
)",
                       {{"blue", 9, 3486.7, 2071.3, 0.5918},
                        {"yellow", 5, 1292.5, 3717.4, -2.7741},
                        {"blue", 13, 1804.2, 1489.5, -1.3977},
                        {"yellow", 12, 2701.3, 3127.7, -2.0521},
                        {"blue", 3, 1256.2, 2094.2, 2.1204},
                        {"yellow", 7, 1323.9, 1741.8, -2.1132},
                        {"blue", 6, 2014.9, 3803.9, -2.6293},
                        {"yellow", 4, 2621.1, 1953.1, 1.3143},
                        {"blue", 1, 3468.1, 1576.6, 2.2056},
                        {"yellow", 6, 2059.8, 3435.1, 0.3592}});
}

// A camera 3 m up with a long lens (f = 1000 px) looking nearly straight down at one corner of an
// SSL 2018 field's defence area, ten robots around the corner, none near the field's edges.
SceneFile CornerScene(const testing::TempDir& dir) {
  return SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 1000
fy_px = 1000
cx_px = 389.5
cy_px = 289.5
k1 = -0.02
rotation_rodrigues = [3.12, 0.03, 0.0]
translation_mm = [-4600, 1400, 3000]
[heights]
default_mm = 140
)",
                       "ssl-2018", R"(field = [40, 100, 50]
body = [30, 30, 34]
blue = [35, 75, 210]
yellow = [235, 215, 45]
pink = [240, 95, 185]
green = [70, 215, 95]
orange = [250, 125, 25]
)",
                       {{"blue", 1, 3700, 800, 0.3},
                        {"blue", 4, 3800, 1900, -1.2},
                        {"yellow", 2, 4200, 2100, 2.0},
                        {"yellow", 7, 5200, 2050, -2.5},
                        {"blue", 9, 5500, 1700, 1.1},
                        {"yellow", 11, 4300, 1350, -0.4},
                        {"blue", 3, 5300, 800, 2.8},
                        {"yellow", 5, 4050, 700, 0.9},
                        {"yellow", 9, 4900, 1650, 1.7},
                        {"blue", 12, 3600, 1400, -2.0}});
}

SetupOptions CornerOptions() { return SslModels({"ssl-2015", "ssl-2018", "ssl-div-b"}); }

// With the camera's height given, the robots' patterns fix what seed 41's corner leaves open: the
// robots' plane is mapped where the true camera maps it, within a pattern's radius. (Before, setup
// refused the frame: the line pixels matched two field lines.)
TEST(SetupCamera, TheRobotsACornerAndTheHeightFixTheCameraTheLinesAloneDoNot) {
  const testing::TempDir dir;
  const SceneFile scene = Seed41Scene(dir);
  const camera::Image frame = render::RenderScene(scene.scene, scene.calibration.camera);
  SetupOptions o = CornerOptions();
  o.camera_height_mm = 3700.0;
  const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
  EXPECT_TRUE(r.few_lines.used);
  EXPECT_GE(r.few_lines.robots, 6);
  EXPECT_LE(r.few_lines.position_sd_mm, r.few_lines.limit_mm);
  const camera::CameraModel fitted = camera::CameraModel::Pinhole(r.calibration_fit.camera);
  const std::vector<double> d =
      MapDistances(scene.calibration.camera, fitted, frame, 40, 100, 140.0, true);
  ASSERT_FALSE(d.empty());
  EXPECT_LT(*std::max_element(d.begin(), d.end()), 60.0) << SetupReportText(r);
  EXPECT_NE(SetupReportText(r).find("the lines do not fix the camera"), std::string::npos)
      << SetupReportText(r);
}

// Without the height, the fit of the corner and the robots' patches knows the robots' positions
// only to more than a pattern's radius: refused, naming the numbers and --camera-height. (With
// it, the robots near the corner would still not choose between it and its mirror image: refused
// as undecided.)
TEST(SetupCamera, ACornerAndTenRobotsWithoutTheHeightDoNotFixTheCamera) {
  const testing::TempDir dir;
  const SceneFile scene = CornerScene(dir);
  const camera::Image frame = render::RenderScene(scene.scene, scene.calibration.camera);
  try {
    const SetupResult r = SetupCamera({&frame}, {"frame.png"}, CornerOptions());
    ADD_FAILURE() << "accepted:\n" << SetupReportText(r);
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("the line pixels matched 2 field line(s)"), std::string::npos) << what;
    EXPECT_NE(what.find("give --camera-height MM"), std::string::npos) << what;
  }
  SetupOptions o = CornerOptions();
  o.camera_height_mm = 3000.0;
  try {
    const SetupResult r = SetupCamera({&frame}, {"frame.png"}, o);
    ADD_FAILURE() << "accepted with the height:\n" << SetupReportText(r);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mapping the frame elsewhere"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace patlab::formats
