// The shared real frames (../shared/frames, not in the repository) through stages 2-6 with the
// thresholds, calibrations, patterns and detector settings of tests/data/vision: exactly the
// detections docs/detect.md reports (results/vision/*.detections.csv). Skipped when the frames are
// absent.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../frame_test_util.h"
#include "patlab/camera/image.h"
#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/frame_detector.h"
#include "patlab/vision/frame_io.h"

namespace patlab::vision {
namespace {

struct Expected {
  std::string pattern, team;
  int id;
  detect::DetectionStatus status;
  int missing_patch;  // pattern patch index, -1 for none
  double x_mm, y_mm, theta_rad;
};

struct FrameRun {
  std::vector<detect::Detection> detections;
  std::vector<detect::Blob> blobs;  // in the detector's palette
  std::vector<std::string> pattern_names, palette;
};

// Stages 2-6 as patlab detect runs them (FrameDetector: blob classes matched to the palette by
// name). `uyvy`: the frame converted to UYVY 4:2:2 first (camera::ToUyvy), as a camera would
// send it.
FrameRun DetectFrame(const std::string& frame, const std::string& thresholds,
                     const std::string& calibration, const std::string& settings,
                     bool uyvy = false) {
  const std::string data = std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/";
  FrameDetector frames(formats::LoadThresholds(data + thresholds),
                       formats::LoadCalibration(data + calibration),
                       formats::LoadDetectorSettings(data + settings), FrameDetectorOptions{});
  camera::Image image = ReadFrame(testing::SharedFrames() + "/" + frame);
  if (uyvy) image = camera::ToUyvy(image);
  const FrameResult& result = frames.Detect(image, frame);
  FrameRun run;
  run.detections = result.detections;
  run.blobs = result.detector_blobs;
  for (const auto& p : frames.detector().config().patterns) {
    run.pattern_names.push_back(p.pattern.name);
  }
  run.palette = frames.detector().config().palette;
  return run;
}

void ExpectDetections(const FrameRun& run, const std::vector<Expected>& expected) {
  ASSERT_EQ(run.detections.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    const detect::Detection& d = run.detections[i];
    const Expected& e = expected[i];
    SCOPED_TRACE("detection " + std::to_string(i));
    EXPECT_EQ(run.pattern_names[static_cast<size_t>(d.pattern)], e.pattern);
    EXPECT_EQ(run.palette[static_cast<size_t>(d.team_colour)], e.team);
    EXPECT_EQ(d.id, e.id);
    EXPECT_EQ(d.status, e.status);
    EXPECT_EQ(d.missing_patch, e.missing_patch);
    // The CSV's 2-decimal positions and 4-decimal angles: the pipeline is deterministic, so
    // only the rounding of those numbers is allowed for.
    EXPECT_NEAR(d.pose.x_mm, e.x_mm, 0.006);
    EXPECT_NEAR(d.pose.y_mm, e.y_mm, 0.006);
    EXPECT_NEAR(d.pose.theta_rad, e.theta_rad, 6e-5);
  }
}

bool HaveFrames() { return std::filesystem::exists(testing::SharedFrames()); }

constexpr auto kOk = detect::DetectionStatus::kOk;
constexpr auto kMissing = detect::DetectionStatus::kMissingPatch;

// Five robots on the field: the yellow one at (557, 200) px with all sectors (ID 5 = left pink,
// back green, right white), the two yellow ones at the top without their dark green sector
// (ID unknown), the two blue ones at the bottom without their black sector (merged with the
// robot's shadow). The robot held at the left edge is missed: its centre patch is covered.
TEST(RealFrames, SslField2008FindsTheFiveRobotsOnTheField) {
  if (!HaveFrames()) GTEST_SKIP() << "no shared frames at " << testing::SharedFrames();
  const FrameRun run = DetectFrame("ssl-field-2008.jpg", "ssl-2008.thresholds.toml",
                                   "ssl-2008.calibration.toml", "ssl-2008.detector.toml");
  ExpectDetections(run, {
                            {"kiks-sectors", "yellow", 5, kOk, -1, 1618.02, -860.93, -2.6837},
                            {"kiks-sectors", "yellow", -1, kMissing, 2, 2246.65, 542.12, -3.0670},
                            {"kiks-sectors", "yellow", -1, kMissing, 3, 2341.24, 128.57, 2.5129},
                            {"kiks-sectors", "blue", 6, kMissing, 4, -109.35, -231.62, 0.7296},
                            {"kiks-sectors", "blue", 15, kMissing, 4, -150.71, -447.00, 0.6954},
                        });
}

// The same frame as UYVY 4:2:2 gives the same five detections (pattern, team, ID, status,
// missing patch). 4:2:2 shares U, V between pixel pairs, so a pair straddling a sector's left or
// right edge may leave the colour class: a region edge moves by at most one pixel (~5.5 mm here)
// and its centroid by at most half that, so poses agree with the RGB frame's to 3 mm and
// 3 mm / 50 mm (a sector's distance from the key) = 0.06 rad. The smallest sector (robot at
// (478, 564) px, green) keeps 15 of its 20 px: ssl-2008.detector.toml's area_ratio_min admits it.
TEST(RealFrames, SslField2008AsUyvyGivesTheSameDetections) {
  if (!HaveFrames()) GTEST_SKIP() << "no shared frames at " << testing::SharedFrames();
  const FrameRun rgb = DetectFrame("ssl-field-2008.jpg", "ssl-2008.thresholds.toml",
                                   "ssl-2008.calibration.toml", "ssl-2008.detector.toml");
  const FrameRun uyvy =
      DetectFrame("ssl-field-2008.jpg", "ssl-2008.thresholds.toml", "ssl-2008.calibration.toml",
                  "ssl-2008.detector.toml", /*uyvy=*/true);
  ASSERT_EQ(rgb.detections.size(), 5u);
  ASSERT_EQ(uyvy.detections.size(), rgb.detections.size());
  for (size_t i = 0; i < rgb.detections.size(); ++i) {
    const detect::Detection& a = rgb.detections[i];
    const detect::Detection& b = uyvy.detections[i];
    SCOPED_TRACE("detection " + std::to_string(i));
    EXPECT_EQ(b.pattern, a.pattern);
    EXPECT_EQ(b.team_colour, a.team_colour);
    EXPECT_EQ(b.id, a.id);
    EXPECT_EQ(b.status, a.status);
    EXPECT_EQ(b.missing_patch, a.missing_patch);
    EXPECT_NEAR(b.pose.x_mm, a.pose.x_mm, 3.0);
    EXPECT_NEAR(b.pose.y_mm, a.pose.y_mm, 3.0);
    EXPECT_NEAR(b.pose.theta_rad, a.pose.theta_rad, 0.06);
  }
}

// All five VSS robots: three round-patch robots of the lime team (IDs cyan 0, red 1, green 2)
// and two square-patch robots (lime: pink/red = ID 2; blue: pink/aqua = ID 1).
TEST(RealFrames, VssTestFrameFindsAllFiveRobots) {
  if (!HaveFrames()) GTEST_SKIP() << "no shared frames at " << testing::SharedFrames();
  const FrameRun run = DetectFrame("vss-test-frame.png", "vss.colors.txt", "vss.calibration.toml",
                                   "vss.detector.toml");
  ExpectDetections(run,
                   {
                       {"vss-rect-squares", "light-green", 2, kOk, -1, 375.64, -634.29, 1.9270},
                       {"vss-rect-squares", "blue", 1, kOk, -1, -470.30, 597.65, 2.4197},
                       {"vss-two-circles", "light-green", 0, kOk, -1, -489.50, -231.36, 0.6163},
                       {"vss-two-circles", "light-green", 1, kOk, -1, -186.23, -206.61, 1.5032},
                       {"vss-two-circles", "light-green", 2, kOk, -1, -327.28, -393.77, -0.0275},
                   });
}

// The CSV results committed in results/vision are what the detector gives now
// (docs/paper-reproduction.md shows them): same number of detections per frame.
TEST(RealFrames, CommittedResultsHaveTheSameCounts) {
  for (const auto& [file, count] : std::vector<std::pair<std::string, int>>{
           {"ssl-field-2008.detections.csv", 5}, {"vss-test-frame.detections.csv", 5}}) {
    std::ifstream in(std::string(PATLAB_SOURCE_DIR) + "/results/vision/" + file);
    ASSERT_TRUE(in) << file;
    std::string line;
    int rows = -1;  // the header
    while (std::getline(in, line)) ++rows;
    EXPECT_EQ(rows, count) << file;
  }
}

}  // namespace
}  // namespace patlab::vision
