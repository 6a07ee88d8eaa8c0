// The VSS two-rectangle robot (patterns/vss-two-rectangles.toml) end to end: rendered with the
// scene renderer (rectangles drawn as rectangles), segmented, detected with the shipped detector
// options, every robot found with its ID and pose.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "patlab/detect/settings.h"
#include "patlab/io/pattern_file.h"
#include "patlab/vision/color_lut.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/scene_render.h"

namespace patlab::vision {
namespace {

const std::string kGolden = std::string(PATLAB_SOURCE_DIR) + "/tests/data/golden/";
const std::string kPatterns = std::string(PATLAB_SOURCE_DIR) + "/patterns/";

TEST(VssRectangles, RenderedRobotsAreAllDetectedWithTheirPoses) {
  // The golden frame's camera (4 m up, tilted, k1 = -0.18, tops at 140 mm) and colours; the
  // pattern's ID colours pink and green give two IDs per team.
  const Calibration calibration = LoadCalibration(kGolden + "ssl-frame.calibration.toml");
  detect::DetectorPattern dp = detect::MakeDetectorPattern(
      io::LoadPatternFile(kPatterns + "vss-two-rectangles.toml"), {"blue", "yellow"}, "",
      {"pink", "green"});
  ASSERT_EQ(dp.codebook.entries.size(), 2u);
  FieldScene scene;
  scene.pattern = dp.pattern;
  scene.codebook = dp.codebook;
  scene.colours = {{"field", {40, 100, 50}},   {"body", {30, 30, 34}},  {"blue", {35, 75, 210}},
                   {"yellow", {235, 215, 45}}, {"pink", {240, 95, 185}}, {"green", {70, 215, 95}},
                   {"orange", {250, 125, 25}}};
  scene.options.width_px = 640;
  scene.options.height_px = 480;
  scene.options.robot_radius_mm = 50.0;  // the dark cube top, 75 mm square, drawn as a disc
  scene.options.seed = 7;
  const std::vector<std::pair<std::string, int>> robots = {
      {"blue", 0}, {"blue", 1}, {"yellow", 0}, {"yellow", 1}, {"blue", 0}, {"yellow", 1}};
  for (size_t i = 0; i < robots.size(); ++i) {
    const double x = -1500.0 + 600.0 * static_cast<double>(i);
    const double y = (i % 2 == 0 ? 600.0 : -700.0) + 50.0 * static_cast<double>(i);
    scene.robots.push_back(
        {robots[i].first, dp.codebook.entries[static_cast<size_t>(robots[i].second)].id,
         Pose2{x, y, -3.0 + 1.1 * static_cast<double>(i)}});
  }
  const Image image = RenderScene(scene, calibration.camera);

  FrameDetector detector(
      LoadThresholds(kGolden + "ssl-frame.thresholds.toml"), calibration,
      detect::MakeDetectorConfig({"blue", "yellow", "pink", "green", "orange"},
                                 detect::DetectorOptions{}, {dp}),
      FrameDetectorOptions{});
  const FrameResult& result = detector.Detect(image, "vss");
  ASSERT_EQ(result.detections.size(), scene.robots.size());
  // Tolerances: a 70 x 32 mm rectangle is ~14 x 6 px here; with 3 levels of noise and 0.7 px of
  // blur its centroid moves by a few hundredths of a pixel (0.2 mm per 0.04 px), and the heading
  // comes from the 36 mm between the two centroids: 0.3 mm / 36 mm ~ 0.01 rad. Hence 1.5 mm and
  // 0.03 rad; a rectangle drawn as its equal-area disc would still pass, a wrong centroid or a
  // swapped key would not.
  for (const RobotPlacement& truth : scene.robots) {
    SCOPED_TRACE(truth.team + " " + std::to_string(truth.id));
    const detect::Detection* found = nullptr;
    for (const detect::Detection& d : result.detections) {
      if (std::hypot(d.pose.x_mm - truth.pose.x_mm, d.pose.y_mm - truth.pose.y_mm) < 30.0) {
        found = &d;
      }
    }
    ASSERT_NE(found, nullptr);
    EXPECT_EQ(found->status, detect::DetectionStatus::kOk);
    EXPECT_EQ(found->id, truth.id);
    EXPECT_EQ(detector.detector().config().palette[static_cast<size_t>(found->team_colour)],
              truth.team);
    EXPECT_NEAR(found->pose.x_mm, truth.pose.x_mm, 1.5);
    EXPECT_NEAR(found->pose.y_mm, truth.pose.y_mm, 1.5);
    EXPECT_NEAR(WrapAngle(found->pose.theta_rad - truth.pose.theta_rad), 0.0, 0.03);
  }
}

}  // namespace
}  // namespace patlab::vision
