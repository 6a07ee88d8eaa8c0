// patlab design, end to end: the built binary writes a pattern file every command loads, the same
// options give byte-identical files, and impossible constraints exit 2 with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::CommandResult;
using testing::RunCommand;

CommandResult Design(const std::string& args) {
  return RunCommand("cd " PATLAB_SOURCE_DIR " && " PATLAB_BINARY " design " + args);
}

TEST(DesignCli, WritesALoadablePatternAndPrintsTheSpeed) {
  const testing::TempDir dir;
  const std::string options =
      " --starts 4 --min-rotation-onset-mm 3.5 --start ssl-standard --name d1 --out ";
  const CommandResult run = Design(options + dir.Path("a"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("best (start "), std::string::npos) << run.out;
  EXPECT_NE(run.err.find(" evaluations/s\n"), std::string::npos) << run.err;
  const std::string file = dir.Path("a/d1.toml");
  const Pattern pattern = formats::LoadPatternFile(file);
  EXPECT_EQ(pattern.name, "d1");
  EXPECT_EQ(pattern.size(), 5);
  // Ready for the other commands.
  const CommandResult ids = RunCommand(std::string(PATLAB_BINARY) + " ids " + file);
  EXPECT_EQ(ids.exit_code, 0) << ids.err;
  EXPECT_NE(ids.out.find("16"), std::string::npos) << ids.out;
  // Same options, same bytes.
  ASSERT_EQ(Design(options + dir.Path("b") + " -q").exit_code, 0);
  EXPECT_EQ(testing::ReadFile(file), testing::ReadFile(dir.Path("b/d1.toml")));
  EXPECT_EQ(testing::ReadFile(dir.Path("a/d1.design.txt")),
            testing::ReadFile(dir.Path("b/d1.design.txt")));
}

TEST(DesignCli, ImpossibleConstraintsExitTwoAndWriteNothing) {
  const testing::TempDir dir;
  const std::string out = " --out " + dir.Path("out");
  const CommandResult none = Design("--id-patches 0" + out);
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_EQ(none.err, "patlab design: id_patches is 0; expected an integer in [1, 11]\n");
  const CommandResult fit = Design("--id-patches 8 --starts 2" + out);
  EXPECT_EQ(fit.exit_code, 2);
  EXPECT_EQ(fit.err,
            "patlab design: no layout of 8 ID patches fits with outer_diameter_mm 180, rim_gap_mm "
            "0, key_radius_mm 25 and min_gap_mm 20 (2 starts); expected fewer or smaller ID "
            "patches, a smaller min_gap_mm or a larger outer_diameter_mm\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out")));
}

// --constraints FILE: the file's options, and flags given on the command line override them.
TEST(DesignCli, ConstraintsFileWithFlagsOverridingIt) {
  const testing::TempDir dir;
  const std::string file =
      dir.Write("c.toml",
                "name = \"fromfile\"\nid_patches = 3\nid_radii_mm = 18\nstarts = 2\n"
                "symmetry = \"mirror\"\n");
  const CommandResult run =
      Design("--constraints " + file + " --id-patches 5 --out " + dir.Path("out") + " -q");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const Pattern p = formats::LoadPatternFile(dir.Path("out/fromfile.toml"));  // name from the file
  EXPECT_EQ(p.size(), 6);                                                     // --id-patches 5 wins
  EXPECT_EQ(p.patches[1].radius_mm, 18.0);  // radius from the file
  const std::string report = testing::ReadFile(dir.Path("out/fromfile.design.txt"));
  EXPECT_NE(report.find("from 2 seeded starts"), std::string::npos) << report;
  EXPECT_NE(report.find(", symmetry mirror"), std::string::npos) << report;
}

}  // namespace
}  // namespace patlab
