// patlab camtrack end to end, the binary run as a user would: a short track through the colour
// camera, its CSV read back by its header.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../test_util.h"

namespace patlab::cli {
namespace {

using testing::kPatlab;
using testing::kSource;
using testing::RunCommand;

std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
  return out;
}

// Every row has as many cells as the header names, and the named columns hold what the track
// was: one run of 40 frames through the Bayer camera, each with the robot found by the detector
// (--detect, adapted to the camera as patlab detect adapts it: without the segmentation's edge
// loss in its area test it found 9 of 300), none with a wrong ID.
TEST(CamtrackCli, EveryRowHasTheHeadersColumns) {
  testing::TempDir dir;
  const std::string csv = dir.Path("t/camtrack.csv");
  const auto r = RunCommand(kPatlab + " camtrack " + kSource +
                            "/experiments/camera-noise/track-scene.toml --thresholds " + kSource +
                            "/experiments/camera-noise/track.thresholds.toml --runs 1 --frames 40 "
                            "--detect --out " +
                            dir.Path("t"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  const std::vector<std::string> header = Cells(line);
  EXPECT_EQ(header.back(), "wrong_id_frames");
  int rows = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = Cells(line);
    ASSERT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < header.size(); ++i) row[header[i]] = cells[i];
    EXPECT_EQ(row["frames"], "40");
    EXPECT_EQ(row["detected_frames"], "40") << line;
    EXPECT_EQ(row["wrong_id_frames"], "0");
    EXPECT_GE(std::stod(row["tau_x"]), 0.0);
    ++rows;
  }
  EXPECT_GE(rows, 4);  // key, id, all, pose (and detect)
}

}  // namespace
}  // namespace patlab::cli
