// patlab import, end to end: runs the built binary on a blank sheet it writes and, when present,
// the shared SSL standard sheet (../shared/frames, not in the repository).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <string>

#include "../test_util.h"
#include "patlab/vision/frame_io.h"

namespace patlab {
namespace {

using testing::CommandResult;
using testing::RunCommand;

CommandResult Import(const std::string& args) {
  return RunCommand("cd " PATLAB_SOURCE_DIR " && " PATLAB_BINARY " import " + args);
}

TEST(ImportCli, BadSheetsExitTwoAndWriteNothing) {
  const testing::TempDir dir;
  const std::string blank = dir.Path("blank.png");
  vision::WritePng(camera::Image::Rgb(400, 200), blank);
  const std::string out = dir.Path("out");
  const CommandResult run = Import(blank + " --out " + out);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.err, "patlab import: " + blank +
                         ": no recognisable cells; expected 200 px cells each with a blue key "
                         "patch and coloured dots\n");
  EXPECT_FALSE(std::filesystem::exists(out));
  const CommandResult missing = Import(dir.Path("none.png") + " --out " + out);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("none.png"), std::string::npos) << missing.err;
  EXPECT_EQ(Import("").exit_code, 2);
  EXPECT_EQ(Import(blank + " " + blank + " --name x").exit_code, 2);
}

// One cell: three green dots 120 degrees apart. Colours must decide the rotation, and a
// monochrome colouring cannot: the layout has no ID, so no codebook file is written.
TEST(ImportCli, LayoutWithoutIdsGetsNoCodebook) {
  const testing::TempDir dir;
  camera::Image image = camera::Image::Rgb(200, 200);
  auto disc = [&image](double cx, double cy, double r, std::array<uint8_t, 3> rgb) {
    for (int y = 0; y < 200; ++y) {
      for (int x = 0; x < 200; ++x) {
        if ((x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r) {
          std::copy(rgb.begin(), rgb.end(), image.Row(y) + 3 * x);
        }
      }
    }
  };
  disc(100, 100, 25, {0, 0, 255});
  for (int k = 0; k < 3; ++k) {
    const double a = 2.0 * 3.14159265358979 * k / 3.0;
    disc(100 + 65 * std::sin(a), 100 - 65 * std::cos(a), 18, {0, 255, 0});
  }
  const std::string sheet = dir.Path("tri.png");
  vision::WritePng(image, sheet);
  const CommandResult run = Import(sheet + " --out " + dir.Path("out"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("  tri: 3 dots, 0 IDs (no codebook written); ID 0 left out: a rotation by "
                         "shift 1 maps it onto itself\n"),
            std::string::npos)
      << run.out;
  EXPECT_TRUE(std::filesystem::exists(dir.Path("out/tri.toml")));
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out/tri.codebook.toml")));
}

TEST(ImportCli, StandardSheetGivesFilesTheOtherCommandsRead) {
  const std::string sheet =
      std::string(PATLAB_SOURCE_DIR) + "/../shared/frames/ssl-standard-pattern-2010-16ids.png";
  if (!std::filesystem::exists(sheet)) {
    GTEST_SKIP() << "no shared sheet at " << sheet
                 << " (real sheets live in ../shared/frames, outside the repository)";
  }
  const testing::TempDir dir;
  const CommandResult run = Import(sheet + " --name ssl-standard --out " + dir.Path());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(
      run.out.find("16 cells of 16, 4 dot positions, 1 layout\n  ssl-standard: 4 dots, 16 IDs"),
      std::string::npos)
      << run.out;
  const CommandResult ids = RunCommand("cd " PATLAB_SOURCE_DIR " && " PATLAB_BINARY " ids " +
                                       dir.Path("ssl-standard.toml") + " --colors 2");
  ASSERT_EQ(ids.exit_code, 0) << ids.err;
  EXPECT_NE(ids.out.find("ssl-standard  4      1          16\n"), std::string::npos) << ids.out;
}

}  // namespace
}  // namespace patlab
