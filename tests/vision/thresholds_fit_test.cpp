#include "patlab/vision/thresholds_fit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "../frame_test_util.h"
#include "../test_util.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/labels_file.h"
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/scene_render.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"

namespace patlab::vision {
namespace {

camera::Image Row(const std::vector<std::array<uint8_t, 3>>& pixels, int width, int height) {
  camera::Image image = camera::Image::Rgb(width, height);
  for (size_t i = 0; i < pixels.size(); ++i) {
    for (int ch = 0; ch < 3; ++ch) image.data[3 * i + ch] = pixels[i][ch];
  }
  return image;
}

ThresholdsFitOptions RgbOptions(int margin, double lo = 0.0, double hi = 100.0) {
  ThresholdsFitOptions o;
  o.space = ColorSpace::kRgb;
  o.margin_levels = margin;
  o.lower_percentile = lo;
  o.upper_percentile = hi;
  return o;
}

void ExpectRange(const ChannelRange& r, int lo, int hi) {
  EXPECT_EQ(r.lo, lo);
  EXPECT_EQ(r.hi, hi);
}

// 4 x 2 pixels; class a: a rectangle of two pixels and a point; class b: a 2 x 2 rectangle. Bounds
// by hand: a R 10..12, G 20..25, B 30..32; b R 50..205, G 0..50, B 0..50; margin 2, clamped.
TEST(ThresholdsFit, BoundsAreTheSampleRangeWidenedByTheMargin) {
  const camera::Image image = Row({{10, 20, 30},
                                   {12, 22, 32},
                                   {200, 0, 0},
                                   {202, 4, 0},  // row 0
                                   {11, 25, 31},
                                   {0, 0, 0},
                                   {205, 1, 3},
                                   {50, 50, 50}},  // row 1
                                  4, 2);
  const Labels labels = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"a\"\nrects = [[0, 0, 1, 0]]\npoints = [[0, 1]]\n"
      "[[class]]\nname = \"b\"\nrects = [[2, 0, 3, 1]]\nmin_area_px = 3\n",
      "l.toml", "");
  const std::vector<int> px = LabelPixels(labels, 4, 2, nullptr);
  EXPECT_EQ(px, (std::vector<int>{0, 0, 1, 1, 0, -1, 1, 1}));
  const ThresholdsFit fit = FitThresholds(image, px, labels, RgbOptions(2));
  ASSERT_EQ(fit.classes.size(), 2u);
  ExpectRange(fit.classes[0].range[0], 8, 14);
  ExpectRange(fit.classes[0].range[1], 18, 27);
  ExpectRange(fit.classes[0].range[2], 28, 34);
  ExpectRange(fit.classes[1].range[0], 48, 207);
  ExpectRange(fit.classes[1].range[1], 0, 52);
  ExpectRange(fit.classes[1].range[2], 0, 52);
  EXPECT_EQ(fit.classes[0].samples, 3);
  EXPECT_EQ(fit.classes[1].samples, 4);
  EXPECT_EQ(fit.classes[0].caught_own, 3);
  EXPECT_EQ(fit.classes[1].caught_own, 4);
  EXPECT_EQ(fit.classes[1].caught_unlabelled, 0);  // (0, 0, 0) is in neither box
  EXPECT_EQ(fit.labelled_px, 7);
  EXPECT_EQ(fit.unlabelled_px, 1);
  EXPECT_TRUE(fit.overlaps.empty());
  EXPECT_EQ(fit.thresholds.classes[1].min_area_px, 3);
  // The display colour defaults to the sample mean: b's mean is (164.25, 13.75, 13.25).
  EXPECT_EQ(fit.thresholds.classes[1].display_rgb, (std::array<uint8_t, 3>{164, 14, 13}));
}

// Percentiles by nearest rank: 5 values 10, 11, 12, 13, 100 -> p25 = v[floor(0.25*4)] = 11,
// p75 = v[ceil(0.75*4)] = v[3] = 13, so the outlier 100 is left out.
TEST(ThresholdsFit, PercentilesDropOutliers) {
  const camera::Image image =
      Row({{10, 0, 0}, {11, 0, 0}, {12, 0, 0}, {13, 0, 0}, {100, 0, 0}}, 5, 1);
  const Labels labels = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"a\"\nrects = [[0, 0, 4, 0]]\n", "l.toml", "");
  const ThresholdsFit fit =
      FitThresholds(image, LabelPixels(labels, 5, 1, nullptr), labels, RgbOptions(0, 25, 75));
  ExpectRange(fit.classes[0].range[0], 11, 13);
  EXPECT_EQ(fit.classes[0].caught_own, 3);  // 10 and 100 fall outside
}

