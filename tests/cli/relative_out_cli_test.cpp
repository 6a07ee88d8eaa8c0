// A new user's first commands: from an empty working directory, every command that writes files
// takes a relative --out folder that does not exist yet ("a/b"), makes it and writes its fixed
// file names there; shipped data is found by name.
#include <gtest/gtest.h>

#include <filesystem>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::kData;
using testing::kPatlab;
using testing::RunCommand;

struct Case {
  std::string arguments;           // after "patlab"; "-o a/b" is appended
  std::vector<std::string> files;  // expected in a/b
};

std::vector<Case> Cases() {
  return {
      {"simulate fig5 --trials 200 --sigmas 1 -q", {"fig5.csv", "fig5.json"}},
      {"track table1 --seed 3 -q", {"table1.csv", "table1_tests.csv", "track_errors.csv"}},
      {"compare simple linear --trials 200 --frames 2 --sigmas 1 -q",
       {"compare.txt", "compare.csv", "compare.json"}},
      {"design --starts 1 --max-evaluations 50 --name d -q", {"d.toml", "d.design.txt"}},
      {"render ssl-frame", {"frame.png", "truth.csv"}},
      {"detect " + kData +
           "golden/ssl-frame.png -t ssl-frame.thresholds -c ssl-frame.calibration "
           "-s ssl-frame.detector",
       {"detections.csv"}},
      {"calibrate ssl-2008.calibration-input", {"calibration.toml", "residuals.csv"}},
      {"thresholds " + kData + "vision/golden-frame.labels.toml", {"thresholds.toml"}},
      {"camtrack track-scene -t track.thresholds --runs 1 --frames 20", {"camtrack.csv"}},
      {"analyze track.csv -q", {"analyze.csv", "analyze.json"}},
  };
}

// A straight track with a wobble for analyze.
std::string Track() {
  std::string track = "frame,x_mm,y_mm\n";
  for (int f = 0; f < 300; ++f) {
    track += std::to_string(f) + "," + std::to_string(10 * f + (f * 7 % 5)) + "," +
             std::to_string(f * 3 % 4) + "\n";
  }
  return track;
}

TEST(RelativeOutCli, EveryCommandMakesARelativeOutFolderThatDoesNotExistYet) {
  for (const Case& c : Cases()) {
    testing::TempDir dir;
    dir.Write("track.csv", Track());
    const auto r =
        RunCommand("cd " + dir.Path() + " && " + kPatlab + " " + c.arguments + " -o a/b");
    EXPECT_EQ(r.exit_code, 0) << c.arguments << "\n" << r.err;
    for (const std::string& file : c.files) {
      EXPECT_TRUE(std::filesystem::is_regular_file(dir.Path("a/b/" + file)))
          << c.arguments << ": no a/b/" << file;
    }
  }
}

// The same commands on a full disk (a file size limit of 1 KiB; SIGXFSZ ignored, so a write past
// it fails with EFBIG): a command that fails before it commits its results leaves no folder it
// made (io/made_folders.h), and one whose results fit commits them into the folders it made.
TEST(RelativeOutCli, ACommandThatFailsBeforeItsCommitLeavesNoFolderItMade) {
  int failed = 0;
  for (const Case& c : Cases()) {
    testing::TempDir dir;
    dir.Write("track.csv", Track());
    const auto r = RunCommand("cd " + dir.Path() + " && trap '' XFSZ && ulimit -f 2 && " + kPatlab +
                              " " + c.arguments + " -o a/b");
    if (r.exit_code == 0) {
      EXPECT_TRUE(std::filesystem::is_directory(dir.Path("a/b"))) << c.arguments;
      continue;
    }
    ++failed;
    EXPECT_EQ(r.exit_code, 1) << c.arguments << "\n" << r.err;
    EXPECT_NE(r.err.find("cannot write: File too large"), std::string::npos) << c.arguments << "\n"
                                                                             << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir.Path("a"))) << c.arguments << ": a/ was left";
  }
  EXPECT_GE(failed, 8);  // all but the commands whose results fit in 1 KiB
}

// simulate --shard into a relative folder, then merge into another.
TEST(RelativeOutCli, ShardsAndTheirMergeGoIntoRelativeFolders) {
  testing::TempDir dir;
  const std::string cd = "cd " + dir.Path() + " && " + kPatlab;
  for (const char* k : {"1/2", "2/2"}) {
    const auto r =
        RunCommand(cd + " simulate fig5 --trials 200 --sigmas 1 -q --shard " + k + " -o shards");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const auto m = RunCommand(cd + " merge shards -q -o merged/here");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_TRUE(std::filesystem::is_regular_file(dir.Path("merged/here/fig5.csv")));
}

}  // namespace
}  // namespace patlab
