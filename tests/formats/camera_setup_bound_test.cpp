// Lines that fit a camera only with its focal length at the fit's lower bound, through which no
// robot decodes at any height, fix no camera (internal::FocalAtItsBound): setup hands such a frame
// to the robots' path. Where robots decode at every height and the lines do not measure the
// height, the fit with the robots is kept however coarse.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/formats/camera_setup_internal.h"
#include "patlab/formats/field_file.h"
#include "ssl_robot_scene.h"

namespace patlab::formats {
namespace {

calib::FamilyCalibration OnlyCamera(double focal_px) {
  calib::FamilyCalibration family;
  family.kept = 0;
  family.calibration.line_pixels = 942;
  family.calibration.fit.camera.fx_px = focal_px;
  return family;
}

// The heights ChooseHeight tried: none decodes a robot.
SetupHeight NothingDecodes() {
  SetupHeight h;
  h.decided_by = "undetermined";
  h.scan = {{1550.0, 310.0, 0, NAN}, {3120.0, 624.0, 0, NAN}, {8310.0, 1662.0, 0, NAN}};
  return h;
}

TEST(FocalAtItsBound, TheOnlyCameraAtTheLowerBoundThroughWhichNothingDecodesIsNamed) {
  const std::vector<calib::Field> fields = {
      LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2015.toml")};
  // Few-lines view 5: 780 px wide, the bound 0.2 widths = 156 px.
  EXPECT_EQ(
      internal::FocalAtItsBound(OnlyCamera(156.0), fields, "frame.png", 780, NothingDecodes()),
      "frame.png: 942 line pixels fit ssl-2015 only with the focal length at the fit's lower "
      "bound (156 px, 0.2 image widths), and no robot decodes through that camera at any "
      "height from 1.55 to 8.31 m: the lines do not fix the camera");
  // Off the bound the lines measured the camera.
  EXPECT_EQ(
      internal::FocalAtItsBound(OnlyCamera(157.0), fields, "frame.png", 780, NothingDecodes()), "");
  // At the bound the lines still fix f / h, and robots decoded at one height choose it (rendered
  // seeds 16, 46, 63 and 104).
  SetupHeight scanned = NothingDecodes();
  scanned.scan[1].robots = 8;
  EXPECT_EQ(internal::FocalAtItsBound(OnlyCamera(156.0), fields, "frame.png", 780, scanned), "");
  SetupHeight given;
  given.decided_by = "given";
  given.robots = given.lines_robots = 3;
  EXPECT_EQ(internal::FocalAtItsBound(OnlyCamera(156.0), fields, "frame.png", 780, given), "");
  // With rivals the robots decide between the cameras (SetupFromLines), bound or not.
  calib::FamilyCalibration rivals = OnlyCamera(156.0);
  rivals.rivals.emplace_back();
  EXPECT_EQ(internal::FocalAtItsBound(rivals, fields, "frame.png", 780, NothingDecodes()), "");
}

// Fresh rendered seed 122 (scripts/setup_rendered.py): 4.0 m over a corner of ssl-div-a's
// defence area. Its lines leave the height open: they fit ssl-div-a anywhere along the valley of
// focal length against height (3.08 +- 25.4 m, f 391 px, where the fit stops once the floor's
// image has settled; it crawled to the focal length's bound, 156 px, 1.23 m up, before), and the
// ten robots decode alike at every height scanned. Kept at the bound's 1.23 m,
// the robots' plane, 140 mm up, was mapped with three times the true parallax: 6 of them over
// 100 mm off (6 false IDs). The fit with the robots measures 4.7 +- 0.8 m (5.6 +- 1.2 m from
// the bound), over the 15 % it needs where the lines measure the height, and is kept where they
// do not.
RenderedView FreshSeed122(const testing::TempDir& dir) {
  return RenderedAsTheScriptDoes(SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 508.099840
fy_px = 508.099840
cx_px = 391.709558
cy_px = 291.704030
k1 = -0.052872
rotation_rodrigues = [2.348224545, 2.057596662, 0.020534053]
translation_mm = [-2025.779718, 3094.948836, 3947.819600]
[heights]
default_mm = 140
)",
                                               "ssl-div-a", R"(field = [48, 110, 59]
body = [32, 29, 35]
blue = [37, 74, 219]
yellow = [249, 211, 47]
pink = [254, 93, 193]
green = [74, 211, 99]
orange = [255, 123, 26]
)",
                                               {{"blue", 8, -3996.9, 3203.2, 2.1598},
                                                {"yellow", 8, -3695.8, 2536.5, 0.4935},
                                                {"blue", 15, -4512.5, 731.1, 0.7227},
                                                {"yellow", 15, -3310.1, 2848.9, 2.5155},
                                                {"blue", 13, -1781.2, 1268.7, -1.3573},
                                                {"yellow", 0, -4259.2, 4191.7, 1.8183},
                                                {"blue", 3, -2511.7, 4079.9, -0.9066},
                                                {"yellow", 1, -3296.7, 1815.4, -1.0692},
                                                {"blue", 14, -2509.0, 1538.1, -0.7762},
                                                {"yellow", 9, -2155.3, 82.8, 3.0217}}),
                                 122, 0.81, 2.56);
}

// The farthest (mm) the fitted camera maps a pixel of a 5 x 5 grid onto the robots' plane (140 mm)
// from where the true one does, the field's half-turn symmetry allowed.
double RobotPlaneOffsetMm(const camera::CameraModel& truth, const camera::PinholeCamera& fitted) {
  const camera::CameraModel f = camera::CameraModel::Pinhole(fitted);
  double same = 0.0, turned = 0.0;
  for (double x = 40.0; x < 780.0; x += 175.0)
    for (double y = 40.0; y < 580.0; y += 125.0) {
      const auto t = truth.PixelToWorld(Vec2(x, y), 140.0);
      const auto q = f.PixelToWorld(Vec2(x, y), 140.0);
      if (!t || !q) return INFINITY;
      same = std::max(same, (*t - *q).norm());
      turned = std::max(turned, (*t + *q).norm());
    }
  return std::min(same, turned);
}

TEST(SetupCamera, LinesThatDoNotMeasureTheHeightLeaveItToTheRobotsHoweverCoarse) {
  const testing::TempDir dir;
  const RenderedView view = FreshSeed122(dir);
  const SetupResult r = SetupCamera({&view.frame}, {"frame.png"}, SslModels({"ssl-div-a"}));
  const std::string report = SetupReportText(r);
  const SetupHeight& h = r.height;
  EXPECT_GT(h.lines_sd_mm, h.lines_height_mm) << report;  // the lines leave the height open
  EXPECT_EQ(h.fitted, "kept") << report;
  EXPECT_EQ(h.decided_by, "robots") << report;
  EXPECT_GT(h.sd_mm, 0.15 * h.height_mm) << report;  // coarse: kept only at the bound
  EXPECT_EQ(h.robots, 10) << report;
  EXPECT_LT(RobotPlaneOffsetMm(view.scene.calibration.camera, r.calibration_fit.camera), 50.0)
      << report;
  EXPECT_FALSE(std::isfinite(h.lines_sd_mm) && h.lines_sd_mm < 0.15 * h.lines_height_mm) << report;
  EXPECT_NE(report.find("(kept: coarse, but the lines do not measure the height at all)"),
            std::string::npos)
      << report;
}

}  // namespace
}  // namespace patlab::formats
