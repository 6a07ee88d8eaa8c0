// FrameDetector end to end on a rendered frame: two SSL robots through stages 1-6 come back with
// their IDs and poses; the class -> palette mapping; the results writer's CSV; the stage profile
// named as pipeline.h and detector.h number the stages; the numbered debug images.
#include "patlab/vision/frame_detector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "../frame_test_util.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/render.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/frame_results.h"

namespace patlab::vision {
namespace {

const std::string kSettings = std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml";

// Blue, yellow (a class the detector's palette also names), pink, green and a class ("grass")
// the palette does not name.
Thresholds Classes() {
  return formats::ParseThresholdsToml(
      "space = \"rgb\"\n"
      "[[class]]\nname = \"blue\"\nr = [0, 80]\ng = [0, 100]\nb = [180, 255]\n"
      "[[class]]\nname = \"pink\"\nr = [200, 255]\ng = [0, 110]\nb = [160, 255]\n"
      "[[class]]\nname = \"green\"\nr = [0, 90]\ng = [180, 255]\nb = [0, 110]\n"
      "[[class]]\nname = \"grass\"\nr = [100, 140]\ng = [100, 140]\nb = [0, 60]\n",
      "t.toml");
}

// 2 mm per px, y up, 400 x 300 px = 800 x 600 mm.
camera::Calibration TwoMmPerPixel() {
  return formats::ParseCalibration(
      "model = \"homography\"\nimage_size_px = [400, 300]\n[[homography]]\nheight_mm = 0\n"
      "matrix = [[2, 0, -400], [0, -2, 300], [0, 0, 1]]\n",
      "c.toml");
}

struct Robot {
  Pose2 pose;
  int entry;  // codebook entry
};

// The robots of the shipped settings' pattern (ssl-standard), blue team, plus a grass blob.
camera::Image RenderRobots(const detect::DetectorConfig& config, const std::vector<Robot>& robots,
                           const camera::Calibration& calibration) {
  const detect::DetectorPattern& dp = config.patterns[0];
  const std::vector<int> slots = detect::IdSlots(dp.pattern);
  std::vector<render::Disc> discs = {{Vec2(-300, -200), 30, {120, 120, 30}}};
  for (const Robot& robot : robots) {
    for (int i = 0; i < dp.pattern.size(); ++i) {
      const Patch& patch = dp.pattern.patches[i];
      render::Rgb rgb = {20, 40, 230};  // blue key
      if (patch.role == PatchRole::kId) {
        const int slot = static_cast<int>(std::find(slots.begin(), slots.end(), i) - slots.begin());
        const std::string& colour =
            dp.codebook.colours[dp.codebook.entries[robot.entry].colour[slot]];
        rgb = colour == "pink" ? render::Rgb{250, 60, 220} : render::Rgb{40, 230, 60};
      }
      discs.push_back({robot.pose.Apply(patch.position_mm), patch.radius_mm, rgb});
    }
  }
  return render::RenderWorldDiscs(400, 300, calibration.camera, 0.0, {70, 70, 70}, discs);
}

TEST(FrameDetector, RenderedRobotsComeBackWithIdsPosesAndStageTimes) {
  const detect::DetectorConfig config = formats::LoadDetectorSettings(kSettings);
  const std::vector<Robot> robots = {{Pose2{-150, 50, 0.5}, 3}, {Pose2{180, -40, -2.0}, 12}};
  const camera::Image image = RenderRobots(config, robots, TwoMmPerPixel());
  FrameDetectorOptions options;
  options.collect_timing = true;
  FrameDetector frames(Classes(), TwoMmPerPixel(), config, options);
  const FrameResult& r = frames.Detect(image, "robots");
  // 2 x 5 patches and the grass blob; the detector sees only the palette's classes.
  EXPECT_EQ(r.blobs.size(), 11u);
  EXPECT_EQ(r.detector_blobs.size(), 10u);
  for (size_t i = 0; i < r.detector_blobs.size(); ++i) {
    const detect::Blob& source = r.blobs[static_cast<size_t>(r.detector_blob_source[i])];
    EXPECT_EQ(config.palette[static_cast<size_t>(r.detector_blobs[i].colour)],
              frames.pipeline().thresholds().classes[static_cast<size_t>(source.colour)].name);
  }
  ASSERT_EQ(r.detections.size(), 2u);
  for (const detect::Detection& d : r.detections) {
    const Robot& robot = d.pose.x_mm < 0 ? robots[0] : robots[1];
    EXPECT_EQ(d.id, config.patterns[0].codebook.entries[robot.entry].id);
    EXPECT_EQ(d.status, detect::DetectionStatus::kOk);
    EXPECT_NEAR(d.pose.x_mm, robot.pose.x_mm, 1.0);
    EXPECT_NEAR(d.pose.y_mm, robot.pose.y_mm, 1.0);
    EXPECT_NEAR(d.pose.theta_rad, robot.pose.theta_rad, 0.02);
  }
  // Stages 2-6 of pipeline.h (Detect reads no file), the detector's 1-8 of detector.h.
  std::vector<std::string_view> stages;
  for (const auto& e : r.profile.entries()) stages.push_back(e.stage);
  EXPECT_EQ(stages,
            std::vector<std::string_view>(kFrameStageNames.begin() + 1, kFrameStageNames.end()));
  EXPECT_EQ(r.detect_profile.entries().size(), detect::kDetectStageNames.size());
  EXPECT_EQ(r.detect_stats.detections, 2);
  EXPECT_EQ(r.vision_stats.blobs, 11);
}

TEST(FrameDetector, WritesTheNumberedDebugImagesAndReadsFiles) {
  const std::string dir = testing::ScratchDir();
  const detect::DetectorConfig config = formats::LoadDetectorSettings(kSettings);
  WritePng(RenderRobots(config, {{Pose2{0, 0, 1.0}, 5}}, TwoMmPerPixel()), dir + "/f1.png");
  FrameDetectorOptions options;
  options.debug_dir = dir + "/debug";
  FrameDetector frames(Classes(), TwoMmPerPixel(), config, options);
  const FrameResult& r = frames.DetectFile(dir + "/f1.png");
  ASSERT_EQ(r.detections.size(), 1u);
  EXPECT_TRUE(r.profile.entries().empty());  // timing off
  const std::vector<std::string> names = DebugImageNames("f1", /*with_detections=*/true);
  EXPECT_EQ(names, (std::vector<std::string>{"f1.2_colour_lookup.png", "f1.4_regions.png",
                                             "f1.5_blobs_to_mm.png", "f1.6_detect.png"}));
  for (const std::string& name : names) {
    const camera::Image debug = ReadFrame(dir + "/debug/" + name);
    EXPECT_EQ(debug.width_px, 400) << name;
    EXPECT_EQ(debug.height_px, 300) << name;
  }
  EXPECT_EQ(DebugImageNames("f1", false).size(), 3u);
}

TEST(FrameDetector, ResultsWriterCsvAndJson) {
  const detect::DetectorConfig config = formats::LoadDetectorSettings(kSettings);
  const camera::Image image = RenderRobots(config, {{Pose2{10, 20, 0.25}, 0}}, TwoMmPerPixel());
  FrameDetector frames(Classes(), TwoMmPerPixel(), config, {});
  FrameResultsWriter detections(frames, /*blobs=*/false), blobs(frames, /*blobs=*/true);
  const FrameResult& r = frames.Detect(image, "a.png");
  detections.Add(r);
  blobs.Add(r);
  const std::string csv = detections.Csv();
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "frame,pattern,team,id,status,x_mm,y_mm,theta_rad,residual_mm2,confidence");
  EXPECT_NE(csv.find("\na.png,ssl-standard,blue,0,ok,"), std::string::npos) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 2);
  const std::string blob_csv = blobs.Csv();
  EXPECT_EQ(std::count(blob_csv.begin(), blob_csv.end(), '\n'), 7);  // header + 6 blobs
  EXPECT_NE(blobs.Json().find("\"colour\": \"grass\""), std::string::npos);
  EXPECT_NE(detections.Json().find("\"status\": \"ok\""), std::string::npos);
}