// In YUV (BT.601 fixed point, image.h): red (255, 0, 0) -> (77, 85, 255) and blue (0, 0, 255) ->
// (29, 255, 107), by hand from the formula; the box spans both.
TEST(ThresholdsFit, YuvBoundsAreInTheLookupTablesSpace) {
  const camera::Image image = Row({{255, 0, 0}, {0, 0, 255}}, 2, 1);
  const Labels labels = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"a\"\npoints = [[0, 0], [1, 0]]\n", "l.toml", "");
  ThresholdsFitOptions o;
  o.margin_levels = 0;
  o.lower_percentile = 0;
  o.upper_percentile = 100;
  const ThresholdsFit fit = FitThresholds(image, LabelPixels(labels, 2, 1, nullptr), labels, o);
  EXPECT_EQ(fit.thresholds.space, ColorSpace::kYuv);
  ExpectRange(fit.classes[0].range[0], 29, 77);
  ExpectRange(fit.classes[0].range[1], 85, 255);
  ExpectRange(fit.classes[0].range[2], 107, 255);
}

// Class a's samples R 10, 16, 20 and b's 15, 18, 30 (G = B = 0), margin 0: boxes R 10..20 and
// 15..30 intersect in 15..20, volume 6 x 1 x 1; a's 16 and 20 lie in b's box, b's 15 and 18 in
// a's. The lookup gives overlaps to the class listed first (a): a catches its 3 and b's 15, 18
// and the unlabelled 17; b keeps only its 30.
TEST(ThresholdsFit, OverlapsAndCatchesAreCounted) {
  const camera::Image image = Row(
      {{10, 0, 0}, {16, 0, 0}, {20, 0, 0}, {15, 0, 0}, {18, 0, 0}, {30, 0, 0}, {17, 0, 0}}, 7, 1);
  const Labels labels = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"a\"\nrects = [[0, 0, 2, 0]]\n"
      "[[class]]\nname = \"b\"\nrects = [[3, 0, 5, 0]]\n",
      "l.toml", "");
  const ThresholdsFit fit =
      FitThresholds(image, LabelPixels(labels, 7, 1, nullptr), labels, RgbOptions(0));
  ASSERT_EQ(fit.overlaps.size(), 1u);
  EXPECT_EQ(fit.overlaps[0].a, 0);
  EXPECT_EQ(fit.overlaps[0].b, 1);
  EXPECT_DOUBLE_EQ(fit.overlaps[0].volume, 6.0);
  EXPECT_EQ(fit.overlaps[0].a_in_b, 2);
  EXPECT_EQ(fit.overlaps[0].b_in_a, 2);
  EXPECT_EQ(fit.classes[0].caught_own, 3);
  EXPECT_EQ(fit.classes[0].caught_other, 2);
  EXPECT_EQ(fit.classes[0].caught_unlabelled, 1);
  EXPECT_EQ(fit.classes[1].caught_own, 1);
  EXPECT_EQ(fit.classes[1].caught_other, 0);
  const std::string report = ThresholdsFitReport(fit);
  EXPECT_NE(report.find("a / b: volume 6, 2 a samples in b's box, 2 b samples in a's box"),
            std::string::npos)
      << report;
}

