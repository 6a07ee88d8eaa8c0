// The segmentation's edge loss in the detector's area test (FrameDetectorOptions::edge_loss_px,
// docs/detect.md "Settings that travel"): the golden scene (tests/data/golden/ssl-frame.toml,
// ~4.8 mm per px, dots of 40 mm = 8 px across) through the colour camera under varied optics
// blur and sensor noise, detected with the SHIPPED detector numbers
// (experiments/detector.toml: [detector] area_ratio_min 0.4, [frame] missing_patch "fit" as
// patlab detect applies it) and the golden thresholds. Nothing here was
// fitted to these frames: the thresholds are the golden frame's, the settings the shipped ones.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "../test_util.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/camera_render.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::vision {
namespace {

using patlab::testing::kGolden;
using patlab::testing::kSource;

struct Condition {
  double blur_sigma_px, exposure_gain, read_noise_levels;
};

// Robots of `scene` found with their team and ID; detections at a robot with its team but no ID
// (fitted with a patch missing: every colour of that slot completes an ID), with a wrong ID, and
// detections that match no robot.
struct Count {
  int found = 0, unknown_id = 0, wrong_id = 0, false_detections = 0;
};

Count DetectScene(const formats::SceneFile& file, const camera::Image& frame, double edge_loss_px) {
  const std::string shipped = kSource + "/experiments/detector.toml";
  FrameDetectorOptions options;
  ApplyFrameSettings(formats::LoadFrameSettings(shipped), &options);
  options.edge_loss_px = edge_loss_px;
  FrameDetector detector(formats::LoadThresholds(kGolden + "ssl-frame.thresholds.toml"),
                         file.calibration, formats::LoadDetectorSettings(shipped), options);
  const FrameResult& result = detector.Detect(frame, "camera");
  const std::vector<std::string>& palette = detector.detector().config().palette;
  Count count;
  for (const detect::Detection& d : result.detections) {
    const render::RobotPlacement* at = nullptr;
    for (const render::RobotPlacement& robot : file.scene.robots) {
      if (d.team_colour >= 0 && palette[static_cast<size_t>(d.team_colour)] == robot.team &&
          std::hypot(d.pose.x_mm - robot.pose.x_mm, d.pose.y_mm - robot.pose.y_mm) < 20.0) {
        at = &robot;
      }
    }
    if (at == nullptr) {
      ++count.false_detections;
    } else if (d.id == at->id) {
      ++count.found;
    } else {
      ++(d.id < 0 ? count.unknown_id : count.wrong_id);
    }
  }
  return count;
}

TEST(EdgeLoss, ShippedSettingsFindEveryRobotUnderBlurAndNoise) {
  // Blur and noise around the golden camera's (0.7 px, 2 levels). Not here: an exposure 15% off
  // or a blur of 0.85 px and more moves the patches' colours out of the golden thresholds' tight
  // boxes (keys found, neighbours not segmented at all, with or without the edge loss): those
  // frames need their own thresholds (patlab thresholds), not another area test.
  const Condition conditions[] = {
      {0.4, 1.0, 2.0}, {0.55, 1.0, 2.0}, {0.7, 1.0, 2.0}, {0.7, 1.0, 4.0}, {0.55, 1.0, 6.0}};
  int missed_without = 0;
  for (const Condition& c : conditions) {
    SCOPED_TRACE("blur " + std::to_string(c.blur_sigma_px) + " px, exposure " +
                 std::to_string(c.exposure_gain) + ", read noise " +
                 std::to_string(c.read_noise_levels));
    formats::SceneFile file = formats::LoadSceneFile(kGolden + "ssl-frame.toml");
    file.scene.options.blur_sigma_px = c.blur_sigma_px;
    render::CameraSensorOptions sensor;
    sensor.exposure_gain = c.exposure_gain;
    sensor.read_noise_levels = c.read_noise_levels;
    const camera::Image frame =
        render::RenderCameraFrame(file.scene, file.calibration.camera, sensor, 11);
    const Count with = DetectScene(file, frame, 1.0);
    const Count without = DetectScene(file, frame, 0.0);
    std::printf(
        "blur %.2f exposure %.2f noise %.0f: %d/%zu found (%d without ID, %d wrong ID, %d false) "
        "with the edge loss, %d (%d without ID, %d wrong ID, %d false) without\n",
        c.blur_sigma_px, c.exposure_gain, c.read_noise_levels, with.found, file.scene.robots.size(),
        with.unknown_id, with.wrong_id, with.false_detections, without.found, without.unknown_id,
        without.wrong_id, without.false_detections);
    EXPECT_EQ(with.found, static_cast<int>(file.scene.robots.size()));
    EXPECT_EQ(with.unknown_id + with.wrong_id + with.false_detections, 0);
    // Without the edge loss, dots fail the area test: missed or, fitted on the other patches
    // ([frame] missing_patch = "fit"), found without their ID -- never with a wrong one.
    EXPECT_EQ(without.wrong_id + without.false_detections, 0);
    missed_without += static_cast<int>(file.scene.robots.size()) - without.found;
  }
  EXPECT_GT(missed_without, 0);
}

}  // namespace
}  // namespace patlab::vision
