// The colour camera (vision/camera_render.h): the golden scene through exposure, the RGGB
// sensor, bilinear demosaicing and UYVY, then through the unchanged real-frame pipeline
// (thresholds, regions, calibration, detector) of the golden frame; determinism per frame
// identity; the demosaicing of a flat colour and of a vertical edge by hand.
#include "patlab/vision/camera_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "../expect_error.h"
#include "patlab/detect/settings.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::vision {
namespace {

const std::string kGolden = std::string(PATLAB_SOURCE_DIR) + "/tests/data/golden/";

struct Rendered {
  SceneFile file;
  const CameraModel& camera;
};

SceneFile GoldenFile() { return LoadSceneFile(kGolden + "ssl-frame.toml"); }

// Every robot of the golden scene found with its team and ID; returns the largest position
// error (mm) and angle error (rad) over the robots.
void DetectAll(const Image& frame, const FieldScene& scene, double* max_pos_mm,
               double* max_theta_rad) {
  FrameDetector detector(LoadThresholds(kGolden + "ssl-frame.thresholds.toml"),
                         LoadCalibration(kGolden + "ssl-frame.calibration.toml"),
                         detect::LoadDetectorSettings(kGolden + "ssl-frame.detector.toml"), {});
  const FrameResult& result = detector.Detect(frame, "camera");
  const std::vector<std::string> palette = {"blue", "yellow", "pink", "green", "orange"};
  *max_pos_mm = *max_theta_rad = 0.0;
  for (const RobotPlacement& robot : scene.robots) {
    SCOPED_TRACE(robot.team + " " + std::to_string(robot.id));
    const detect::Detection* found = nullptr;
    for (const detect::Detection& d : result.detections) {
      if (d.id == robot.id && d.team_colour >= 0 && palette[d.team_colour] == robot.team)
        found = &d;
    }
    ASSERT_NE(found, nullptr);
    *max_pos_mm = std::max(*max_pos_mm, std::hypot(found->pose.x_mm - robot.pose.x_mm,
                                                   found->pose.y_mm - robot.pose.y_mm));
    *max_theta_rad =
        std::max(*max_theta_rad, std::abs(WrapAngle(found->pose.theta_rad - robot.pose.theta_rad)));
  }
  EXPECT_EQ(result.detections.size(), scene.robots.size());
}

// The golden frame's tolerances (tests/cli/golden_frame_test.cpp derives them for 0.1 px of
// centroid error at 0.207 px per mm): here the sensor adds read and shot noise (2 levels, 0.05
// per level: about 3 levels on a patch) and demosaicing and 4:2:2 smear each edge by up to one
// pixel, symmetrically for a disc, so a patch centroid moves by a few tenths of a pixel: at most
// 0.5 px = 2.4 mm per patch, 2.4 mm for the origin, 2.4 / 65 mm = 0.037 rad for the angle.
TEST(CameraRender, GoldenSceneThroughTheSensorIsDetected) {
  const SceneFile file = GoldenFile();
  const Rendered g{file, file.calibration.camera};
  const CameraSensorOptions sensor;
  const Image frame = RenderCameraFrame(g.file.scene, g.camera, sensor, 7);
  EXPECT_EQ(frame.format, PixelFormat::kUyvy);
  double pos = 0.0, theta = 0.0;
  DetectAll(frame, g.file.scene, &pos, &theta);
  EXPECT_LT(pos, 2.4);
  EXPECT_LT(theta, 0.037);
  std::printf("camera frame: max position error %.3f mm, max angle error %.4f rad\n", pos, theta);
}

TEST(CameraRender, SameFrameIdentitySameImage) {
  const SceneFile file = GoldenFile();
  const Rendered g{file, file.calibration.camera};
  const CameraSensorOptions sensor;
  const Image a = RenderCameraFrame(g.file.scene, g.camera, sensor, 3);
  const Image b = RenderCameraFrame(g.file.scene, g.camera, sensor, 3);
  const Image c = RenderCameraFrame(g.file.scene, g.camera, sensor, 4);
  EXPECT_EQ(a.data, b.data);
  EXPECT_NE(a.data, c.data);
}

// A flat colour through the mosaic without noise comes back exactly (every neighbour mean of a
// constant is the constant); a vertical edge between two colours is interpolated across one
// pixel by hand: at the R site just left of the edge, green is the mean of its 4 neighbours.
TEST(CameraRender, BilinearDemosaicingByHand) {
  CameraSensorOptions quiet;
  quiet.read_noise_levels = 0.0;
  quiet.shot_noise_gain = 0.0;
  Image flat = Image::Rgb(8, 6);
  for (size_t i = 0; i < flat.data.size(); i += 3) {
    flat.data[i] = 200;
    flat.data[i + 1] = 100;
    flat.data[i + 2] = 50;
  }
  EXPECT_EQ(SimulateSensor(flat, quiet, 0).data, ToUyvy(flat).data);
  Image edge = flat;  // columns 0..3 (200, 100, 50), columns 4..7 (200, 20, 50)
  for (int y = 0; y < 6; ++y) {
    for (int x = 4; x < 8; ++x) edge.Row(y)[3 * x + 1] = 20;
  }
  // Photosite (4, 2) is R (even row, even column): green = (G(3,2) + G(5,2) + G(4,1) + G(4,3)) / 4
  // = (100 + 20 + 20 + 20) / 4 = 40; its pixel pair (4, 5) shares U and V, Y is its own.
  const Image out = SimulateSensor(edge, quiet, 0);
  int expected_y, u, v;
  RgbToYuv(200, 40, 50, &expected_y, &u, &v);
  EXPECT_EQ(out.Row(2)[2 * 4 + 1], expected_y);
  quiet.exposure_gain = 2.0;  // 200 x 2 clips at 255
  int clipped_y;
  RgbToYuv(255, 200, 100, &clipped_y, &u, &v);
  EXPECT_EQ(SimulateSensor(flat, quiet, 0).Row(0)[1], clipped_y);
}

TEST(CameraRender, OptionsAreChecked) {
  CameraSensorOptions o;
  o.exposure_gain = 0.0;
  EXPECT_INPUT_ERROR(Validate(o), "exposure_gain is 0; expected a number in (0, 16]");
  o = CameraSensorOptions{};
  o.read_noise_levels = 100.0;
  EXPECT_INPUT_ERROR(Validate(o),
                     "read_noise_levels is 100; expected a number in [0, 64] (8-bit levels)");
  EXPECT_INPUT_ERROR(SimulateSensor(Image::Rgb(3, 2), CameraSensorOptions{}, 0),
                     "image width_px is 3; expected an even width for UYVY");
}

}  // namespace
}  // namespace patlab::vision
