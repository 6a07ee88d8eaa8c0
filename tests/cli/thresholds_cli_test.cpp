// patlab thresholds end to end, and the detect flags that go with it (--explain, the palette
// warnings), the binary run as a user would.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "../test_util.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/color_lut.h"

namespace patlab::cli {
namespace {

using testing::RunCommand;

const std::string kBinary = PATLAB_BINARY;
const std::string kData = std::string(PATLAB_SOURCE_DIR) + "/tests/data/";
const std::string kGolden = kData + "golden/ssl-frame.";

long CountSubstrings(const std::string& text, const std::string& part) {
  long n = 0;
  for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// The golden frame's labels -> thresholds -> the golden frame's robots, with the report.
TEST(ThresholdsCli, FitsTheGoldenFrameLabelsAndDetectsWithThem) {
  testing::TempDir dir;
  const std::string t = dir.Path("t/thresholds.toml");
  const auto r =
      RunCommand(kBinary + " thresholds " + kData + "vision/golden-frame.labels.toml -o " +
                 dir.Path("t") + " -s " + kGolden + "detector.toml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\npink               40  "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no overlapping classes"), std::string::npos) << r.out;
  EXPECT_EQ(formats::LoadThresholds(t).classes.size(), 5u);
  const auto d = RunCommand(kBinary + " detect " + kGolden + "png -t " + t + " -c " + kGolden +
                            "calibration.toml -s " + kGolden + "detector.toml --explain");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_EQ(std::count(d.out.begin(), d.out.end(), '\n'), 11);  // header + 10 robots
  EXPECT_EQ(CountSubstrings(d.err, ": detected, id "), 10) << d.err;
}

// A silent mismatch: "magenta" for the palette's "pink" warns on stderr, and --explain
// says why each robot with a pink dot is missed (too few neighbours).
TEST(ThresholdsCli, DetectWarnsAboutNamesAndExplainsTheMisses) {
  testing::TempDir dir;
  std::string text = testing::ReadFile(kGolden + "thresholds.toml");
  text.replace(text.find("name = \"pink\""), 13, "name = \"magenta\"");
  const std::string t = dir.Write("t.toml", text);
  const auto d = RunCommand(kBinary + " detect " + kGolden + "png -t " + t + " -c " + kGolden +
                            "calibration.toml -s " + kGolden + "detector.toml --explain --debug " +
                            dir.Path("debug"));
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_NE(d.err.find("patlab detect: warning: " + t +
                       ": class \"magenta\" is no colour of the detector's palette; its blobs "
                       "are not shown to the detector\n"),
            std::string::npos)
      << d.err;
  EXPECT_NE(d.err.find("patlab detect: warning: detector colour \"pink\" is used by a pattern "
                       "but no class of " +
                       t + " has that name"),
            std::string::npos);
  // Only yellow 8 (GGGG: no pink dot) is still found; the nine others lack pink neighbours.
  EXPECT_EQ(CountSubstrings(d.err, ": detected, id 8 (ok)"), 1) << d.err;
  EXPECT_EQ(CountSubstrings(d.err, ": few_neighbours: "), 9) << d.err;
  EXPECT_TRUE(std::filesystem::exists(dir.Path("debug/ssl-frame.6_detect.png")));
}

TEST(ThresholdsCli, BadLabelsAreExit2WithNothingWritten) {
  testing::TempDir dir;
  const std::string labels =
      dir.Write("l.toml", "image = \"" + kGolden +
                              "png\"\n[[class]]\nname = \"blue\"\nrects = [[0, 0, 5, 480]]\n");
  const auto r = RunCommand(kBinary + " thresholds " + labels + " -o " + dir.Path("t.toml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "patlab thresholds: " + labels +
                       ":4: rectangle corner [5, 480] of class \"blue\" lies outside the 640x480 "
                       "image; expected 0 <= x < 640 and 0 <= y < 480\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("t.toml")));
}

}  // namespace
}  // namespace patlab::cli
