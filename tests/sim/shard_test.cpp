// Shards and their merge (src/patlab/sim/shard.h): the merged CSV and manifest are the unsharded
// run's, byte for byte (run keys aside), for known and detect mode; bad shards are refused.
#include "patlab/sim/shard.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/core/format.h"
#include "patlab/core/rng.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/sim/report.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;

Experiment Small(uint64_t seed = 9) {
  Experiment e;
  e.name = "small";
  for (const char* p : {"triangle", "butterfly"}) {
    e.patterns.push_back(testing::ShippedPattern(p));
    e.pattern_files.push_back(p);
  }
  e.estimators = {Estimator::kFast, Estimator::kMl};
  e.sigmas_mm = {0.0, 0.5, 1.0, 2.0};
  e.trials = 2000;
  e.seed = seed;
  return e;
}

// Runs share k of n of `e` and writes its shard file into `dir`; returns the path.
std::string WriteKnownShard(const Experiment& e, int k, int n, const testing::TempDir& dir) {
  RunOptions options;
  options.shard = ShardSpec{k, n};
  const RunResult r = RunExperiment(e, options);
  return dir.Write(ShardFileName(e.name, options.shard),
                   KnownShardText(e, r, options.shard, e.name, "test"));
}

TEST(Shard, ParseAcceptsKOfNAndRejectsEverythingElse) {
  const ShardSpec s = ParseShardSpec("2/8", "--shard");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 8);
  EXPECT_TRUE(s.Holds(1));
  EXPECT_TRUE(s.Holds(9));
  EXPECT_FALSE(s.Holds(2));
  for (const char* bad :
       {"0/3", "4/3", "x/y", "3", "1/0", "-1/3", "1/3/", "1/ 3", "", "1/100001"}) {
    EXPECT_INPUT_ERROR(ParseShardSpec(bad, "--shard"),
                       std::string("--shard is '") + bad +
                           "'; expected K/N with integers 1 <= K <= N <= 100000, e.g. 2/8");
  }
  EXPECT_EQ(ShardFileName("fig5", s), "fig5.shard-2-of-8.json");
}

TEST(Shard, MergedKnownSharesEqualTheUnshardedRunByteForByte) {
  const Experiment e = Small();
  const RunResult whole = RunExperiment(e, {});
  const std::string csv = ResultsCsv(e, whole);
  // 3 shares of 8 points (uneven), and 11 shares: three of them hold no point.
  for (int n : {3, 11}) {
    testing::TempDir dir;
    for (int k = n; k >= 1; --k) WriteKnownShard(e, k, n, dir);
    const MergedOutputs merged = MergeShards({dir.Path()}, dir.Path("out"), "");
    EXPECT_EQ(merged.csv, csv) << n;
    EXPECT_EQ(merged.json, ManifestJson(e, whole, {merged.csv_path, merged.json_path})) << n;
    EXPECT_EQ(merged.csv_path, dir.Path("out/small.csv"));
  }
}

TEST(Shard, TrialRangeSharesMergeToTheUnshardedRunByteForByte) {
  // Points of three blocks (2 x 2^20 + 5000 trials): with 2 or 4 shares no share holds a whole
  // point; the merge folds every point's blocks as the runner does, so the CSV is the same bytes
  // and the manifest the same bytes. Two points, one with ML non-converged
  // trials and the first block's KS/Wilcoxon comparison.
  Experiment e = Small();
  e.patterns.resize(1);
  e.pattern_files.resize(1);
  e.sigmas_mm = {0.5, 3.0};
  e.trials = 2 * kStatisticsBlockTrials + 5000;
  e.ml_options.max_iterations = 2;
  RunOptions options;
  options.threads = 2;
  const RunResult whole = RunExperiment(e, options);
  const std::string csv = ResultsCsv(e, whole);
  for (int n : {2, 4}) {
    testing::TempDir dir;
    for (int k = 1; k <= n; ++k) WriteKnownShard(e, k, n, dir);
    const MergedOutputs merged = MergeShards({dir.Path()}, dir.Path("out"), "");
    EXPECT_EQ(merged.csv, csv) << n;
    EXPECT_EQ(merged.json, ManifestJson(e, whole, {merged.csv_path, merged.json_path})) << n;
  }
  // A missing share is named, and nothing is merged.
  testing::TempDir dir;
  const std::string s1 = WriteKnownShard(e, 1, 2, dir);
  EXPECT_INPUT_ERROR_STARTS_WITH(MergeShards({s1}, dir.Path("out"), ""), "missing shards 2/2");
}

