#include "patlab/vision/thresholds_auto.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/scene_file.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/render/camera_render.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::vision {
namespace {

using patlab::testing::kData;

// A carpet with square patches of three colours painted at known places: each class's cluster
// is exactly its patches' pixels, its box holds its colour and not the carpet's.
TEST(ThresholdsAuto, FindsCarpetAndPaintedPatchesExactly) {
  camera::Image image = camera::Image::Rgb(120, 80);
  const auto paint = [&](int x0, int y0, int size, std::array<uint8_t, 3> rgb) {
    for (int y = y0; y < std::min(y0 + size, 80); ++y) {
      for (int x = x0; x < x0 + size; ++x) std::copy(rgb.begin(), rgb.end(), image.Row(y) + 3 * x);
    }
  };
  paint(0, 0, 120, {40, 100, 50});   // carpet, 120 x 80
  paint(10, 10, 6, {35, 75, 210});   // blue: 36 px
  paint(40, 10, 5, {235, 215, 45});  // yellow: 25 px
  paint(70, 40, 4, {240, 95, 185});  // pink: 16 px
  paint(90, 40, 4, {240, 95, 185});  // pink: 16 px more
  const AutoThresholdsFit fit =
      FitThresholdsAuto({&image}, {"Blue", "yellow", "magenta"}, io::DefaultColourVocabulary(), {});
  ASSERT_EQ(fit.classes.size(), 3u);
  EXPECT_EQ(fit.classes[0].name, "blue");
  EXPECT_EQ(fit.classes[2].name, "pink");
  EXPECT_EQ(fit.classes[0].pixels, 36);
  EXPECT_EQ(fit.classes[1].pixels, 25);
  EXPECT_EQ(fit.classes[2].pixels, 32);
  EXPECT_EQ(fit.carpet.pixels, 120 * 80 - 36 - 25 - 32);
  const ColorLut lut(fit.thresholds);
  const auto classify = [&](int r, int g, int b) {
    int y, u, v;
    camera::RgbToYuv(r, g, b, &y, &u, &v);
    return lut.Classify(y, u, v);
  };
  EXPECT_EQ(classify(35, 75, 210), 0);
  EXPECT_EQ(classify(235, 215, 45), 1);
  EXPECT_EQ(classify(240, 95, 185), 2);
  EXPECT_EQ(classify(40, 100, 50), -1);
  // Three quarters of the light: the boxes hold for 0.7 .. 1.4 times it.
  EXPECT_EQ(classify(35 * 3 / 4, 75 * 3 / 4, 210 * 3 / 4), 0);
  EXPECT_EQ(classify(240 * 3 / 4, 95 * 3 / 4, 185 * 3 / 4), 2);
  // Flat clusters: every class is far from every other in units of spread.
  for (const AutoClassFit& c : fit.classes) EXPECT_GT(c.separability, 10.0) << c.name;
}

// Labels seed their class: an amber patch labelled "yellow" (between the vocabulary's yellow and
// orange) becomes yellow's cluster, with its labelled pixels counted, and yellow's box holds it.
TEST(ThresholdsAuto, LabelledPixelsSeedTheirClass) {
  camera::Image image =
      camera::Image::Rgb(200, 150);  // 0.4% of it (max_patch_fraction) is 120 px > 25
  for (int y = 0; y < 150; ++y) {
    for (int x = 0; x < 200; ++x) {
      const bool patch = x >= 20 && x < 25 && y >= 10 && y < 15;
      const std::array<uint8_t, 3> rgb =
          patch ? std::array<uint8_t, 3>{240, 170, 30} : std::array<uint8_t, 3>{40, 100, 50};
      std::copy(rgb.begin(), rgb.end(), image.Row(y) + 3 * x);
    }
  }
  LabelledFrame labelled;
  labelled.image = &image;
  labelled.labels.assign(200 * 150, -1);
  for (int x = 20; x < 25; ++x) labelled.labels[12 * 200 + x] = 0;  // a row of it, as "Yellow"
  labelled.class_names = {"Yellow"};
  const AutoThresholdsFit fit =
      FitThresholdsAuto({}, {"orange", "yellow"}, io::DefaultColourVocabulary(), {}, {labelled});
  EXPECT_EQ(fit.classes[1].labelled, 5);
  EXPECT_EQ(fit.classes[1].pixels, 25);
  EXPECT_EQ(fit.classes[0].pixels, 0);
  int y, u, v;
  camera::RgbToYuv(240, 170, 30, &y, &u, &v);
  EXPECT_EQ(ColorLut(fit.thresholds).Classify(y, u, v), 1);
}

TEST(ThresholdsAuto, BadInputIsAnInputError) {
  const camera::Image image = camera::Image::Rgb(4, 4);
  EXPECT_INPUT_ERROR(
      FitThresholdsAuto({&image}, {"blue", "pnik"}, io::DefaultColourVocabulary(), {}),
      "unknown colour 'pnik'; expected a colour of settings/colours.toml (did you mean 'pink'?)");
  EXPECT_INPUT_ERROR(
      FitThresholdsAuto({&image}, {"pink", "Magenta"}, io::DefaultColourVocabulary(), {}),
      "colour 'pink' asked for twice; expected distinct classes");
  AutoThresholdsOptions o;
  o.lighting_max_gain = 0.5;
  EXPECT_INPUT_ERROR(FitThresholdsAuto({&image}, {"blue"}, io::DefaultColourVocabulary(), o),
                     "lighting_max_gain is 0.5; expected in [1, 4]");
}

// Fitted on one colour-camera frame of the golden scene at exposure 1, the thresholds find every
// robot of another scene (other poses, IDs, ball place) with its team and ID at exposures 0.8
// and 1.25 and another sensor seed.
TEST(ThresholdsAuto, FittedOnOneFrameFindEveryRobotOfOtherFramesAndExposures) {
  const formats::SceneFile golden = formats::LoadSceneFile(kData + "golden/ssl-frame.toml");
  render::CameraSensorOptions sensor;
  const camera::Image fit_frame =
      render::RenderCameraFrame(golden.scene, golden.calibration.camera, sensor, 0);
  const detect::DetectorConfig config =
      formats::LoadDetectorSettings(kData + "golden/ssl-frame.detector.toml");
  const AutoThresholdsFit fit =
      FitThresholdsAuto({&fit_frame}, config.palette, io::DefaultColourVocabulary(), {});
  const formats::SceneFile holdout =
      formats::LoadSceneFile(kData + "vision/thresholds-holdout.scene.toml");
  FrameDetector frames(fit.thresholds,
                       formats::LoadCalibration(kData + "golden/ssl-frame.calibration.toml"),
                       config, {});
  for (const double exposure : {0.8, 1.0, 1.25}) {
    sensor.exposure_gain = exposure;
    sensor.seed = 99;
    const camera::Image frame =
        render::RenderCameraFrame(holdout.scene, holdout.calibration.camera, sensor, 3);
    const FrameResult& result = frames.Detect(frame, "holdout");
    EXPECT_EQ(result.detections.size(), holdout.scene.robots.size()) << exposure << "\n"
                                                                     << AutoThresholdsReport(fit);
    const auto& palette = frames.detector().config().palette;
    for (const render::RobotPlacement& robot : holdout.scene.robots) {
      const bool found = std::any_of(
          result.detections.begin(), result.detections.end(), [&](const detect::Detection& d) {
            return d.id == robot.id && palette[static_cast<size_t>(d.team_colour)] == robot.team;
          });
      EXPECT_TRUE(found) << robot.team << " " << robot.id << " at exposure " << exposure;
    }
  }
}

}  // namespace
}  // namespace patlab::vision
