// The colour fit setup keeps (internal::ChooseColourFit): of the blobs' fits at the settings'
// stand-out threshold and segmentation scale and at their neighbours, and the pixel clustering,
// the one that decodes the most robots. The scene is a fresh rendered seed of
// scripts/setup_rendered.py (docs/setup.md), rendered as the script renders it.
#include <gtest/gtest.h>

#include <string>

#include "../test_util.h"
#include "patlab/formats/camera_setup.h"
#include "ssl_robot_scene.h"

namespace patlab::formats {
namespace {

// Fresh rendered seed 89: a dim frame (brightness 0.76, exposure 0.83) from 4.8 m over a goal of
// ssl-div-a, eight robots whose ID patches are 2.5-3 px in radius. The green patches lie 14-20
// Delta E from the green carpet: at the settings' standout_delta_e 20 none stands out, the class
// green named one blob (a piece of field line), no robot decoded, and the three models whose
// lines the frame fits alike (ssl-div-a, ssl-div-b, ssl-2018) were a tie: refused. At 0.7 of the
// threshold the green patches stand out, 8 robots decode through ssl-div-a's camera and none
// through the others', whose defence areas put the robots' patterns at the wrong scale.
RenderedView FreshSeedEightyNine(const testing::TempDir& dir) {
  return RenderedAsTheScriptDoes(SslRobotScene(dir, R"(model = "pinhole"
image_size_px = [780, 580]
[pinhole]
fx_px = 603.190214
fy_px = 603.190214
cx_px = 398.574701
cy_px = 280.792261
k1 = -0.115688
rotation_rodrigues = [-2.427917080, -1.968117027, 0.020067296]
translation_mm = [768.585480, 4549.887090, 4807.962877]
[heights]
default_mm = 140
)",
                                               "ssl-div-a", R"(field = [38, 82, 47]
body = [24, 21, 27]
blue = [28, 52, 167]
yellow = [188, 149, 36]
pink = [192, 66, 147]
green = [56, 149, 76]
orange = [200, 87, 20]
)",
                                               {{"blue", 2, -5032.3, 2133.8, 2.6368},
                                                {"yellow", 12, -4025.7, -1736.7, -1.0788},
                                                {"blue", 8, -5473.4, -854.8, 1.5232},
                                                {"yellow", 1, -5224.1, -599.2, -0.7235},
                                                {"blue", 10, -4567.7, -890.2, -2.5133},
                                                {"yellow", 8, -4220.9, 2046.9, 0.7152},
                                                {"blue", 5, -5372.4, -2064.1, -2.4404},
                                                {"yellow", 5, -3564.2, 2024.6, 0.1603}}),
                                 89, 0.831, 3.37);
}

TEST(SetupCamera, DullPatchesNearTheCarpetsColourStandOutAtTheLowerThreshold) {
  const testing::TempDir dir;
  const RenderedView view = FreshSeedEightyNine(dir);
  const SetupResult r =
      SetupCamera({&view.frame}, {"frame.png"}, SslModels({"ssl-div-a", "ssl-div-b", "ssl-2018"}));
  const std::string report = SetupReportText(r);
  EXPECT_EQ(r.field.name, "ssl-div-a") << report;
  EXPECT_TRUE(r.robots_decided) << report;
  EXPECT_LT(FloorOffsetMm(view.scene.calibration.camera, r.calibration_fit.camera), 100.0)
      << report;
  // Every fit at the given threshold decodes nothing; the kept one, at 0.7 of it, all eight.
  ASSERT_EQ(r.blob_fits.size(), 6u) << report;
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(r.blob_fits[i].standout_delta_e, 20.0);
    EXPECT_EQ(r.blob_fits[i].robots, 0) << report;
  }
  for (size_t i = 3; i < 6; ++i) EXPECT_DOUBLE_EQ(r.blob_fits[i].standout_delta_e, 14.0);
  EXPECT_EQ(r.colour_fit, "blobs");
  EXPECT_DOUBLE_EQ(r.standout_delta_e, 14.0);
  EXPECT_EQ(r.robots_by_blobs, 8) << report;
  EXPECT_NE(report.find("colour fit: blobs at standout_delta_e 14, segment_k "), std::string::npos)
      << report;
  EXPECT_NE(report.find("(robots decoded by the blobs at standout_delta_e 20, segment_k 60: 0, "
                        "40: 0, 90: 0; at standout_delta_e 14, segment_k 60: "),
            std::string::npos)
      << report;
}

}  // namespace
}  // namespace patlab::formats