TEST(FrameDetector, OptionsAreChecked) {
  FrameDetectorOptions options;
  EXPECT_TRUE(Check(options).empty());
  options.raw_width_px = 63;
  options.raw_height_px = 48;
  EXPECT_INPUT_ERROR(Validate(options),
                     "raw frame size 63x48; expected a positive even width and a positive height");
  options.raw_width_px = 64;
  options.segmenter.min_area_px = 0;
  EXPECT_INPUT_ERROR(FrameDetector(Classes(), TwoMmPerPixel(), std::nullopt, options),
                     "min_area_px is 0; expected an integer >= 1");
}

// A settings file's [frame] table reaches the detector through the front end: its missing-patch
// policy replaces the [detector] one, its edge loss shrinks the lower area bound (2 mm per px:
// a 1 px rim of the ssl-standard 20 mm dots leaves (18/20)^2, 2 px (16/20)^2).
TEST(FrameDetector, FrameSettingsReachTheDetector) {
  const detect::DetectorConfig config = formats::LoadDetectorSettings(kSettings);
  ASSERT_EQ(config.options.missing_patch, detect::MissingPatchPolicy::kReject);
  FrameDetectorOptions options;
  FrameDetector as_is(Classes(), TwoMmPerPixel(), config, options);
  EXPECT_EQ(as_is.detector().config().options.missing_patch, detect::MissingPatchPolicy::kReject);
  const double r = config.patterns[0].pattern.patches[1].radius_mm;
  EXPECT_NEAR(as_is.detector().config().options.area_ratio_min,
              0.4 * (r - 2.0) * (r - 2.0) / (r * r), 1e-12);

  ApplyFrameSettings(
      formats::ParseFrameSettings("[frame]\nedge_loss_px = 2\nmissing_patch = \"fit\"\n", "s.toml"),
      &options);
  EXPECT_EQ(options.edge_loss_px, 2.0);
  FrameDetector adapted(Classes(), TwoMmPerPixel(), config, options);
  EXPECT_EQ(adapted.detector().config().options.missing_patch, detect::MissingPatchPolicy::kFit);
  EXPECT_NEAR(adapted.detector().config().options.area_ratio_min,
              0.4 * (r - 4.0) * (r - 4.0) / (r * r), 1e-12);

  // An empty [frame] changes nothing; the shipped file's makes frames fit.
  FrameDetectorOptions unchanged;
  ApplyFrameSettings(detect::FrameSettings{}, &unchanged);
  EXPECT_EQ(unchanged.edge_loss_px, 1.0);
  EXPECT_FALSE(unchanged.missing_patch.has_value());
  ApplyFrameSettings(formats::LoadFrameSettings(kSettings), &unchanged);
  EXPECT_EQ(unchanged.missing_patch, detect::MissingPatchPolicy::kFit);

  options.edge_loss_px = -0.5;
  EXPECT_INPUT_ERROR(FrameDetector(Classes(), TwoMmPerPixel(), config, options),
                     "edge_loss_px is -0.5; expected a number in [0, 10] (px)");
  options.edge_loss_px = 1.0;
  ApplyFrameSettings(formats::ParseFrameSettings("[frame]\nlight_luma = 76\n", "s.toml"), &options);
  EXPECT_EQ(options.light_luma, 76.0);
  options.light_luma = -1.0;
  EXPECT_INPUT_ERROR(FrameDetector(Classes(), TwoMmPerPixel(), config, options),
                     "light_luma is -1; expected in (0, 255]");
}

