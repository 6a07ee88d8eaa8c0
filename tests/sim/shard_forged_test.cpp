// Forged shards (src/patlab/sim/shard.h): shards edited with their checksum recomputed, as a
// forger or a buggy tool would, are refused by their values before anything is written, each
// with the file and what is wrong; many bad shards are listed up to a cap.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/core/format.h"
#include "patlab/core/rng.h"
#include "patlab/sim/shard.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;
using nlohmann::json;

Experiment TriangleExperiment() {
  Experiment e;
  e.name = "small";
  e.patterns.push_back(testing::ShippedPattern("triangle"));
  e.pattern_files.push_back("triangle");
  e.estimators = {Estimator::kFast, Estimator::kMl};
  e.sigmas_mm = {0.5, 1.0};
  e.trials = 200;
  e.seed = 3;
  return e;
}

// The two shards of TriangleExperiment(), computed once.
struct Shards {
  testing::TempDir dir;
  std::string s1, s2, text2;
  Shards() {
    const Experiment e = TriangleExperiment();
    for (int k = 1; k <= 2; ++k) {
      RunOptions options;
      options.shard = ShardSpec{k, 2};
      const std::string path =
          dir.Write(ShardFileName(e.name, options.shard),
                    KnownShardText(e, RunExperiment(e, options), options.shard, e.name, "test"));
      (k == 1 ? s1 : s2) = path;
    }
    text2 = testing::ReadFile(s2);
  }
  // Shard 2 edited by `edit`, its checksum recomputed as shard.cpp computes it.
  void Forge(const std::function<void(json&)>& edit) {
    json j = json::parse(text2);
    edit(j);
    j.erase("checksum");
    j["checksum"] = StringPrintf(
        "%016llx",
        static_cast<unsigned long long>(StreamKey(0).Add(std::string_view(j.dump())).value()));
    dir.Write(ShardFileName("small", {2, 2}), j.dump(1) + "\n");
  }
  void Merge() { MergeShards({s1, s2}, dir.Path("out"), ""); }
};

TEST(ShardForged, AShortRowIsRefused) {
  Shards s;
  s.Forge([](json& j) {
    std::string row = j["points"][0]["rows"][0];
    j["points"][0]["rows"][0] = row.substr(0, row.rfind(','));
  });
  EXPECT_INPUT_ERROR_STARTS_WITH(s.Merge(), s.s2 + ": point 1 row 1 'triangle,fast,1,200,");
  EXPECT_FALSE(std::filesystem::exists(s.dir.Path("out")));
}

TEST(ShardForged, NegativeAndOverflowingCountsAreRefused) {
  Shards s;
  s.Forge([](json& j) { j["points"][0]["count"] = -5; });
  EXPECT_INPUT_ERROR(
      s.Merge(), s.s2 + ": point 1: count -5; expected the 200 of every point of the experiment");
  s.Forge([](json& j) { j["points"][0]["count"] = INT64_MAX; });
  EXPECT_INPUT_ERROR(s.Merge(), s.s2 +
                                    ": point 1: count 9223372036854775807; expected the 200 of "
                                    "every point of the experiment");
  s.Forge([](json& j) { j["points"][0]["ml_nonconverged"] = 201; });
  EXPECT_INPUT_ERROR(s.Merge(), s.s2 + ": point 1: ml_nonconverged 201; expected 0..200");
  s.Forge([](json& j) { j["points"][0]["index"] = 7; });
  EXPECT_INPUT_ERROR(s.Merge(), s.s2 + ": point 7: index out of range; expected 0..1");
}

TEST(ShardForged, TimingsOutsideARunAreRefused) {
  Shards s;
  s.Forge([](json& j) { j["run"]["timings_s"]["wall"] = -1.5; });
  EXPECT_INPUT_ERROR(s.Merge(),
                     s.s2 + ": run.timings_s.wall -1.5; expected seconds in [0, 31536000]");
  s.Forge([](json& j) { j["run"]["threads"] = -2; });
  EXPECT_INPUT_ERROR(s.Merge(), s.s2 + ": run.threads -2; expected 0..1048576");
}

TEST(ShardForged, ANewlineInTheHeaderAndASlashInTheNameAreRefused) {
  Shards s;
  s.Forge([](json& j) { j["csv_header"] = "pattern,estimator\nsigma_mm"; });
  EXPECT_INPUT_ERROR(s.Merge(), s.s2 +
                                    ": csv_header 'pattern,estimator\\x0asigma_mm'; expected one "
                                    "non-empty line without control characters");
  s.Forge([](json& j) { j["name"] = "../escaped"; });
  EXPECT_INPUT_ERROR(s.Merge(),
                     s.s2 +
                         ": name '../escaped' holds '/'; expected a non-empty name of at "
                         "most 200 bytes of UTF-8 without '/', '\\', control "
                         "characters or NUL");
}

