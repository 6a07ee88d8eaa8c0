// Tests of scene sampling and frame scoring (src/patlab/sim/scene.h).
#include "scene_score.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "../test_util.h"
#include "patlab/core/error.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"

namespace patlab::sim {
namespace {

detect::Detector ShippedDetector() {
  return detect::Detector(
      formats::LoadDetectorSettings(std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml"));
}

TEST(Scene, TenRobotsFivePerTeamDistinctIdsApartAndABall) {
  detect::Detector detector = ShippedDetector();
  RandomStream rng(1, 0, 0);
  const Scene scene = GenerateScene(detector, SceneOptions{}, PatchNoise{}, rng);
  ASSERT_EQ(scene.robots.size(), 10u);
  std::set<std::pair<int, int>> team_ids;
  for (const SceneRobot& r : scene.robots) team_ids.insert({r.team_colour, r.id});
  EXPECT_EQ(team_ids.size(), 10u);
  for (size_t a = 0; a < scene.robots.size(); ++a) {
    for (size_t b = 0; b < a; ++b) {
      EXPECT_GE(std::hypot(scene.robots[a].pose.x_mm - scene.robots[b].pose.x_mm,
                           scene.robots[a].pose.y_mm - scene.robots[b].pose.y_mm),
                180.0);
    }
  }
  EXPECT_EQ(scene.blobs.size(), 10u * 5u + 1u);  // five patches per robot, a ball
}

TEST(Scene, SameIdentitySameScene) {
  detect::Detector detector = ShippedDetector();
  SceneOptions options;
  options.false_blob_rate_per_m2 = 1.0;
  PatchNoise noise{0.5, {}};
  RandomStream a(9, 4, 17), b(9, 4, 17);
  const Scene sa = GenerateScene(detector, options, noise, a);
  const Scene sb = GenerateScene(detector, options, noise, b);
  ASSERT_EQ(sa.blobs.size(), sb.blobs.size());
  for (size_t i = 0; i < sa.blobs.size(); ++i) {
    EXPECT_EQ(sa.blobs[i].position_mm, sb.blobs[i].position_mm);
    EXPECT_EQ(sa.blobs[i].colour, sb.blobs[i].colour);
  }
}

TEST(Scene, CleanFramesAreDetectedPerfectly) {
  detect::Detector detector = ShippedDetector();
  const DetectionScore score = EvaluateScenes(detector, SceneOptions{}, PatchNoise{}, 5, 0, 50);
  EXPECT_EQ(score.robots, 500);
  EXPECT_EQ(score.correct, 500);
  EXPECT_EQ(score.false_positives, 0);
  EXPECT_LT(score.position_rms_mm(), 1e-9);
}

TEST(Scene, FalseBlobsArePoissonAndDoNotCreateDetections) {
  // 1 false blob per m^2 on the 6.05 x 4.05 m field: mean 24.5 per frame; 200 frames: total
  // 4900 +- 4 * sqrt(4900).
  detect::Detector detector = ShippedDetector();
  SceneOptions options;
  options.false_blob_rate_per_m2 = 1.0;
  long total = 0;
  for (int f = 0; f < 200; ++f) {
    RandomStream rng(2, 0, f);
    total += GenerateScene(detector, options, PatchNoise{0.5, {}}, rng).num_false_blobs;
  }
  EXPECT_NEAR(static_cast<double>(total), 4900.0, 4.0 * 70.0);
  const DetectionScore score = EvaluateScenes(detector, options, PatchNoise{0.5, {}}, 2, 0, 200);
  EXPECT_EQ(score.wrong_id, 0);
  EXPECT_GE(score.detection_rate(), 0.99);
  EXPECT_LE(score.false_positives_per_frame(), 0.05);
}

TEST(Scene, MissingPatchesAndColourErrorsLowerTheRate) {
  // Each of a robot's 5 patches is missing with p = 0.1: P(all present) = 0.9^5 = 0.59.
  detect::Detector detector = ShippedDetector();
  SceneOptions options;
  options.missing_patch_probability = 0.1;
  const DetectionScore score = EvaluateScenes(detector, options, PatchNoise{}, 3, 0, 200);
  const double p = std::pow(0.9, 5), se = std::sqrt(p * (1 - p) / 2000.0);
  EXPECT_NEAR(score.detection_rate(), p, 4.0 * se);

  SceneOptions colours;
  colours.colour_error_probability = 0.05;
  const DetectionScore with_errors = EvaluateScenes(detector, colours, PatchNoise{}, 3, 1, 200);
  EXPECT_GT(with_errors.wrong_id, 0);  // a pink/green swap is another valid SSL ID
  EXPECT_LT(with_errors.detection_rate(), 0.9);
}

TEST(Scene, ScoringCountsWrongIdsAndFalsePositives) {
  Scene scene;
  scene.robots = {{0, 0, 3, Pose2{0, 0, 0}}, {0, 1, 4, Pose2{1000, 0, 0}}};
  std::vector<detect::Detection> detections(3);
  detections[0].team_colour = 0;
  detections[0].id = 3;
  detections[0].pose = Pose2{1.0, 0.0, 0.01};
  detections[1].team_colour = 1;
  detections[1].id = 5;
  detections[1].pose = Pose2{1000.0, 10.0, 0.0};
  detections[2].team_colour = 0;
  detections[2].id = 1;
  detections[2].pose = Pose2{-2000.0, 0.0, 0.0};
  const FrameScore score = ScoreFrame(scene, detections);
  EXPECT_EQ(score.correct, 1);
  EXPECT_EQ(score.wrong_id, 1);
  EXPECT_EQ(score.false_positives, 1);
  EXPECT_EQ(score.missed, 0);
  ASSERT_EQ(score.pose_errors.size(), 1u);
  EXPECT_DOUBLE_EQ(score.pose_errors[0].dx_mm, 1.0);
  EXPECT_DOUBLE_EQ(score.pose_errors[0].dtheta_rad, 0.01);
}

TEST(Scene, BadOptions) {
  detect::Detector detector = ShippedDetector();
  SceneOptions options;
  options.robots_per_team = 17;
  RandomStream rng(1, 0, 0);
  EXPECT_INPUT_ERROR(GenerateScene(detector, options, PatchNoise{}, rng),
                     "scene: robots_per_team is 17; expected at most 16 (the IDs of ssl-standard)");
  options = SceneOptions{};
  options.colour_error_probability = 1.5;
  EXPECT_INPUT_ERROR(GenerateScene(detector, options, PatchNoise{}, rng),
                     "scene: colour_error_probability is 1.5; expected a probability in [0, 1]");
}

}  // namespace
}  // namespace patlab::sim
