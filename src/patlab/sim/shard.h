// Sweeps split across processes or machines (docs/merge.md): `patlab simulate EXP --shard K/N`
// computes only share K of N and writes one shard file; `patlab merge` checks that every share
// of one experiment is present and intact and writes the CSV and manifest the unsharded run
// writes, byte for byte.
//
// A share is whole data points: point i of the grid (the runner's order: pattern-major, then
// false-blob rate in detect mode, then sigma) belongs to share (i mod N) + 1, so every share mixes
// cheap and expensive points. A point's random numbers depend only on what it is (point_key.h),
// so a point computed in any share is the point of the unsharded run, and its CSV rows are the
// same bytes. Known-correspondence and detect-mode experiments shard alike; a point of more than
// one block of trials (frames) is shared out block by block, and the merge folds its blocks with
// the runners' FinishPoint / FinishDetectPoint (docs/merge.md).
//
// A shard file is JSON: the format tag and version, the patlab version, the experiment's
// fingerprint (a StreamKey of its content: the manifest without file paths, every pattern, and in
// detect mode the codebooks and palette; two shards merge only when they come from the same
// experiment, seed, grid and patlab version, however its path was typed), the share K/N,
// the points it holds with their CSV rows and totals, the manifest's run-independent part, and a
// checksum of all of it, so a truncated or edited shard is refused.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/sim/detect_runner.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/runner.h"

namespace patlab::sim {

// ShardSpec (runner.h): share K of N.

// Parses "K/N"; messages name `flag`: "--shard is '0/3'; expected K/N with integers
// 1 <= K <= N <= 100000, e.g. 2/8".
ShardSpec ParseShardSpec(std::string_view text, std::string_view flag);

// "<base>.shard-K-of-N.json": the file `patlab simulate --shard K/N --name base` writes.
std::string ShardFileName(const std::string& base, const ShardSpec& shard);

// The shard file of a known-correspondence run (RunOptions::shard) or a detect-mode run;
// `base` is the output base name the merge will use.
std::string KnownShardText(const Experiment& experiment, const RunResult& result,
                           const ShardSpec& shard, const std::string& base,
                           const std::string& command_line);
std::string DetectShardText(const Experiment& experiment, const DetectRunResult& result,
                            const ShardSpec& shard, const std::string& base,
                            const std::string& command_line);

// What `patlab merge` writes: <out_dir>/<base>.csv and <base>.json.
struct MergedOutputs {
  std::string csv_path, csv;
  std::string json_path, json;
};

// Reads the shard files (a directory stands for every *.shard-*-of-*.json in it), checks them
// and merges them. Throws InputError, before anything is written, naming the file and what was
// expected when a file is not an intact shard, comes from another experiment, seed or patlab
// version, repeats a share, or when shares are missing (all of them named). `name` overrides
// the base name recorded in the shards. `progress` (optional) is called after each shard file
// is read and checked: (files read, files in all).
MergedOutputs MergeShards(const std::vector<std::string>& inputs, const std::string& out_dir,
                          const std::string& name,
                          const std::function<void(int, int)>& progress = {});

}  // namespace patlab::sim
