// Cases of the malformed-input suite (malformed_cases.h): shard files given to `patlab merge`,
// truncated, edited (the checksum no longer matches) or forged (edited with the checksum
// recomputed, as a forger or a buggy tool would): each is refused naming the file and what is
// wrong, before anything is written (docs/merge.md).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "malformed_case.h"
#include "patlab/core/format.h"
#include "patlab/core/rng.h"

namespace patlab::testing {

// The two shards of a small experiment, written by the real tool into DIR/shards.
inline void WriteTwoShards(const std::string& dir) {
  WriteBytes(dir + "e.toml", "name = \"e\"\npatterns_dir = \"" PATLAB_SOURCE_DIR
                             "/patterns\"\npatterns = [\"butterfly\"]\ntrials = 100\nseed = "
                             "1\n[sigma]\nvalues = [1, 2]\n");
  for (const char* share : {"1/2", "2/2"}) {
    const std::string command = std::string(PATLAB_BINARY) + " simulate " + dir +
                                "e.toml -q --shard " + share + " --out " + dir + "shards";
    if (std::system(command.c_str()) != 0) std::abort();
  }
  std::filesystem::remove(dir + "e.toml");
}

inline std::string ShardTwo(const std::string& dir) { return dir + "shards/e.shard-2-of-2.json"; }

inline std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Shard 2 edited by `edit`, its checksum recomputed as patlab computes it (a 64-bit StreamKey
// of the content without the checksum).
template <typename Edit>
void ForgeShardTwo(const std::string& dir, Edit edit) {
  WriteTwoShards(dir);
  nlohmann::json j = nlohmann::json::parse(ReadBytes(ShardTwo(dir)));
  edit(j);
  j.erase("checksum");
  j["checksum"] = StringPrintf(
      "%016llx",
      static_cast<unsigned long long>(StreamKey(0).Add(std::string_view(j.dump())).value()));
  WriteBytes(ShardTwo(dir), j.dump(1) + "\n");
}

inline MalformedCase MergeCase(const char* name, int exit_code, const std::string& message,
                               void (*setup)(const std::string&)) {
  return {name, {}, "merge {dir}shards --out {dir}out -q", exit_code, message, setup};
}

inline std::vector<MalformedCase> ShardMalformedCases() {
  using namespace std::string_literals;
  using nlohmann::json;
  return {
      MergeCase("MergeShardTruncated", 2,
                "patlab merge: {dir}shards/e.shard-2-of-2.json: not JSON (truncated or edited?); "
                "expected a shard file as 'patlab simulate --shard K/N' wrote it"s,
                [](const std::string& dir) {
                  WriteTwoShards(dir);
                  const std::string text = ReadBytes(ShardTwo(dir));
                  WriteBytes(ShardTwo(dir), text.substr(0, text.size() / 2));
                }),
      MergeCase("MergeShardEmptyFile", 2,
                "patlab merge: {dir}shards/e.shard-2-of-2.json: not JSON (truncated or edited?); "
                "expected a shard file as 'patlab simulate --shard K/N' wrote it"s,
                [](const std::string& dir) {
                  WriteTwoShards(dir);
                  WriteBytes(ShardTwo(dir), "");
                }),
      MergeCase(
          "MergeShardNotAShard", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: not a patlab shard file (no \"format\": "
          "\"patlab shard\"); expected a shard file as 'patlab simulate --shard K/N' wrote it"s,
          [](const std::string& dir) {
            WriteTwoShards(dir);
            WriteBytes(ShardTwo(dir), "{\"format\": \"something else\"}");
          }),
      MergeCase(
          "MergeShardForgedShortRow", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: point 1 row 1 "
          "'butterfly,fast,2,100,isotropic,-0.09837894008,0.8830350303,0... (381 bytes)' is not "
          "one CSV record of 42 cells; expected a row as the header"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) {
              std::string row = j["points"][0]["rows"][0];
              j["points"][0]["rows"][0] = row.substr(0, row.rfind(','));
            });
          }),
      MergeCase(
          "MergeShardForgedNegativeCount", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: point 1: count -5; expected the 100 of "
          "every point of the experiment"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["points"][0]["count"] = -5; });
          }),
      MergeCase(
          "MergeShardForgedOverflowingCount", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: point 1: count 9223372036854775807; "
          "expected the 100 of every point of the experiment"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["points"][0]["count"] = 9223372036854775807LL; });
          }),
      MergeCase("MergeShardForgedNonconvergedBeyondCount", 2,
                "patlab merge: {dir}shards/e.shard-2-of-2.json: point 1: ml_nonconverged 1000; "
                "expected 0..100"s,
                [](const std::string& dir) {
                  ForgeShardTwo(dir, [](json& j) { j["points"][0]["ml_nonconverged"] = 1000; });
                }),
      MergeCase(
          "MergeShardForgedHeaderNewline", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: csv_header 'pattern\\x0aestimator'; "
          "expected one non-empty line without control characters"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["csv_header"] = "pattern\nestimator"; });
          }),
      MergeCase(
          "MergeShardForgedAbsurdTiming", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: run.timings_s.wall 1e+300; expected "
          "seconds in [0, 31536000]"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["run"]["timings_s"]["wall"] = 1e300; });
          }),
      MergeCase(
          "MergeShardForgedNegativeTiming", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: run.timings_s.simulate -1; expected "
          "seconds in [0, 31536000]"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["run"]["timings_s"]["simulate"] = -1; });
          }),
      MergeCase(
          "MergeShardForgedSlashInName", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: name '../../escaped' holds '/'; expected "
          "a non-empty name of at most 200 bytes of UTF-8 without '/', '\\', control characters or "
          "NUL"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["name"] = "../../escaped"; });
          }),
      MergeCase(
          "MergeShardForgedControlCharInName", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: name 'e\\x01x' holds a control character "
          "or NUL; expected a non-empty name of at most 200 bytes of UTF-8 without '/', '\\', "
          "control characters or NUL"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["name"] = "e\x01x"; });
          }),
      MergeCase(
          "MergeShardForgedPointOutOfRange", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: point 99: index out of range; expected "
          "0..1"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["points"][0]["index"] = 99; });
          }),
      MergeCase(
          "MergeShardForgedThreads", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: run.threads -3; expected 0..1048576"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["run"]["threads"] = -3; });
          }),
      MergeCase(
          "MergeShardForgedFieldType", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: a field is missing or has the wrong "
          "type; expected a shard file as 'patlab simulate --shard K/N' wrote it"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["points"][0]["count"] = "many"; });
          }),
      MergeCase(
          "MergeShardForgedShareOfOtherCount", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: shard 2/3; expected a share of N = 2 "
          "like {dir}shards/e.shard-1-of-2.json"s,
          [](const std::string& dir) { ForgeShardTwo(dir, [](json& j) { j["shards"] = 3; }); }),
      MergeCase(
          "MergeShardForgedNoRows", 2,
          "patlab merge: {dir}shards/e.shard-2-of-2.json: point 1 has no CSV rows; expected at "
          "least one"s,
          [](const std::string& dir) {
            ForgeShardTwo(dir, [](json& j) { j["points"][0]["rows"] = json::array(); });
          }),
  };
}

}  // namespace patlab::testing