// A detect-mode experiment in `dir` (Butterfly with 2 ID colours, Triangle with 3): `body` is the
// experiment file after its name and mode.
Experiment LoadDetect(const testing::TempDir& dir, const std::string& body) {
  for (const char* name : {"butterfly", "triangle"}) {
    dir.Write(std::string("patterns/") + name + ".toml",
              testing::ReadFile(std::string(PATLAB_SOURCE_DIR) + "/patterns/" + name + ".toml"));
  }
  dir.Write("experiments/det.toml",
            "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"cyan\", \"orange\"]\n"
            "[detector]\npatch_sigma_mm = 1.0\n"
            "[[pattern]]\npattern = \"butterfly\"\nid_colours = [\"pink\", \"green\"]\n"
            "key_colours = [\"blue\", \"yellow\"]\n"
            "[[pattern]]\npattern = \"triangle\"\nid_colours = [\"pink\", \"green\", \"cyan\"]\n"
            "key_colours = [\"blue\", \"yellow\"]\n");
  return formats::LoadExperimentFile(
      dir.Write("experiments/e.toml", "name = \"det\"\ncorrespondence = \"detect\"\n" + body));
}

// Runs share k of n of the detect experiment `e` and writes its shard file into `dir`.
std::string WriteDetectShard(const Experiment& e, int k, int n, const testing::TempDir& dir) {
  RunOptions options;
  options.shard = ShardSpec{k, n};
  options.threads = 2;
  return dir.Write("shards/" + ShardFileName("det", options.shard),
                   DetectShardText(e, RunDetectExperiment(e, options), options.shard, "det", "t"));
}

TEST(Shard, MergedDetectSharesEqualTheUnshardedRun) {
  testing::TempDir dir;
  const Experiment e = LoadDetect(
      dir,
      "patterns = [\"butterfly\", \"triangle\"]\nseed = 5\n[sigma]\nvalues = [0.5, 2]\n"
      "[detect]\nsettings = \"det.toml\"\nframes = 100\nfalse_blob_rate_per_m2 = [0, 3]\n");
  const DetectRunResult whole = RunDetectExperiment(e, {});
  for (int k = 1; k <= 3; ++k) WriteDetectShard(e, k, 3, dir);
  const MergedOutputs merged = MergeShards({dir.Path("shards")}, dir.Path("out"), "");
  EXPECT_EQ(merged.csv, DetectResultsCsv(e, whole));
  EXPECT_EQ(merged.json, DetectManifestJson(e, whole, {merged.csv_path, merged.json_path}));
}

TEST(Shard, DetectTrialRangeSharesMergeToTheUnshardedRunByteForByte) {
  // Detect points of three blocks of frames (2 x 2^14 + 300 frames; small frames: one robot per
  // team, no ball): with 2 or 4 shares no share holds a whole point. The merge adds every
  // point's counters and folds its pose-error moments as the runner does (FinishDetectPoint), so
  // the CSV is the same bytes and the manifest the same bytes. Two points, with
  // false blobs, missing patches and colour errors, so that every counter is non-zero somewhere.
  testing::TempDir dir;
  const Experiment e =
      LoadDetect(dir,
                 "patterns = [\"triangle\"]\nseed = 5\n[sigma]\nvalues = [1, 4]\n"
                 "[detect]\nsettings = \"det.toml\"\nframes = " +
                     std::to_string(2 * kStatisticsBlockFrames + 300) +
                     "\nrobots_per_team = 1\nball = false\nfalse_blob_rate_per_m2 = 1\n"
                     "missing_patch_probability = 0.02\ncolour_error_probability = 0.02\n");
  RunOptions options;
  options.threads = 2;
  const DetectRunResult whole = RunDetectExperiment(e, options);
  ASSERT_EQ(whole.points.size(), 2U);
  EXPECT_GT(whole.points[1].wrong_id + whole.points[1].ambiguous, 0);
  const std::string csv = DetectResultsCsv(e, whole);
  for (int n : {2, 4}) {
    testing::TempDir shards;
    for (int k = n; k >= 1; --k) WriteDetectShard(e, k, n, shards);
    const MergedOutputs merged = MergeShards({shards.Path("shards")}, dir.Path("out"), "");
    EXPECT_EQ(merged.csv, csv) << n;
    EXPECT_EQ(merged.json, DetectManifestJson(e, whole, {merged.csv_path, merged.json_path})) << n;
    EXPECT_EQ(nlohmann::json::parse(merged.json)["total_frames"], whole.total_frames) << n;
  }
  // A missing share is named, and nothing is merged.
  testing::TempDir one;
  const std::string s2 = WriteDetectShard(e, 2, 4, one);
  const std::string s3 = WriteDetectShard(e, 3, 4, one);
  EXPECT_INPUT_ERROR_STARTS_WITH(MergeShards({s2, s3}, dir.Path("out"), ""),
                                 "missing shards 1/4, 4/4 of experiment 'det'");
}

