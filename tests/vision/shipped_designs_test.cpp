// The shipped detector settings of the common real designs (settings/vss*.detector.toml,
// settings/ssl-standard.detector.toml): each loads, carries no [detector] tolerances (setup
// chooses them), and every VSS design is found with its team and ID from exact blobs at random
// poses through the family settings (vss.detector) -- and the real VSS frame of ../shared/frames
// (skipped when absent), with the hand thresholds and calibration of tests/data/vision, gives its
// five robots with the team and ID of the real-frame tests; the SSL standard sheet its 16 IDs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "../frame_test_util.h"
#include "../test_util.h"
#include "patlab/core/rng.h"
#include "patlab/detect/codebook.h"
#include "patlab/detect/detector.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"

namespace patlab::vision {
namespace {

const std::string kSettingsDir = std::string(PATLAB_SOURCE_DIR) + "/settings/";

TEST(ShippedDesigns, EverySettingsFileLoadsWithoutTolerances) {
  for (const char* name : {"vss", "vss-two-circles", "vss-rect-squares", "vss-two-rectangles",
                           "vss-square-diagonal", "ssl-standard"}) {
    SCOPED_TRACE(name);
    const std::string path = kSettingsDir + name + ".detector.toml";
    const detect::DetectorConfig config = formats::LoadDetectorSettings(path);
    EXPECT_FALSE(config.patterns.empty());
    EXPECT_EQ(patlab::testing::ReadFile(path).find("\n[detector]"), std::string::npos);
    const detect::DetectorOptions defaults;
    EXPECT_EQ(config.options.patch_sigma_mm, defaults.patch_sigma_mm);
    EXPECT_EQ(config.options.reach_margin_mm, defaults.reach_margin_mm);
    for (const detect::DetectorPattern& p : config.patterns) {
      EXPECT_EQ(p.key_colours, (std::vector<std::string>{"blue", "yellow"}));
    }
  }
  // Each VSS codebook file is every colouring GenerateCodebook finds for the pattern's symmetry,
  // with the same numbers (LoadDetectorSettings has checked it against the pattern's rotations).
  for (const detect::DetectorPattern& p :
       formats::LoadDetectorSettings(kSettingsDir + "vss.detector.toml").patterns) {
    SCOPED_TRACE(p.pattern.name);
    const detect::Codebook generated = detect::GenerateCodebook(
        p.pattern, detect::FindSymmetry(p.pattern, p.symmetry_tolerance_mm), p.codebook.colours);
    ASSERT_EQ(generated.entries.size(), p.codebook.entries.size());
    for (size_t i = 0; i < generated.entries.size(); ++i) {
      EXPECT_EQ(generated.entries[i].id, p.codebook.entries[i].id);
      EXPECT_EQ(generated.entries[i].colour, p.codebook.entries[i].colour);
    }
  }
  EXPECT_EQ(formats::LoadDetectorSettings(kSettingsDir + "ssl-standard.detector.toml")
                .patterns.at(0)
                .codebook.entries.size(),
            16u);
}

// Every design of the family, every ID, both teams, at random poses: exact blobs (each patch's
// centre and area) -> the right pattern, team and ID, and nothing else.
TEST(ShippedDesigns, FamilySettingsFindEveryDesignTeamAndId) {
  const detect::DetectorConfig config =
      formats::LoadDetectorSettings(kSettingsDir + "vss.detector.toml");
  detect::Detector detector(config);
  RandomStream rng(17, 0, 0);
  for (size_t p = 0; p < config.patterns.size(); ++p) {
    const detect::DetectorPattern& dp = config.patterns[p];
    const std::vector<int> slots = detect::IdSlots(dp.pattern);
    for (const detect::CodebookEntry& entry : dp.codebook.entries) {
      for (int team = 0; team < 2; ++team) {
        const Pose2 pose{rng.Uniform(-700, 700), rng.Uniform(-600, 600), rng.Uniform(-3.1, 3.1)};
        std::vector<detect::Blob> blobs;
        for (int i = 0; i < dp.pattern.size(); ++i) {
          const Patch& patch = dp.pattern.patches[static_cast<size_t>(i)];
          std::string colour = dp.key_colours[static_cast<size_t>(team)];
          if (patch.role == PatchRole::kId) {
            const size_t slot = std::find(slots.begin(), slots.end(), i) - slots.begin();
            colour = dp.codebook.colours[static_cast<size_t>(entry.colour[slot])];
          }
          blobs.push_back(
              {pose.Apply(patch.position_mm), detector.ColourLabel(colour), patch.Area()});
        }
        std::vector<detect::Detection> detections;
        detector.Detect(blobs, &detections);
        SCOPED_TRACE(dp.pattern.name + " id " + std::to_string(entry.id));
        ASSERT_EQ(detections.size(), 1u);
        EXPECT_EQ(detections[0].pattern, static_cast<int>(p));
        EXPECT_EQ(config.palette[static_cast<size_t>(detections[0].team_colour)],
                  dp.key_colours[static_cast<size_t>(team)]);
        EXPECT_EQ(detections[0].id, entry.id);
        EXPECT_NEAR(detections[0].pose.x_mm, pose.x_mm, 1e-6);
      }
    }
  }
}

// The real VSS frame with the family settings and the hand thresholds, whose class "lime" is the
// yellow team under that light (the VSS rules' team colours are blue and yellow): renamed
// yellow here. The truth is that of RealFrames.VssTestFrameFindsAllFiveRobots.
TEST(ShippedDesigns, RealVssFrameFindsItsFiveRobotsWithTheFamilySettings) {
  const std::string frame = testing::SharedFrames() + "/vss-test-frame.png";
  if (!std::filesystem::exists(frame)) GTEST_SKIP() << "no shared frames";
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  patlab::testing::TempDir dir;
  const std::string thresholds = dir.Path("vss.colors.txt");
  std::ofstream(thresholds) << std::regex_replace(
      patlab::testing::ReadFile(data + "vss.colors.txt"), std::regex(" lime\n"), " yellow\n");
  FrameDetector frames(
      formats::LoadThresholds(thresholds), formats::LoadCalibration(data + "vss.calibration.toml"),
      formats::LoadDetectorSettings(kSettingsDir + "vss.detector.toml"), FrameDetectorOptions{});
  const FrameResult& r = frames.Detect(ReadFrame(frame), "vss-test-frame.png");
  struct Robot {
    std::string pattern, team;
    int id;
    double x_mm, y_mm;
  };
  const std::vector<Robot> truth = {{"vss-rect-squares", "yellow", 2, 375.64, -634.29},
                                    {"vss-rect-squares", "blue", 1, -470.30, 597.65},
                                    {"vss-two-circles", "yellow", 0, -489.50, -231.36},
                                    {"vss-two-circles", "yellow", 1, -186.23, -206.61},
                                    {"vss-two-circles", "yellow", 2, -327.28, -393.77}};
  const detect::DetectorConfig& config = frames.detector().config();
  ASSERT_EQ(r.detections.size(), truth.size());
  for (const Robot& robot : truth) {
    int found = 0;
    for (const detect::Detection& d : r.detections) {
      found += static_cast<int>(
          config.patterns[static_cast<size_t>(d.pattern)].pattern.name == robot.pattern &&
          config.palette[static_cast<size_t>(d.team_colour)] == robot.team && d.id == robot.id &&
          std::hypot(d.pose.x_mm - robot.x_mm, d.pose.y_mm - robot.y_mm) < 10.0);
    }
    EXPECT_EQ(found, 1) << robot.pattern << " " << robot.team << " " << robot.id;
  }
}

// The SSL standard 16-ID sheet of ../shared/frames with the shipped ssl-standard settings (and the
// sheet's thresholds and calibration of tests/data/vision): every ID 0..15 once, blue.
TEST(ShippedDesigns, SslStandardSheetGivesItsSixteenIds) {
  const std::string frame = testing::SharedFrames() + "/ssl-standard-pattern-2010-16ids.png";
  if (!std::filesystem::exists(frame)) GTEST_SKIP() << "no shared frames";
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  FrameDetector frames(formats::LoadThresholds(data + "ssl-standard-sheet.thresholds.toml"),
                       formats::LoadCalibration(data + "ssl-standard-sheet.calibration.toml"),
                       formats::LoadDetectorSettings(kSettingsDir + "ssl-standard.detector.toml"),
                       FrameDetectorOptions{});
  const FrameResult& r = frames.Detect(ReadFrame(frame), "sheet");
  std::vector<int> ids;
  for (const detect::Detection& d : r.detections) {
    EXPECT_EQ(frames.detector().config().palette[static_cast<size_t>(d.team_colour)], "blue");
    ids.push_back(d.id);
  }
  std::sort(ids.begin(), ids.end());
  std::vector<int> expected(16);
  for (int i = 0; i < 16; ++i) expected[static_cast<size_t>(i)] = i;
  EXPECT_EQ(ids, expected);
}

}  // namespace
}  // namespace patlab::vision
