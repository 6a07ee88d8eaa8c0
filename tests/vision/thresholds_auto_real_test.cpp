// patlab thresholds --auto on the two shared real frames (../shared/frames, GPL-3.0, read from
// there and skipped when absent): each frame fitted on itself with no labels, the classes its
// detector settings' palette, then detected with those settings and its calibration, and the
// detections scored against the robots counted by eye.
//
// How the robots were counted: the frames were looked at at full size; a robot is a robot top
// whose pattern the detector settings describe, fully inside the image. Its position is the
// centre of its key (team-colour) patch in pixels, read off the image to a few pixels. Its ID is
// the codebook entry of the colours seen on it (for the VSS frame: two-circles cyan = 0, red = 1,
// green = 2; rect-squares pink + aqua = 1, pink + red = 2); -1 where the ID patches cannot be
// told apart by eye (the SSL frame's far robots), scored by team only.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "../frame_test_util.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/io/colour_vocabulary.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"
#include "patlab/vision/thresholds_auto.h"

namespace patlab::vision {
namespace {

struct ExpectedRobot {
  std::string team;
  int id;  // -1: by team only
  double x_px, y_px;
};

struct Score {
  int found = 0;      // expected robots with a detection of their team (and ID) within 20 px
  int false_ids = 0;  // detections with an ID that match no expected robot
};

Score FitAndScore(const std::string& frame, const std::string& settings,
                  const std::string& calibration, const std::vector<ExpectedRobot>& expected) {
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  const Image image = ReadFrame(testing::SharedFrames() + "/" + frame);
  const detect::DetectorConfig config = detect::LoadDetectorSettings(data + settings);
  const AutoThresholdsFit fit =
      FitThresholdsAuto({&image}, config.palette, io::DefaultColourVocabulary(), {});
  FrameDetector frames(fit.thresholds, LoadCalibration(data + calibration), config, {});
  const FrameResult& result = frames.Detect(image, frame);
  const auto& palette = frames.detector().config().palette;
  std::vector<bool> used(result.detections.size(), false);
  Score score;
  for (const ExpectedRobot& robot : expected) {
    for (size_t i = 0; i < result.detections.size(); ++i) {
      const detect::Detection& d = result.detections[i];
      const int key = config.patterns[static_cast<size_t>(d.pattern)].pattern.key_index;
      const int blob = d.blob[static_cast<size_t>(key)];
      if (used[i] || blob < 0 || palette[static_cast<size_t>(d.team_colour)] != robot.team) {
        continue;
      }
      const Vec2 px =
          result.blob_regions[static_cast<size_t>(result.detector_blob_source[blob])].centroid_px;
      if (std::hypot(px.x() - robot.x_px, px.y() - robot.y_px) > 20.0) continue;
      if (robot.id >= 0 && d.id != robot.id) continue;
      used[i] = true;
      ++score.found;
      break;
    }
  }
  for (size_t i = 0; i < result.detections.size(); ++i) {
    if (!used[i] && result.detections[i].id >= 0) ++score.false_ids;
  }
  return score;
}

bool HaveFrames() {
  return std::filesystem::exists(testing::SharedFrames() + "/vss-test-frame.png");
}

TEST(ThresholdsAutoReal, VssFrameFittedOnItself) {
  if (!HaveFrames()) GTEST_SKIP() << "no shared frames at " << testing::SharedFrames();
  const Score s = FitAndScore("vss-test-frame.png", "vss.detector.toml", "vss.calibration.toml",
                              {{"blue", 1, 145, 28},
                               {"light-green", 2, 540, 598},
                               {"light-green", 0, 133, 413},
                               {"light-green", 1, 276, 403},
                               {"light-green", 2, 209, 490}});
  EXPECT_EQ(s.found, 5);
  EXPECT_EQ(s.false_ids, 0);
}

TEST(ThresholdsAutoReal, SslFrameFittedOnItself) {
  if (!HaveFrames()) GTEST_SKIP() << "no shared frames at " << testing::SharedFrames();
  const Score s =
      FitAndScore("ssl-field-2008.jpg", "ssl-2008.detector.toml", "ssl-2008.calibration.toml",
                  {{"yellow", 5, 557, 200},
                   {"yellow", -1, 345, 60},
                   {"yellow", -1, 258, 82},
                   {"blue", 6, 434, 557},
                   {"blue", 15, 478, 562}});
  EXPECT_EQ(s.found, 5);
  EXPECT_EQ(s.false_ids, 0);
}

}  // namespace
}  // namespace patlab::vision