TEST(Shard, TheFingerprintIsTheExperimentsContentNotItsPathAsTyped) {
  // Shares run as `patlab simulate exp.toml`, `./exp.toml` or from another directory merge: the
  // fingerprint leaves out the file paths and takes the content. The merged manifest records
  // the paths of the first share.
  testing::TempDir dir;
  const std::string body =
      "patterns = [\"butterfly\", \"triangle\"]\nseed = 5\n[sigma]\nvalues = [0.5, 2]\n"
      "[detect]\nsettings = \"det.toml\"\nframes = 50\n";
  const Experiment plain = LoadDetect(dir, body);
  const Experiment dotted =
      formats::LoadExperimentFile(dir.Path("experiments/./../experiments/e.toml"));
  ASSERT_NE(plain.source_file, dotted.source_file);
  WriteDetectShard(plain, 1, 2, dir);
  WriteDetectShard(dotted, 2, 2, dir);
  const MergedOutputs merged = MergeShards({dir.Path("shards")}, dir.Path("out"), "");
  const DetectRunResult whole = RunDetectExperiment(plain, {});
  EXPECT_EQ(merged.csv, DetectResultsCsv(plain, whole));
  EXPECT_EQ(merged.json, DetectManifestJson(plain, whole, {merged.csv_path, merged.json_path}));
  // The same paths with other content are another experiment: a settings file whose Triangle
  // lists its ID colours in another order (another codebook) is refused.
  dir.Write("experiments/det.toml",
            "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"cyan\", \"orange\"]\n"
            "[detector]\npatch_sigma_mm = 1.0\n"
            "[[pattern]]\npattern = \"butterfly\"\nid_colours = [\"pink\", \"green\"]\n"
            "key_colours = [\"blue\", \"yellow\"]\n"
            "[[pattern]]\npattern = \"triangle\"\nid_colours = [\"pink\", \"cyan\", \"green\"]\n"
            "key_colours = [\"blue\", \"yellow\"]\n");
  const std::string other =
      WriteDetectShard(formats::LoadExperimentFile(dir.Path("experiments/e.toml")), 2, 2, dir);
  EXPECT_INPUT_ERROR_STARTS_WITH(
      MergeShards({dir.Path("shards/det.shard-1-of-2.json"), other}, dir.Path("out"), ""),
      other + ": shard of experiment 'det', seed 5, patlab " + PATLAB_VERSION + ", fingerprint ");
}

