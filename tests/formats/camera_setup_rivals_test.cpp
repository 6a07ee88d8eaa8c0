// Cameras the lines explain nearly alike, decided by a piece of line only one of them explains
// (calib::internal::OwnLinesDecide), and a rival camera that explains more line than the true
// one but sees above the horizon (calib::internal::AboveHorizon). The scenes are fresh rendered
// seeds of scripts/setup_rendered.py (docs/setup.md), rendered as the script renders them.
#include <gtest/gtest.h>

#include <string>

#include "../test_util.h"
#include "patlab/formats/camera_setup.h"
#include "ssl_robot_scene.h"

namespace patlab::formats {
namespace {

// Fresh rendered seed 20: a camera 3.1 m over the centre circle of ssl-div-b. The circle and the
// two lines crossing in it look the same a quarter turn round and in ssl-div-a or ssl-2018, and
// the seven robots decode through each of those cameras: by line length (2126 px against 2090 px)
// and by robots a tie, refused. The frame's bottom-right corner shows about 30 px of touch line,
// 3000 mm from the midline, that the other cameras leave bare while they explain no line pixel
// of their own: that piece decides.
RenderedView FreshSeedTwenty(const testing::TempDir& dir) {
  return RenderedAsTheScriptDoes(SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 553.783474
fy_px = 553.783474
cx_px = 389.549665
cy_px = 291.026233
k1 = -0.033045
rotation_rodrigues = [2.987052464, -0.906660521, 0.066805311]
translation_mm = [-488.665728, -175.068769, 3134.859850]
[heights]
default_mm = 140
)",
                                               "ssl-div-b", R"(field = [32, 73, 43]
body = [27, 25, 33]
blue = [32, 61, 205]
yellow = [214, 176, 44]
pink = [219, 78, 180]
green = [64, 176, 93]
orange = [228, 102, 24]
)",
                                               {{"blue", 8, 347.6, 856.0, -2.8112},
                                                {"yellow", 14, 737.1, -1655.0, -3.1104},
                                                {"blue", 13, 53.5, -600.1, 0.3207},
                                                {"yellow", 15, -982.3, -154.9, 0.7098},
                                                {"blue", 15, 501.2, 73.5, 2.6288},
                                                {"yellow", 7, -363.5, 1102.4, -0.7630},
                                                {"blue", 4, -523.5, -207.4, 1.2224}}),
                                 20, 1.038, 2.07);
}

TEST(SetupCamera, APieceOfTouchLineInACornerDecidesACentreView) {
  const testing::TempDir dir;
  const RenderedView view = FreshSeedTwenty(dir);
  const SetupResult r =
      SetupCamera({&view.frame}, {"frame.png"}, SslModels({"ssl-div-b", "ssl-div-a", "ssl-2018"}));
  const std::string report = SetupReportText(r);
  EXPECT_EQ(r.field.name, "ssl-div-b") << report;
  EXPECT_TRUE(r.undecided.empty()) << report;  // the lines decided
  EXPECT_LT(FloorOffsetMm(view.scene.calibration.camera, r.calibration_fit.camera), 30.0) << report;
  EXPECT_EQ(std::max(r.robots_by_blobs, r.robots_by_pixels), 7) << report;
}

// Fresh rendered seed 196: a camera 3.0 m over an ssl-2012 corner (defence arc, goal and touch
// lines, a piece of the centre circle). ssl-2009's fit ran off from its overhead start to a
// camera 42 mm over the floor, tilted 86 deg, whose marks piled near the horizon explained 2161
// px of line against the true camera's 1666: kept, it found no robot. A camera whose horizon
// crosses the image is no camera over the field (calib::internal::AboveHorizon).
RenderedView FreshSeed196(const testing::TempDir& dir) {
  return RenderedAsTheScriptDoes(SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 546.728231
fy_px = 546.728231
cx_px = 384.716917
cy_px = 296.884241
k1 = -0.095593
rotation_rodrigues = [3.054081639, -0.701903090, 0.073068234]
translation_mm = [-2536.143760, -179.640137, 2921.256834]
[heights]
default_mm = 140
)",
                                               "ssl-2012", R"(field = [60, 159, 69]
body = [36, 39, 38]
blue = [42, 97, 237]
yellow = [255, 255, 51]
pink = [255, 123, 209]
green = [85, 255, 107]
orange = [255, 161, 28]
)",
                                               {{"blue", 11, 2384.4, -1744.8, 1.8789},
                                                {"yellow", 9, 2594.4, -123.8, 1.3787},
                                                {"blue", 7, 1718.8, -1433.8, 1.0208},
                                                {"yellow", 2, 1972.2, -645.3, -1.0433},
                                                {"blue", 12, 1818.1, 196.0, -2.9825},
                                                {"yellow", 13, 1162.3, -1743.7, 1.4202},
                                                {"blue", 1, 1674.8, -1896.8, -3.0544},
                                                {"yellow", 15, 1377.8, 325.2, 2.0864},
                                                {"blue", 9, 584.2, -1032.9, 1.4505},
                                                {"yellow", 12, 954.7, -438.7, -2.0284}}),
                                 196, 0.921, 2.08);
}

TEST(SetupCamera, ACameraThatSeesAboveTheHorizonIsNoFieldCamera) {
  const testing::TempDir dir;
  const RenderedView view = FreshSeed196(dir);
  const SetupResult r =
      SetupCamera({&view.frame}, {"frame.png"}, SslModels({"ssl-2012", "ssl-2009"}));
  const std::string report = SetupReportText(r);
  EXPECT_EQ(r.field.name, "ssl-2012") << report;
  EXPECT_LT(FloorOffsetMm(view.scene.calibration.camera, r.calibration_fit.camera), 30.0) << report;
  EXPECT_EQ(std::max(r.robots_by_blobs, r.robots_by_pixels), 10) << report;
}

}  // namespace
}  // namespace patlab::formats