TEST(ThresholdsFit, MaskColoursLabelPixels) {
  const Labels labels = formats::ParseLabels(
      "image = \"x.png\"\nmask = \"m.png\"\n[[class]]\nname = \"a\"\nmask = [255, 0, 0]\n"
      "[[class]]\nname = \"b\"\nmask = [0, 0, 255]\n",
      "l.toml", "dir");
  EXPECT_EQ(labels.mask_path, "dir/m.png");
  const camera::Image mask = Row({{255, 0, 0}, {0, 0, 0}, {0, 0, 255}, {255, 0, 0}}, 2, 2);
  EXPECT_EQ(LabelPixels(labels, 2, 2, &mask), (std::vector<int>{0, -1, 1, 0}));
  EXPECT_INPUT_ERROR(LabelPixels(labels, 3, 2, &mask),
                     "l.toml:2: mask dir/m.png is 2x2; expected the image's size 3x2");
  const camera::Image no_blue = Row({{255, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, 2, 2);
  EXPECT_INPUT_ERROR(LabelPixels(labels, 2, 2, &no_blue),
                     "l.toml:6: class \"b\" labels no pixel (its mask colour is not in the mask, "
                     "or classes listed before it took its pixels); expected at least one sample "
                     "pixel");
}

TEST(ThresholdsFit, TomlRoundTrips) {
  Thresholds t;
  t.space = ColorSpace::kYuv;
  ColorClass c;
  c.name = "pink";
  c.display_rgb = {255, 0, 255};
  c.range = {ChannelRange{140, 255}, ChannelRange{90, 135}, ChannelRange{170, 255}};
  c.max_area_px = 200;
  t.classes.push_back(c);
  const std::string text = ThresholdsToml(t, "made by a test\nsecond line");
  EXPECT_EQ(text.substr(0, 31), "# made by a test\n# second line\n");
  const Thresholds back = formats::ParseThresholdsToml(text, "t.toml");
  ASSERT_EQ(back.classes.size(), 1u);
  EXPECT_EQ(back.classes[0].name, "pink");
  EXPECT_EQ(back.classes[0].display_rgb, c.display_rgb);
  ExpectRange(back.classes[0].range[2], 170, 255);
  EXPECT_EQ(back.classes[0].max_area_px, 200);
}

TEST(ThresholdsFit, LabelErrorsNameFileAndLine) {
  const Labels labels = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"blue\"\npoints = [[1, 1], [5, 2]]\n", "l.toml", "");
  EXPECT_INPUT_ERROR(LabelPixels(labels, 5, 3, nullptr),
                     "l.toml:4: point [5, 2] of class \"blue\" lies outside the 5x3 image; "
                     "expected 0 <= x < 5 and 0 <= y < 3");
  const Labels rect = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"blue\"\nrects = [\n  [0, 0, 1, 1],\n  [0, 0, 2, "
      "3],\n]\n",
      "l.toml", "");
  EXPECT_INPUT_ERROR(LabelPixels(rect, 5, 3, nullptr),
                     "l.toml:6: rectangle corner [2, 3] of class \"blue\" lies outside the 5x3 "
                     "image; expected 0 <= x < 5 and 0 <= y < 3");
  EXPECT_INPUT_ERROR(
      formats::ParseLabels("image = \"x.png\"\n[[class]]\nname = \"blue\"\n", "l.toml", ""),
      "l.toml:2: class \"blue\" has no samples; expected points, rects or a mask "
      "colour");
  EXPECT_INPUT_ERROR(
      formats::ParseLabels("image = \"x.png\"\n[[class]]\nname = \"b\"\nrects = [[3, 0, 1, 1]]\n",
                           "l.toml", ""),
      "l.toml:4: rectangle [3, 0, 1, 1] in [[class]] 1 is empty; expected x0 <= x1 and y0 <= y1");
  EXPECT_INPUT_ERROR(
      formats::ParseLabels("image = \"x.png\"\n[[class]]\nname = \"b\"\npoints = [[3, 0, 1]]\n",
                           "l.toml", ""),
      "l.toml:4: an item of points in [[class]] 1 is not [x, y]; expected [[x, y], ...] with "
      "integer pixel coordinates");
  EXPECT_INPUT_ERROR(
      formats::ParseLabels("image = \"x.png\"\n[[class]]\nname = \"b\"\nmask = [1, 2, 3]\n",
                           "l.toml", ""),
      "l.toml:2: class \"b\" has a mask colour but the file names no mask; expected mask = "
      "\"FILE.png\"");
  EXPECT_INPUT_ERROR(
      formats::ParseLabels("image = \"x.png\"\n[[class]]\nname = \"b\"\npoint = [[1, 1]]\n",
                           "l.toml", ""),
      "l.toml:4: unknown key 'point' in [[class]] 1; expected one of: name, display, points, "
      "rects, mask, min_area_px, max_area_px");
  EXPECT_INPUT_ERROR(formats::ParseLabels("image = \"x.png\"\n", "l.toml", ""),
                     "l.toml: no classes; expected at least one [[class]] table");
  // "magenta" is pink (settings/colours.toml); "orange" is a colour but not of this palette.
  const Labels magenta = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"magenta\"\npoints = [[1, 1]]\n", "l.toml", "");
  CheckClassesKnown(magenta, {"blue", "pink"});
  const Labels orange = formats::ParseLabels(
      "image = \"x.png\"\n[[class]]\nname = \"Orange\"\npoints = [[1, 1]]\n", "l.toml", "");
  EXPECT_INPUT_ERROR(CheckClassesKnown(orange, {"blue", "pink"}),
                     "l.toml:2: unknown class \"orange\"; expected one of the detector palette: "
                     "blue, pink");
}

