// End-to-end tests of `patlab simulate --shard K/N` and `patlab merge`, and of points keyed by
// identity through the real binary (the Butterfly at sigma = 1 mm in every grid).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../test_util.h"

namespace patlab {
namespace {

using testing::kPatlab;
using testing::RunCommand;
using testing::SmallExperiment;

const std::string kFig5 = std::string(PATLAB_SOURCE_DIR) + "/experiments/fig5.toml";

bool Exists(const std::string& path) { return std::filesystem::exists(path); }

TEST(MergeCli, ShardsMergeIntoTheUnshardedCsvAndManifest) {
  testing::TempDir dir;
  const std::string e = dir.Write("small.toml", SmallExperiment());
  ASSERT_EQ(RunCommand(kPatlab + " simulate " + e + " -q --out " + dir.Path("whole")).exit_code, 0);
  for (const char* k : {"1/2", "2/2"}) {
    const auto r = RunCommand(kPatlab + " simulate " + e + " -q --threads 1 --shard " + k +
                              " --out " + dir.Path("shards"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_TRUE(Exists(dir.Path("shards/small.shard-1-of-2.json")));
  EXPECT_FALSE(Exists(dir.Path("shards/small.csv")));
  const auto m =
      RunCommand(kPatlab + " merge " + dir.Path("shards") + " -q --out " + dir.Path("merged"));
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_EQ(testing::ReadFile(dir.Path("merged/small.csv")),
            testing::ReadFile(dir.Path("whole/small.csv")));
  // The manifest too, byte for byte: it describes the results, not how they were run.
  EXPECT_EQ(testing::ReadFile(dir.Path("merged/small.json")),
            testing::ReadFile(dir.Path("whole/small.json")));
}

TEST(MergeCli, SharesOfTheExperimentTypedAsAnotherPathMerge) {
  // The fingerprint is the experiment's content (docs/merge.md): share 1 run as ./small.toml in
  // its directory, share 2 as ../small.toml from a subdirectory, merge into the unsharded CSV.
  testing::TempDir dir;
  const std::string e = dir.Write("small.toml", SmallExperiment());
  dir.Write("sub/.keep", "");
  dir.Write("shards/.keep", "");
  ASSERT_EQ(RunCommand(kPatlab + " simulate " + e + " -q --out " + dir.Path("whole")).exit_code, 0);
  const auto r1 = RunCommand("(cd " + dir.Path() + " && " + kPatlab +
                             " simulate ./small.toml -q --shard 1/2 --out shards)");
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  const auto r2 = RunCommand("(cd " + dir.Path("sub") + " && " + kPatlab +
                             " simulate ../small.toml -q --shard 2/2 --out ../shards)");
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  const auto m =
      RunCommand(kPatlab + " merge " + dir.Path("shards") + " -q --out " + dir.Path("merged"));
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_EQ(testing::ReadFile(dir.Path("merged/small.csv")),
            testing::ReadFile(dir.Path("whole/small.csv")));
}

TEST(MergeCli, BadShardFlagsAndIncompleteMergesExitTwoAndWriteNothing) {
  testing::TempDir dir;
  const std::string e = dir.Write("small.toml", SmallExperiment());
  for (const char* bad : {"0/3", "4/3", "x/y"}) {
    const auto r =
        RunCommand(kPatlab + " simulate " + e + " -q --shard " + bad + " --out " + dir.Path("bad"));
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find(std::string("--shard is '") + bad +
                         "'; expected K/N with integers 1 <= K <= N <= 100000, e.g. 2/8"),
              std::string::npos)
        << r.err;
  }
  EXPECT_FALSE(Exists(dir.Path("bad")));
  const auto both = RunCommand(kPatlab + " simulate " + e + " -q --shard 1/2 --replay 0,1");
  EXPECT_EQ(both.exit_code, 2);
  EXPECT_NE(both.err.find("--shard and --replay together; expected one of them"), std::string::npos)
      << both.err;
  const auto none = RunCommand(kPatlab + " merge --out " + dir.Path("bad"));
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("missing SHARD; expected 'patlab merge SHARD... --out DIR' (see --help)"),
            std::string::npos)
      << none.err;
  ASSERT_EQ(
      RunCommand(kPatlab + " simulate " + e + " -q --shard 2/3 --out " + dir.Path("s")).exit_code,
      0);
  const auto r = RunCommand(kPatlab + " merge " + dir.Path("s") + " --out " + dir.Path("out"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing shards 1/3, 3/3 of experiment 'small', seed 77"), std::string::npos)
      << r.err;
  EXPECT_FALSE(Exists(dir.Path("out")));
}

// The rows of a CSV for one pattern at one sigma.
std::string Rows(const std::string& csv, const std::string& prefix) {
  std::istringstream in(csv);
  std::string line, rows;
  while (std::getline(in, line)) {
    if (line.starts_with(prefix)) rows += line + "\n";
  }
  return rows;
}

// When points were keyed by their grid position, the Butterfly's row at sigma = 1 mm was 0.44997
// in fig5.toml, 0.44917 with --sigmas 0.5,1 and 0.45031 with --sigmas 1,2; now every grid gives
// the same bytes.
TEST(MergeCli, TheButterflyAtOneMillimetreIsTheSameRowInEveryGrid) {
  testing::TempDir dir;
  std::string reference;
  int run = 0;
  for (const char* sigmas : {"", " --sigmas 0.5,1", " --sigmas 1,2", " --sigmas 1"}) {
    const std::string out = dir.Path(std::to_string(run++));
    const auto r =
        RunCommand(kPatlab + " simulate " + kFig5 + " -q --trials 2000" + sigmas + " --out " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string rows = Rows(testing::ReadFile(out + "/fig5.csv"), "butterfly,fast,1,");
    ASSERT_FALSE(rows.empty()) << sigmas;
    if (reference.empty()) reference = rows;
    EXPECT_EQ(rows, reference) << sigmas;
  }
}

}  // namespace
}  // namespace patlab
