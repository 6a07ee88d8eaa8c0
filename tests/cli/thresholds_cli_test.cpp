// patlab thresholds end to end, and the detect flags that go with it (--explain, the palette
// warnings), the binary run as a user would.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/color_lut.h"

namespace patlab::cli {
namespace {

using testing::kData;
using testing::kGoldenFrame;
using testing::kPatlab;
using testing::RunCommand;

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
      RunCommand(kPatlab + " thresholds " + kData + "vision/golden-frame.labels.toml -o " +
                 dir.Path("t") + " -s " + kGoldenFrame + "detector.toml");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\npink               40  "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no overlapping classes"), std::string::npos) << r.out;
  EXPECT_EQ(formats::LoadThresholds(t).classes.size(), 5u);
  const auto d =
      RunCommand(kPatlab + " detect " + kGoldenFrame + "png -t " + t + " -c " + kGoldenFrame +
                 "calibration.toml -s " + kGoldenFrame + "detector.toml --explain");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_EQ(std::count(d.out.begin(), d.out.end(), '\n'), 11);  // header + 10 robots
  EXPECT_EQ(CountSubstrings(d.err, ": detected, id "), 10) << d.err;
}

// A silent mismatch: "rosa" (no colour of the vocabulary, close to none) for the palette's "pink"
// warns on stderr, and --explain says why each robot with a pink dot is missed (too few
// neighbours). "magenta" is pink (settings/colours.toml): no warning, all ten robots found.
TEST(ThresholdsCli, DetectWarnsAboutNamesAndExplainsTheMisses) {
  testing::TempDir dir;
  std::string text = testing::ReadFile(kGoldenFrame + "thresholds.toml");
  std::string magenta = text;
  magenta.replace(magenta.find("name = \"pink\""), 13, "name = \"Magenta\"");
  const std::string m = dir.Write("m.toml", magenta);
  const auto ok =
      RunCommand(kPatlab + " detect " + kGoldenFrame + "png -t " + m + " -c " + kGoldenFrame +
                 "calibration.toml -s " + kGoldenFrame + "detector.toml");
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(ok.err, "");
  EXPECT_EQ(std::count(ok.out.begin(), ok.out.end(), '\n'), 11);  // header + 10 robots
  text.replace(text.find("name = \"pink\""), 13, "name = \"rosa\"");
  const std::string t = dir.Write("t.toml", text);
  const auto d = RunCommand(kPatlab + " detect " + kGoldenFrame + "png -t " + t + " -c " +
                            kGoldenFrame + "calibration.toml -s " + kGoldenFrame +
                            "detector.toml --explain --debug " + dir.Path("debug"));
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_NE(d.err.find("patlab detect: warning: " + t +
                       ": class \"rosa\" is no colour of the detector's palette; its blobs "
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

// --auto on one colour-camera frame of the golden scene, classes from the detector settings:
// the report, then every robot of the golden frame found with the written thresholds.
TEST(ThresholdsCli, AutoFitsAFrameWithNoLabels) {
  testing::TempDir dir;
  const auto f =
      RunCommand(kPatlab + " render " + kGoldenFrame + "toml --camera -o " + dir.Path("f"));
  ASSERT_EQ(f.exit_code, 0) << f.err;
  const auto r = RunCommand(kPatlab + " thresholds --auto " + dir.Path("f/frame.png") + " -s " +
                            kGoldenFrame + "detector.toml -o " + dir.Path("t"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("class ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("\ncarpet "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\norange "), std::string::npos) << r.out;
  const vision::Thresholds t = formats::LoadThresholds(dir.Path("t/thresholds.toml"));
  ASSERT_EQ(t.classes.size(), 5u);
  EXPECT_EQ(t.classes[0].name, "blue");
  const auto d =
      RunCommand(kPatlab + " detect " + kGoldenFrame + "png -t " + dir.Path("t/thresholds.toml") +
                 " -c " + kGoldenFrame + "calibration.toml -s " + kGoldenFrame + "detector.toml");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_EQ(std::count(d.out.begin(), d.out.end(), '\n'), 11);  // header + 10 robots
  EXPECT_EQ(CountSubstrings(d.out, ",ok,"), 10) << d.out;
}

// --labels seeds the classes with the labelled pixels of another file's frame: every labelled
// pixel is counted in its class (10 blue, 40 pink, golden-frame.labels.toml).
TEST(ThresholdsCli, AutoWithLabelsCountsTheLabelledPixels) {
  testing::TempDir dir;
  const auto r = RunCommand(kPatlab + " thresholds --auto " + kGoldenFrame + "png -s " +
                            kGoldenFrame + "detector.toml --labels " + kData +
                            "vision/golden-frame.labels.toml -o " + dir.Path("t"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\nblue   "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("      10 "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("      40 "), std::string::npos) << r.out;
}

TEST(ThresholdsCli, AutoBadInputIsExit2) {
  testing::TempDir dir;
  const auto r = RunCommand(kPatlab + " thresholds --auto " + kGoldenFrame +
                            "png --classes blue,pnik -o " + dir.Path("t"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "patlab thresholds: --classes: unknown colour 'pnik'; expected a colour of "
            "settings/colours.toml (did you mean 'pink'?)\n");
  const auto n =
      RunCommand(kPatlab + " thresholds --auto " + kGoldenFrame + "png -o " + dir.Path("t"));
  EXPECT_EQ(n.exit_code, 2);
  EXPECT_EQ(n.err,
            "patlab thresholds: --auto without --classes or --settings; expected the "
            "colour classes\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("t/thresholds.toml")));
}

TEST(ThresholdsCli, BadLabelsAreExit2WithNothingWritten) {
  testing::TempDir dir;
  const std::string labels =
      dir.Write("l.toml", "image = \"" + kGoldenFrame +
                              "png\"\n[[class]]\nname = \"blue\"\nrects = [[0, 0, 5, 480]]\n");
  const auto r = RunCommand(kPatlab + " thresholds " + labels + " -o " + dir.Path("t.toml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "patlab thresholds: " + labels +
                       ":4: rectangle corner [5, 480] of class \"blue\" lies outside the 640x480 "
                       "image; expected 0 <= x < 640 and 0 <= y < 480\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("t.toml")));
}

// The shipped labels (settings/ssl-frame.labels.toml), by name, as README.md's example runs them:
// the frame they label is the one `patlab render ssl-frame` draws, and the thresholds fitted
// from four of its robots find all ten robots of that frame with their true team and ID.
TEST(ThresholdsCli, ShippedLabelsByNameMakeThresholdsThatFindTheRenderedFramesRobots) {
  testing::TempDir dir;
  const std::string in_dir = "cd " + dir.Path() + " && " + kPatlab;
  const auto render = RunCommand(in_dir + " render ssl-frame -o frame");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  EXPECT_EQ(testing::ReadFile(dir.Path("frame/frame.png")),
            testing::ReadFile(std::string(PATLAB_SOURCE_DIR) + "/settings/ssl-frame.png"));
  const auto fit =
      RunCommand(in_dir + " thresholds ssl-frame.labels -s ssl-frame.detector -o thresholds");
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  EXPECT_NE(fit.out.find("no overlapping classes"), std::string::npos) << fit.out;
  const auto d = RunCommand(in_dir +
                            " detect frame/frame.png -t thresholds/thresholds.toml -c "
                            "ssl-frame.calibration -s ssl-frame.detector -o detections");
  ASSERT_EQ(d.exit_code, 0) << d.err;
  // Every robot of the truth (team,id,...) is detected as such, status ok, and nothing else.
  std::vector<std::string> truth, found;
  std::istringstream truth_lines(testing::ReadFile(dir.Path("frame/truth.csv")));
  std::string line;
  std::getline(truth_lines, line);  // header
  while (std::getline(truth_lines, line)) {
    const size_t second = line.find(',', line.find(',') + 1);
    if (line.rfind("ball", 0) != 0) truth.push_back(line.substr(0, second));
  }
  std::istringstream detections(testing::ReadFile(dir.Path("detections/detections.csv")));
  std::getline(detections, line);  // frame,pattern,team,id,status,...
  while (std::getline(detections, line)) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 5u) << line;
    EXPECT_EQ(cells[4], "ok") << line;
    found.push_back(cells[2] + "," + cells[3]);
  }
  std::sort(truth.begin(), truth.end());
  std::sort(found.begin(), found.end());
  EXPECT_EQ(truth.size(), 10u);
  EXPECT_EQ(found, truth);
}

}  // namespace
}  // namespace patlab::cli