TEST(ThresholdsFit, OptionsAreChecked) {
  ThresholdsFitOptions o;
  o.lower_percentile = 50;
  EXPECT_INPUT_ERROR(Validate(o), "lower_percentile is 50; expected in [0, 50)");
  o = {};
  o.margin_levels = 200;
  EXPECT_INPUT_ERROR(Validate(o), "margin_levels is 200; expected an integer in [0, 128]");
}

}  // namespace
}  // namespace patlab::vision

namespace patlab::vision {
namespace {

using patlab::testing::kData;

ThresholdsFit FitFile(const std::string& labels_path) {
  const Labels labels = formats::LoadLabels(labels_path);
  const camera::Image image = ReadFrame(labels.image_path);
  return FitThresholds(image, LabelPixels(labels, image.width_px, image.height_px, nullptr), labels,
                       ThresholdsFitOptions{});
}

// Thresholds fitted to samples of four robots of the golden frame find every robot of a frame
// they never saw: eight robots at other poses with other IDs and other sensor noise.
TEST(ThresholdsFit, GoldenFrameLabelsDetectEveryRobotOfAnotherFrame) {
  const ThresholdsFit fit = FitFile(kData + "vision/golden-frame.labels.toml");
  EXPECT_TRUE(fit.overlaps.empty());
  const formats::SceneFile holdout =
      formats::LoadSceneFile(kData + "vision/thresholds-holdout.scene.toml");
  const camera::Image frame = render::RenderScene(holdout.scene, holdout.calibration.camera);
  FrameDetector frames(fit.thresholds,
                       formats::LoadCalibration(kData + "golden/ssl-frame.calibration.toml"),
                       formats::LoadDetectorSettings(kData + "golden/ssl-frame.detector.toml"), {});
  EXPECT_TRUE(frames.warnings().empty());
  const FrameResult& result = frames.Detect(frame, "holdout");
  ASSERT_EQ(result.detections.size(), holdout.scene.robots.size());
  const auto& palette = frames.detector().config().palette;
  for (const render::RobotPlacement& robot : holdout.scene.robots) {
    const auto it = std::find_if(
        result.detections.begin(), result.detections.end(), [&](const detect::Detection& d) {
          return d.id == robot.id && palette[static_cast<size_t>(d.team_colour)] == robot.team;
        });
    ASSERT_NE(it, result.detections.end()) << robot.team << " " << robot.id;
    EXPECT_EQ(it->status, detect::DetectionStatus::kOk);
    // Within 3 mm: ~10 sigma of the golden test's per-robot position error (golden_frame_test).
    EXPECT_NEAR(it->pose.x_mm, robot.pose.x_mm, 3.0);
    EXPECT_NEAR(it->pose.y_mm, robot.pose.y_mm, 3.0);
  }
}

// The real SSL frame: labels on two of its five robots. Both are found again, and so is the
// held-out blue robot at (478, 562) px; the two held-out yellow robots near the top edge are not
// (their yellow is darker than the labelled robot's box: docs/thresholds.md).
TEST(ThresholdsFit, RealSslFrameLabelsFindTheLabelledAndAHeldOutRobot) {
  if (!std::filesystem::exists(testing::SharedFrames() + "/ssl-field-2008.jpg")) {
    GTEST_SKIP() << "no shared frames at " << testing::SharedFrames();
  }
  const ThresholdsFit fit = FitFile(kData + "vision/ssl-2008.labels.toml");
  FrameDetector frames(fit.thresholds,
                       formats::LoadCalibration(kData + "vision/ssl-2008.calibration.toml"),
                       formats::LoadDetectorSettings(kData + "vision/ssl-2008.detector.toml"), {});
  const FrameResult& result = frames.DetectFile(testing::SharedFrames() + "/ssl-field-2008.jpg");
  std::vector<int> ids;
  for (const detect::Detection& d : result.detections) ids.push_back(d.id);
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<int>{5, 6, 15}));
}

}  // namespace
}  // namespace patlab::vision
