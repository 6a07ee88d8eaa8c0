// The colour camera (render/camera_render.h): the golden scene through exposure, the RGGB
// sensor, bilinear demosaicing and UYVY, then through the unchanged real-frame pipeline
// (thresholds, regions, calibration, detector) of the golden frame; determinism per frame
// identity; the demosaicing of a flat colour and of a vertical edge by hand.
#include "patlab/render/camera_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::render {
namespace {

using testing::kGolden;

struct Rendered {
  formats::SceneFile file;
  const camera::CameraModel& camera;
};

formats::SceneFile GoldenFile() { return formats::LoadSceneFile(kGolden + "ssl-frame.toml"); }

// Every robot of the golden scene found with its team and ID; returns the largest position
// error (mm) and angle error (rad) over the robots.
void DetectAll(const camera::Image& frame, const FieldScene& scene, double* max_pos_mm,
               double* max_theta_rad) {
  vision::FrameDetector detector(formats::LoadThresholds(kGolden + "ssl-frame.thresholds.toml"),
                                 formats::LoadCalibration(kGolden + "ssl-frame.calibration.toml"),
                                 formats::LoadDetectorSettings(kGolden + "ssl-frame.detector.toml"),
                                 {});
  const vision::FrameResult& result = detector.Detect(frame, "camera");
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
  const formats::SceneFile file = GoldenFile();
  const Rendered g{file, file.calibration.camera};
  const CameraSensorOptions sensor;
  const camera::Image frame = RenderCameraFrame(g.file.scene, g.camera, sensor, 7);
  EXPECT_EQ(frame.format, camera::PixelFormat::kUyvy);
  double pos = 0.0, theta = 0.0;
  DetectAll(frame, g.file.scene, &pos, &theta);
  EXPECT_LT(pos, 2.4);
  EXPECT_LT(theta, 0.037);
  std::printf("camera frame: max position error %.3f mm, max angle error %.4f rad\n", pos, theta);
}

TEST(CameraRender, SameFrameIdentitySameImage) {
  const formats::SceneFile file = GoldenFile();
  const Rendered g{file, file.calibration.camera};
  const CameraSensorOptions sensor;
  const camera::Image a = RenderCameraFrame(g.file.scene, g.camera, sensor, 3);
  const camera::Image b = RenderCameraFrame(g.file.scene, g.camera, sensor, 3);
  const camera::Image c = RenderCameraFrame(g.file.scene, g.camera, sensor, 4);
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
  camera::Image flat = camera::Image::Rgb(8, 6);
  for (size_t i = 0; i < flat.data.size(); i += 3) {
    flat.data[i] = 200;
    flat.data[i + 1] = 100;
    flat.data[i + 2] = 50;
  }
  EXPECT_EQ(SimulateSensor(flat, quiet, 0).data, camera::ToUyvy(flat).data);
  camera::Image edge = flat;  // columns 0..3 (200, 100, 50), columns 4..7 (200, 20, 50)
  for (int y = 0; y < 6; ++y) {
    for (int x = 4; x < 8; ++x) edge.Row(y)[3 * x + 1] = 20;
  }
  // Photosite (4, 2) is R (even row, even column): green = (G(3,2) + G(5,2) + G(4,1) + G(4,3)) / 4
  // = (100 + 20 + 20 + 20) / 4 = 40; its pixel pair (4, 5) shares U and V, Y is its own.
  const camera::Image out = SimulateSensor(edge, quiet, 0);
  int expected_y, u, v;
  camera::RgbToYuv(200, 40, 50, &expected_y, &u, &v);
  EXPECT_EQ(out.Row(2)[2 * 4 + 1], expected_y);
  quiet.exposure_gain = 2.0;  // 200 x 2 clips at 255
  int clipped_y;
  camera::RgbToYuv(255, 200, 100, &clipped_y, &u, &v);
  EXPECT_EQ(SimulateSensor(flat, quiet, 0).Row(0)[1], clipped_y);
}

// An independent bilinear demosaic, written as the textbook convolution of each colour's
// masked mosaic (green: the cross kernel [0 1 0; 1 4 1; 0 1 0] / 4, red and blue: [1 2 1; 2 4 2;
// 1 2 1] / 4, Gonzalez & Woods; rounded half up), on the whole golden frame without noise: the
// renderer's UYVY must equal ToUyvy of this byte for byte. A demosaic that takes the wrong
// neighbours, weights or phase anywhere changes bytes at every colour edge (checked: green from 2
// instead of 4 neighbours, or R and B swapped at the G sites, fails here while the detection
// test above still passes).
camera::Image ReferenceDemosaic(const camera::Image& rgb) {
  const int w = rgb.width_px, h = rgb.height_px;
  auto channel = [](int x, int y) {
    return y % 2 == 0 ? (x % 2 == 0 ? 0 : 1) : (x % 2 == 0 ? 1 : 2);
  };
  auto reflect = [](int i, int n) { return i < 0 ? -i : (i >= n ? 2 * n - 2 - i : i); };
  camera::Image out = camera::Image::Rgb(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        // Sum of kernel weight x sample over the 3x3 neighbourhood, for samples of colour c.
        int num = 0, den = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int sx = reflect(x + dx, w), sy = reflect(y + dy, h);
            if (channel(sx, sy) != c) continue;
            const int weight = c == 1 ? (dx == 0 && dy == 0 ? 4 : (dx == 0 || dy == 0 ? 1 : 0))
                                      : (dx == 0 && dy == 0 ? 4 : (dx == 0 || dy == 0 ? 2 : 1));
            num += weight * rgb.Row(sy)[3 * sx + c];
            den += weight;
          }
        }
        out.Row(y)[3 * x + c] = static_cast<uint8_t>((2 * num + den) / (2 * den));
      }
    }
  }
  return out;
}