// [frame] binning: a frame twice the size, each pixel a 2 x 2 block, with its camera resized to
// match, is binned back to the frame itself and detected exactly alike, its blobs reported in the
// frame's own pixels; frames must have the calibration's own size, not the binned one.
TEST(FrameDetector, BinnedFramesAreDetectedAsTheFramesTheyBinTo) {
  const detect::DetectorConfig config = formats::LoadDetectorSettings(kSettings);
  const std::vector<Robot> robots = {{Pose2{-150, 50, 0.5}, 3}, {Pose2{180, -40, -2.0}, 12}};
  const camera::Image image = RenderRobots(config, robots, TwoMmPerPixel());
  const camera::Image doubled = testing::BlockUpsampled(image, 2);
  FrameDetectorOptions options;
  ApplyFrameSettings(formats::ParseFrameSettings("[frame]\nbinning = 2\n", "s.toml"), &options);
  EXPECT_EQ(options.binning, 2);
  FrameDetector binned(Classes(), TwoMmPerPixel().Resized(2.0, 800, 600), config, options);
  FrameDetector plain(Classes(), TwoMmPerPixel(), config, FrameDetectorOptions{});
  const std::vector<detect::Detection> expected = plain.Detect(image, "robots").detections;
  const FrameResult& r = binned.Detect(doubled, "doubled");
  ASSERT_EQ(expected.size(), 2u);
  ASSERT_EQ(r.detections.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(r.detections[i].id, expected[i].id);
    EXPECT_NEAR(r.detections[i].pose.x_mm, expected[i].pose.x_mm, 1e-9);
    EXPECT_NEAR(r.detections[i].pose.y_mm, expected[i].pose.y_mm, 1e-9);
    EXPECT_NEAR(r.detections[i].pose.theta_rad, expected[i].pose.theta_rad, 1e-9);
  }
  // The blobs' pixels are the frame's own: as the doubled frame segmented without binning.
  FrameDetector whole(Classes(), TwoMmPerPixel().Resized(2.0, 800, 600), config, {});
  const std::vector<Region> binned_regions = r.blob_regions;
  const std::vector<Region>& regions = whole.Detect(doubled, "doubled").blob_regions;
  ASSERT_EQ(binned_regions.size(), regions.size());
  ASSERT_GE(regions.size(), 8u);
  for (size_t i = 0; i < regions.size(); ++i) {
    EXPECT_EQ(binned_regions[i].area_px, regions[i].area_px);
    EXPECT_EQ(binned_regions[i].x_min, regions[i].x_min);
    EXPECT_EQ(binned_regions[i].y_max, regions[i].y_max);
    EXPECT_NEAR(binned_regions[i].centroid_px.x(), regions[i].centroid_px.x(), 1e-9);
    EXPECT_NEAR(binned_regions[i].centroid_px.y(), regions[i].centroid_px.y(), 1e-9);
  }
  EXPECT_INPUT_ERROR(binned.Detect(image, "small"),
                     "small: image is 400x300; expected 800x600 as in c.toml");
  options.binning = 9;
  EXPECT_INPUT_ERROR(FrameDetector(Classes(), TwoMmPerPixel(), config, options),
                     "binning is 9; expected an integer in [1, 8]");
}

