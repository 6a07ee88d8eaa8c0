// patlab compare, end to end: runs the built binary on the shipped patterns with small runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::CommandResult;
using testing::RunCommand;

CommandResult Compare(const std::string& args) {
  return RunCommand("cd " PATLAB_SOURCE_DIR " && " PATLAB_BINARY " compare " + args);
}

constexpr const char* kSmallComparison = " --trials 3000 --frames 20 --sigmas 1,4 -q";

TEST(CompareCli, WritesTheThreeFilesAndRanks) {
  const testing::TempDir dir;
  const CommandResult run = Compare(std::string("triangle ssl-standard --sort-by ids_2c --out ") +
                                    dir.Path() + kSmallComparison);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out, "");
  const std::string text = testing::ReadFile(dir.Path("compare.txt"));
  EXPECT_NE(text.find("Designs ranked by ids_2c (best first)"), std::string::npos) << text;
  const std::string csv = testing::ReadFile(dir.Path("compare.csv"));
  EXPECT_EQ(csv.substr(0, csv.find(',', csv.find(',') + 1)), "rank,design");
  EXPECT_NE(csv.find("\n1,ssl-standard,patterns/ssl-standard.toml,5,4,170,19.9998,1,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\n2,triangle,patterns/triangle.toml,4,3,"), std::string::npos) << csv;
  const nlohmann::json j = nlohmann::json::parse(testing::ReadFile(dir.Path("compare.json")));
  EXPECT_EQ(j["rows"][0]["design"], "ssl-standard");
  EXPECT_EQ(j["rows"][0]["cells"]["ids_2c"], 16);
  EXPECT_TRUE(j["rows"][1]["cells"]["rotation_onset_mm"].is_null());  // colours decide
  // The same numbers on stdout, and for any thread count.
  const CommandResult csv1 =
      Compare(std::string("triangle ssl-standard --sort-by ids_2c --format csv "
                          "--threads 1") +
              kSmallComparison);
  EXPECT_EQ(csv1.out, csv);
}

TEST(CompareCli, BadInputExitsTwoAndWritesNothing) {
  const testing::TempDir dir;
  const std::string out = " --out " + dir.Path("out");
  const CommandResult sort = Compare("simple --sort-by speed --colors 2 --sigmas 2" + out);
  EXPECT_EQ(sort.exit_code, 2);
  EXPECT_EQ(
      sort.err.rfind("patlab compare: --sort-by is \"speed\"; expected one of: diameter_mm, ", 0),
      0u)
      << sort.err;
  const CommandResult missing = Compare("no-such-design" + out);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("no-such-design"), std::string::npos) << missing.err;
  const std::string fixed_only = dir.Write("fixed.toml",
                                           "name = \"fixed\"\n"
                                           "[[patch]]\nrole = \"key\"\nx = 0.0\ny = 0.0\n"
                                           "radius = 25.0\n"
                                           "[[patch]]\nrole = \"fixed\"\ncolour = \"red\"\n"
                                           "x = 65.0\ny = 0.0\nradius = 20.0\n");
  const CommandResult no_ids = Compare(fixed_only + out);
  EXPECT_EQ(no_ids.exit_code, 2);
  EXPECT_EQ(no_ids.err, "patlab compare: " + fixed_only +
                            ": design fixed has no ID slots; expected at least one patch with "
                            "role = \"id\"\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out")));
  EXPECT_EQ(Compare("").exit_code, 2);
}

}  // namespace
}  // namespace patlab