TEST(CameraRender, DemosaicEqualsTheTextbookConvolutionOnTheGoldenScene) {
  formats::SceneFile file = GoldenFile();
  file.scene.options.noise_sigma_levels = 0.0;
  const camera::Image radiance = RenderScene(file.scene, file.calibration.camera);
  CameraSensorOptions quiet;
  quiet.read_noise_levels = 0.0;
  quiet.shot_noise_gain = 0.0;
  // Mosaic: every pixel keeps only its own channel; the reference fills the others from it.
  const camera::Image reference = camera::ToUyvy(ReferenceDemosaic(radiance));
  const camera::Image out = SimulateSensor(radiance, quiet, 0);
  ASSERT_EQ(out.data.size(), reference.data.size());
  size_t differing = 0;
  for (size_t i = 0; i < out.data.size(); ++i) differing += out.data[i] != reference.data[i];
  EXPECT_EQ(differing, 0u);
  quiet.chroma_422 = false;  // the RGB itself, before 4:2:2
  EXPECT_EQ(SimulateSensor(radiance, quiet, 0).data, ReferenceDemosaic(radiance).data);
}

// A window of a frame is that frame's pixels there (noise keyed by whole-frame coordinates,
// principal point shifted): away from the window's border every byte agrees, up to one level
// where a sub-sample on an edge rounds the other way.
TEST(CameraRender, WindowIsTheWholeFramesPixels) {
  const formats::SceneFile file = GoldenFile();
  const CameraSensorOptions sensor;
  CameraJitter jitter;
  jitter.roll_sigma_rad = 0.002;
  jitter.height_sigma_mm = 3.0;
  const camera::Image whole =
      RenderCameraFrame(file.scene, file.calibration.camera, sensor, 5, jitter);
  const PixelWindow window{200, 140, 120, 90};
  const camera::Image part =
      RenderCameraWindow(file.scene, file.calibration.camera, sensor, 5, window, jitter);
  ASSERT_EQ(part.width_px, 120);
  int compared = 0, differing = 0, worst = 0;
  for (int y = 8; y < window.height - 8; ++y) {
    for (int i = 16; i < 2 * window.width - 16; ++i) {
      const int a = part.Row(y)[i], b = whole.Row(window.y0 + y)[2 * window.x0 + i];
      ++compared;
      differing += a != b;
      worst = std::max(worst, std::abs(a - b));
    }
  }
  EXPECT_LE(worst, 1);
  EXPECT_LT(differing, compared / 1000 + 1);
  EXPECT_INPUT_ERROR(
      RenderCameraWindow(file.scene, file.calibration.camera, sensor, 5, {1, 0, 10, 10}),
      "window origin is (1, 0); expected even coordinates (Bayer phase, UYVY pixel pairs)");
}

// Jitter moves the camera, not the world: roll phi about the optical axis keeps the camera
// centre, a height change moves it along z; the same frame identity gives the same camera.
TEST(CameraRender, JitterMovesTheCameraPerFrame) {
  const formats::SceneFile file = GoldenFile();
  const camera::PinholeCamera& c = file.calibration.camera.pinhole();
  CameraJitter jitter;
  jitter.roll_sigma_rad = 0.01;
  const camera::PinholeCamera a = JitterCamera(c, jitter, 3), b = JitterCamera(c, jitter, 3);
  EXPECT_EQ(a.rotation, b.rotation);
  const Eigen::Vector3d centre = -c.rotation.transpose() * c.translation_mm;
  EXPECT_LT((-a.rotation.transpose() * a.translation_mm - centre).norm(), 1e-9);
  // The rotation between the two cameras is about the camera's z axis only.
  const Eigen::Matrix3d delta = a.rotation * c.rotation.transpose();
  EXPECT_NEAR(delta(2, 2), 1.0, 1e-12);
  EXPECT_GT(std::abs(delta(0, 1)), 0.0);
  jitter = CameraJitter{};
  jitter.height_sigma_mm = 5.0;
  const camera::PinholeCamera h = JitterCamera(c, jitter, 3);
  const Eigen::Vector3d moved = -h.rotation.transpose() * h.translation_mm - centre;
  EXPECT_NEAR(moved.x(), 0.0, 1e-9);
  EXPECT_GT(std::abs(moved.z()), 0.0);
  EXPECT_EQ(JitterCamera(c, CameraJitter{}, 3).rotation, c.rotation);
  jitter.roll_sigma_rad = 0.2;
  EXPECT_INPUT_ERROR(Validate(jitter),
                     "roll_sigma_rad is 0.2; expected a number in [0, 0.1] (rad)");
}

TEST(CameraRender, OptionsAreChecked) {
  CameraSensorOptions o;
  o.exposure_gain = 0.0;
  EXPECT_INPUT_ERROR(Validate(o), "exposure_gain is 0; expected a number in (0, 16]");
  o = CameraSensorOptions{};
  o.read_noise_levels = 100.0;
  EXPECT_INPUT_ERROR(Validate(o),
                     "read_noise_levels is 100; expected a number in [0, 64] (8-bit levels)");
  EXPECT_INPUT_ERROR(SimulateSensor(camera::Image::Rgb(3, 2), CameraSensorOptions{}, 0),
                     "image width_px is 3; expected an even width for UYVY");
}

}  // namespace
}  // namespace patlab::render
