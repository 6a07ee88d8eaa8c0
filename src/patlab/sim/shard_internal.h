// Inside the shards (shard.h): the constants of the shard format and the JSON form of its entries,
// shared by the writing of a shard (shard.cpp) and the merge (shard_merge.cpp).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "patlab/sim/detect_runner.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/runner.h"

namespace patlab::sim::shard_detail {

using nlohmann::json;

inline constexpr const char* kFormat = "patlab shard";
inline constexpr int kFormatVersion = 2;  // 2: trial-range shares (blocks)
// The manifest key that describes where a run wrote rather than the experiment: the fingerprint
// leaves it out (a manifest records no other run fact; shards keep theirs under "run").
inline constexpr const char* kRunKeys[] = {"outputs"};
// The manifest keys that sum over points: each shard holds its part, the merge sums them.
inline constexpr const char* kTotalKeys[] = {"total_trials", "total_frames",
                                             "ml_nonconverged_trials"};

std::string Hex(uint64_t v);
// The rows of the CSV text `csv` after its header (`*header`), one string per row without its
// line end (a row's quoted cells may hold line breaks), each written as io/csv.h writes it.
std::vector<std::string> SplitRows(const std::string& csv, std::string* header);
// The checksum of a shard: a StreamKey over the dump of everything but the checksum itself.
std::string Checksum(json shard);
// The fingerprint: what the experiment is, by content (shard_entries.cpp).
std::string Fingerprint(json manifest, const Experiment& experiment);
// The manifest without its run keys and totals.
json ExperimentPart(const std::string& manifest_text);
// One point of a shard: its grid index, trials or frames, ML non-converged trials and CSV rows.
json PointEntry(int64_t index, int64_t count, int64_t nonconverged, std::vector<std::string> rows);
// One block of a trial-range share and its inverse (json exceptions on a malformed entry).
json BlockEntry(const PointResult& header, const PointBlock& block);
void ReadBlockEntry(const json& j, PointResult* header, PointBlock* block);
// The same for a detect-mode block.
json DetectBlockEntry(const DetectPointResult& header, const DetectBlock& b);
void ReadDetectBlockEntry(const json& j, DetectPointResult* header, DetectBlock* b);

// Every problem of a shard's values, once its fields have their types (shard_check.cpp): the name
// a file base name, the CSV header one line and each row one record of its cells, every point's
// count the experiment's per point, counts and ranges within bounds, every number finite, the
// run's timings within a year. Each problem reads "<what> <value>; expected <what>".
std::vector<std::string> ShardProblems(const json& shard);
// The first `shown` items joined by "; ", then "; ... and 99,990 more": a merge of 100,000 bad
// shards prints a few lines, not megabytes.
inline constexpr size_t kProblemsShown = 10;
std::string CappedList(const std::vector<std::string>& items, size_t shown = kProblemsShown);

}  // namespace patlab::sim::shard_detail