// A frame's light is its median luma, in either pixel format: the carpet's where it covers most of
// the view, whatever the few bright or dark pixels do.
TEST(FrameDetector, FrameLightIsTheMedianLuma) {
  camera::Image image = camera::Image::Rgb(64, 48);
  for (size_t i = 0; i < image.data.size(); i += 3) {
    image.data[i] = 40, image.data[i + 1] = 100, image.data[i + 2] = 50;  // luma 76
  }
  for (int y = 0; y < 12; ++y) std::fill_n(image.data.begin() + y * image.RowBytes(), 96, 255);
  EXPECT_EQ(FrameLight(image), 76.0);
  EXPECT_EQ(FrameLight(camera::ToUyvy(image)), 76.0);
}

// A missing-patch fit is checked where its missing patch should be (MissingPatchLook). Four
// rendered ssl-standard robots (2 mm per px), the front-left dot of three of them changed: painted
// orange (a palette colour no ID dot has: a fit there is not this pattern -> dropped), painted the
// background grey (unseen, as an occluded patch or one the light does not show -> kept, nothing
// in its footprint), shrunk to radius 7 mm (a pink blob below the area range, as a patch merged
// or cut up -> kept, its own colour in the footprint); the fourth intact.
TEST(FrameDetector, MissingPatchFitsAreCheckedWhereThePatchShouldBe) {
  const detect::DetectorConfig config = formats::LoadDetectorSettings(kSettings);
  const detect::DetectorPattern& dp = config.patterns[0];
  const std::vector<int> slots = detect::IdSlots(dp.pattern);
  struct Change {
    Pose2 pose;
    int entry;
    render::Rgb dot_rgb;
    double dot_radius_mm;  // 0: unchanged
  };
  const render::Rgb kOrange{255, 140, 0}, kGrey{70, 70, 70};
  const std::vector<Change> robots = {{Pose2{-200, 120, 0.3}, 3, kOrange, 20.0},
                                      {Pose2{200, 120, -1.0}, 5, kGrey, 20.0},
                                      {Pose2{-200, -130, 2.0}, 9, {}, 7.0},
                                      {Pose2{200, -130, 0.0}, 12, {}, 0.0}};
  std::vector<render::Disc> discs;
  for (const Change& robot : robots) {
    for (int i = 0; i < dp.pattern.size(); ++i) {
      const Patch& patch = dp.pattern.patches[i];
      render::Rgb rgb = {20, 40, 230};  // blue key
      double radius = patch.radius_mm;
      if (patch.role == PatchRole::kId) {
        const int slot = static_cast<int>(std::find(slots.begin(), slots.end(), i) - slots.begin());
        const std::string& colour =
            dp.codebook.colours[dp.codebook.entries[robot.entry].colour[slot]];
        rgb = colour == "pink" ? render::Rgb{250, 60, 220} : render::Rgb{40, 230, 60};
        if (i == 1 && robot.dot_radius_mm == 20.0) rgb = robot.dot_rgb;
        if (i == 1 && robot.dot_radius_mm > 0.0) radius = robot.dot_radius_mm;
      }
      discs.push_back({robot.pose.Apply(patch.position_mm), radius, rgb});
    }
  }
  const camera::Image image =
      render::RenderWorldDiscs(400, 300, TwoMmPerPixel().camera, 0.0, kGrey, discs);
  Thresholds thresholds = Classes();
  thresholds.classes.push_back(
      formats::ParseThresholdsToml("space = \"rgb\"\n[[class]]\nname = \"orange\"\n"
                                   "r = [220, 255]\ng = [100, 180]\nb = [0, 60]\n",
                                   "t.toml")
          .classes[0]);
  FrameDetectorOptions options;
  options.missing_patch = detect::MissingPatchPolicy::kFit;
  options.explain = true;
  FrameDetector frames(thresholds, TwoMmPerPixel(), config, options);
  const FrameResult& r = frames.Detect(image, "robots");

  ASSERT_EQ(r.missing_patch_looks.size(), 3u);
  for (const MissingPatchLook& look : r.missing_patch_looks) {
    EXPECT_EQ(look.detection.missing_patch, 1);
    // The dot's footprint: pi 20^2 mm^2 at 4 mm^2 per px, ~314 px.
    EXPECT_NEAR(look.pixels, std::numbers::pi * 100.0, 20.0);
    const double x = look.detection.pose.x_mm, y = look.detection.pose.y_mm;
    if (x < 0 && y > 0) {  // orange: nearly all other colours
      EXPECT_GT(look.other, 0.9 * look.pixels);
      EXPECT_EQ(look.own, 0);
      EXPECT_TRUE(look.rejected);
    } else if (x > 0) {  // grey: nothing classified
      EXPECT_EQ(look.own + look.other, 0);
      EXPECT_FALSE(look.rejected);
    } else {  // shrunk: (7/20)^2 = 12% its colour
      EXPECT_NEAR(static_cast<double>(look.own) / look.pixels, 0.1225, 0.04);
      EXPECT_EQ(look.other, 0);
      EXPECT_FALSE(look.rejected);
    }
  }
  // The intact robot with its ID, the grey and shrunk ones fitted on the other four patches; the
  // orange one is no detection, and --explain says why.
  ASSERT_EQ(r.detections.size(), 3u);
  int intact = 0;
  for (const detect::Detection& d : r.detections) {
    EXPECT_GT(std::hypot(d.pose.x_mm + 200, d.pose.y_mm - 120), 100.0);
    if (d.status == detect::DetectionStatus::kOk) {
      ++intact;
      EXPECT_EQ(d.id, dp.codebook.entries[12].id);
    }
  }
  EXPECT_EQ(intact, 1);
  const std::string text = ExplanationText(r, frames);
  EXPECT_NE(text.find("missing_patch_colour: fitted without patch 1"), std::string::npos) << text;
  EXPECT_NE(text.find("; missing patch 1 shows 0% its colours, 0% other colours of"),
            std::string::npos)
      << text;
}

}  // namespace
}  // namespace patlab::vision

namespace patlab::vision {
namespace {

// A thresholds class "magenta" where the detector palette says "pink" drops
// every pink-dotted robot; the front end says so, naming both sides.
TEST(FrameDetector, WarnsWhenClassNamesAndPaletteDisagree) {
  const std::string golden = std::string(PATLAB_SOURCE_DIR) + "/tests/data/golden/";
  Thresholds t = formats::LoadThresholds(golden + "ssl-frame.thresholds.toml");
  t.source = "t.toml";
  t.classes[static_cast<size_t>(t.Find("pink"))].name = "magenta";
  const detect::DetectorConfig config =
      formats::LoadDetectorSettings(golden + "ssl-frame.detector.toml");
  EXPECT_EQ(PaletteWarnings(t, config),
            (std::vector<std::string>{
                "t.toml: class \"magenta\" is no colour of the detector's palette; its blobs are "
                "not shown to the detector",
                "detector colour \"pink\" is used by a pattern but no class of t.toml has that "
                "name; no blob can have it, so patterns needing it are not detected"}));
  t.classes[static_cast<size_t>(t.Find("magenta"))].name = "pink";
  EXPECT_TRUE(PaletteWarnings(t, config).empty());
}

}  // namespace
}  // namespace patlab::vision