TEST(Shard, MissingRepeatedAndForeignSharesAreNamed) {
  const Experiment e = Small();
  testing::TempDir dir;
  const std::string s1 = WriteKnownShard(e, 1, 4, dir);
  const std::string s3 = WriteKnownShard(e, 3, 4, dir);
  const std::string fp =
      nlohmann::json::parse(testing::ReadFile(s1))["fingerprint"].get<std::string>();
  EXPECT_INPUT_ERROR(MergeShards({s1, s3}, dir.Path("out"), ""),
                     "missing shards 2/4, 4/4 of experiment 'small', seed 9, patlab " +
                         std::string(PATLAB_VERSION) + ", fingerprint " + fp +
                         "; expected one file for each share 1..4; nothing written");
  EXPECT_INPUT_ERROR(MergeShards({s1, s3, s1}, dir.Path("out"), ""),
                     s1 + ": share 1/4 again (also " + s1 + "); expected each share once");
  // Another seed is another experiment.
  testing::TempDir other_dir;
  const std::string other = WriteKnownShard(Small(10), 2, 4, other_dir);
  const std::string other_fp =
      nlohmann::json::parse(testing::ReadFile(other))["fingerprint"].get<std::string>();
  EXPECT_INPUT_ERROR(MergeShards({s1, other}, dir.Path("out"), ""),
                     other + ": shard of experiment 'small', seed 10, patlab " +
                         std::string(PATLAB_VERSION) + ", fingerprint " + other_fp +
                         "; expected a shard of experiment 'small', seed 9, patlab " +
                         PATLAB_VERSION + ", fingerprint " + fp + " like " + s1);
  // Another share count.
  const std::string s2of3 = WriteKnownShard(e, 2, 3, other_dir);
  EXPECT_INPUT_ERROR(MergeShards({s1, s2of3}, dir.Path("out"), ""),
                     s2of3 + ": shard 2/3; expected a share of N = 4 like " + s1);
}

// A shard edited consistently (checksum recomputed as shard.cpp does) to claim another patlab
// version is refused by version.
TEST(Shard, ShardsOfAnotherPatlabVersionAreRefused) {
  const Experiment e = Small();
  testing::TempDir dir;
  const std::string s1 = WriteKnownShard(e, 1, 1, dir);
  nlohmann::json j = nlohmann::json::parse(testing::ReadFile(s1));
  j["version"] = "0.0.9";
  j.erase("checksum");
  j["checksum"] = StringPrintf(
      "%016llx",
      static_cast<unsigned long long>(StreamKey(0).Add(std::string_view(j.dump())).value()));
  dir.Write(ShardFileName("small", {1, 1}), j.dump(1) + "\n");
  EXPECT_INPUT_ERROR(MergeShards({s1}, dir.Path("out"), ""),
                     s1 + ": written by patlab \"0.0.9\"; expected " + PATLAB_VERSION +
                         " (this patlab): rerun the shard with this version");
}

TEST(Shard, TruncatedOrEditedShardsAreRefused) {
  const Experiment e = Small();
  testing::TempDir dir;
  const std::string s1 = WriteKnownShard(e, 1, 2, dir);
  const std::string s2 = WriteKnownShard(e, 2, 2, dir);
  const std::string text = testing::ReadFile(s2);
  const std::string expected = "; expected a shard file as 'patlab simulate --shard K/N' wrote it";
  dir.Write(ShardFileName("small", {2, 2}), text.substr(0, text.size() / 2));
  EXPECT_INPUT_ERROR(MergeShards({s1, s2}, dir.Path("out"), ""),
                     s2 + ": not JSON (truncated or edited?)" + expected);
  // One digit of one result changed: the checksum no longer matches.
  std::string edited = text;
  const size_t row = edited.find("\"butterfly,fast,");
  ASSERT_NE(row, std::string::npos);
  const size_t digit = edited.find_first_of("123456789", row + 30);
  edited[digit] = edited[digit] == '9' ? '8' : static_cast<char>(edited[digit] + 1);
  dir.Write(ShardFileName("small", {2, 2}), edited);
  EXPECT_INPUT_ERROR_STARTS_WITH(MergeShards({s1, s2}, dir.Path("out"), ""), s2 + ": checksum \"");
  dir.Write(ShardFileName("small", {2, 2}), "{\"format\": \"something else\"}");
  EXPECT_INPUT_ERROR(MergeShards({s1, s2}, dir.Path("out"), ""),
                     s2 + ": not a patlab shard file (no \"format\": \"patlab shard\")" + expected);
  testing::TempDir empty;
  EXPECT_INPUT_ERROR(MergeShards({empty.Path("")}, dir.Path("out"), ""),
                     empty.Path("") + ": no *.shard-K-of-N.json files; expected shard files");
  EXPECT_INPUT_ERROR(MergeShards({}, dir.Path("out"), ""),
                     "no shard files given; expected SHARD... (files or dirs)");
  EXPECT_INPUT_ERROR(MergeShards({dir.Path("nothing")}, dir.Path("out"), ""),
                     dir.Path("nothing") +
                         ": cannot read; expected a shard file written by 'patlab simulate "
                         "--shard'");
}

}  // namespace
}  // namespace patlab::sim