// Two values wrong in one file are both named.
TEST(ShardForged, EveryProblemOfAShardIsNamed) {
  Shards s;
  s.Forge([](json& j) {
    j["points"][0]["count"] = 0;
    j["run"]["timings_s"]["simulate"] = 1e9;
  });
  EXPECT_INPUT_ERROR(s.Merge(), s.s2 +
                                    ": point 1: count 0; expected the 200 of every point of the "
                                    "experiment; run.timings_s.simulate 1000000000.0; expected "
                                    "seconds in [0, 31536000]");
}

// Trial-range shares (one point of two blocks, one block a share): each block's range alone lies
// within the point, so only the tiling tells a forged range: block 1 must start where block 0
// ends, and the blocks must add up to the point's trials.
TEST(ShardForged, BlocksThatDoNotTileTheirPointAreRefused) {
  Experiment e = TriangleExperiment();
  e.estimators = {Estimator::kFast};
  e.sigmas_mm = {1.0};
  e.trials = kStatisticsBlockTrials + 1000;
  testing::TempDir dir;
  std::string paths[2], text2;
  for (int k = 1; k <= 2; ++k) {
    RunOptions options;
    options.shard = ShardSpec{k, 2};
    options.threads = 2;
    paths[k - 1] =
        dir.Write(ShardFileName(e.name, options.shard),
                  KnownShardText(e, RunExperiment(e, options), options.shard, e.name, "test"));
  }
  text2 = testing::ReadFile(paths[1]);
  const auto forge = [&](const std::function<void(json&)>& edit) {
    json j = json::parse(text2);
    edit(j);
    j.erase("checksum");
    j["checksum"] = StringPrintf(
        "%016llx",
        static_cast<unsigned long long>(StreamKey(0).Add(std::string_view(j.dump())).value()));
    dir.Write(ShardFileName("small", {2, 2}), j.dump(1) + "\n");
  };
  const std::string block1 = std::to_string(kStatisticsBlockTrials);
  ASSERT_EQ(json::parse(text2)["blocks"][0]["first"].get<int64_t>(), kStatisticsBlockTrials);
  forge([](json& j) {
    j["blocks"][0]["first"] = j["blocks"][0]["first"].get<int64_t>() + 1;
    j["blocks"][0]["count"] = j["blocks"][0]["count"].get<int64_t>() - 1;
  });
  EXPECT_INPUT_ERROR(MergeShards({paths[0], paths[1]}, dir.Path("out"), ""),
                     paths[1] + ": block 1 of point 0 starts at trial " +
                         std::to_string(kStatisticsBlockTrials + 1) + "; expected " + block1 +
                         ", where block 0 ends");
  forge([](json& j) { j["blocks"][0]["count"] = j["blocks"][0]["count"].get<int64_t>() - 1; });
  EXPECT_INPUT_ERROR(MergeShards({paths[0], paths[1]}, dir.Path("out"), ""),
                     paths[1] + ": the blocks of point 0 add up to " +
                         std::to_string(e.trials - 1) + " trials; expected the " +
                         std::to_string(e.trials) + " of every point");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("out")));
  dir.Write(ShardFileName("small", {2, 2}), text2);  // the shard as written merges
  EXPECT_NO_THROW(MergeShards({paths[0], paths[1]}, dir.Path("out"), ""));
}

// Twelve files that are not shards: ten are named, then how many more.
TEST(ShardForged, ManyBadShardsAreListedUpToACap) {
  testing::TempDir dir;
  std::vector<std::string> paths;
  for (int k = 1; k <= 12; ++k) {
    paths.push_back(dir.Write("x.shard-" + std::to_string(k) + "-of-12.json", "{"));
  }
  std::string expected = "12 of 12 shard files are not intact: ";
  for (int k = 0; k < 10; ++k) {
    expected += (k == 0 ? "" : "; ") + paths[k] +
                ": not JSON (truncated or edited?); expected a shard file as 'patlab simulate "
                "--shard K/N' wrote it";
  }
  expected += "; ... and 2 more; nothing written";
  EXPECT_INPUT_ERROR(MergeShards(paths, dir.Path("out"), ""), expected);
}

}  // namespace
}  // namespace patlab::sim
