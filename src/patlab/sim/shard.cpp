#include "patlab/sim/shard.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/core/rng.h"
#include "patlab/io/atomic_file.h"
#include "patlab/sim/point_key.h"
#include "patlab/sim/report.h"

#include "patlab/sim/shard_internal.h"

namespace patlab::sim {

using namespace shard_detail;  // NOLINT(google-build-using-namespace)

namespace {

std::string ShardText(const Experiment& experiment, const std::string& manifest_text,
                      const std::string& header, json points, const ShardSpec& shard,
                      const std::string& base, int64_t points_total, json run,
                      json blocks = json::array(), int64_t blocks_per_point = 1) {
  json s;
  s["format"] = kFormat;
  s["format_version"] = kFormatVersion;
  s["version"] = PATLAB_VERSION;
  s["name"] = base;
  s["mode"] = std::string(NameOf(experiment.correspondence, kCorrespondenceNames));
  s["manifest"] = ExperimentPart(manifest_text);
  s["fingerprint"] = Fingerprint(s["manifest"], experiment);
  s["shard"] = shard.index;
  s["shards"] = shard.count;
  s["points_total"] = points_total;
  s["csv_header"] = header;
  s["points"] = std::move(points);
  s["blocks_per_point"] = blocks_per_point;
  s["blocks"] = std::move(blocks);
  s["noise"] = experiment.noise.Describe();
  s["run"] = std::move(run);
  s["checksum"] = Checksum(s);
  return s.dump(1) + "\n";
}

template <typename Result>
json RunPart(const Result& result, const std::string& command_line) {
  return json{{"command_line", command_line},
              {"threads", result.threads},
              {"timings_s",
               {{"simulate", result.simulate_seconds},
                {"statistics", result.statistics_seconds},
                {"wall", result.wall_seconds}}}};
}

}  // namespace

ShardSpec ParseShardSpec(std::string_view text, std::string_view flag) {
  const std::string expected =
      "; expected K/N with integers 1 <= K <= N <= " + std::to_string(kMaxShards) + ", e.g. 2/8";
  const size_t slash = text.find('/');
  ShardSpec spec;
  const auto parse = [](std::string_view part, int* value) {
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), *value);
    return !part.empty() && ec == std::errc() && end == part.data() + part.size();
  };
  if (slash == std::string_view::npos || !parse(text.substr(0, slash), &spec.index) ||
      !parse(text.substr(slash + 1), &spec.count) || spec.count < 1 || spec.count > kMaxShards ||
      spec.index < 1 || spec.index > spec.count) {
    throw InputError(std::string(flag) + " is '" + std::string(text) + "'" + expected);
  }
  return spec;
}

std::string ShardFileName(const std::string& base, const ShardSpec& shard) {
  return base + ".shard-" + std::to_string(shard.index) + "-of-" + std::to_string(shard.count) +
         ".json";
}

std::string KnownShardText(const Experiment& experiment, const RunResult& result,
                           const ShardSpec& shard, const std::string& base,
                           const std::string& command_line) {
  json points = json::array();
  std::string header;
  for (const PointResult& p : result.points) {
    RunResult one;
    one.points = {p};
    int64_t nonconverged = 0;
    for (const EstimatorResult& r : p.estimators) nonconverged += r.nonconverged;
    points.push_back(PointEntry(p.point, p.trials, nonconverged,
                                SplitRows(ResultsCsv(experiment, one), &header)));
  }
  if (header.empty()) SplitRows(ResultsCsv(experiment, RunResult{}), &header);
  const int64_t total =
      static_cast<int64_t>(experiment.patterns.size() * experiment.sigmas_mm.size());
  // Trial-range shares: each block with the header of its point (block_headers runs in the order
  // of the points the blocks belong to).
  json blocks = json::array();
  size_t h = 0;
  for (size_t i = 0; i < result.blocks.size(); ++i) {
    if (i > 0 && result.blocks[i].work.point != result.blocks[i - 1].work.point) ++h;
    blocks.push_back(BlockEntry(result.block_headers.at(h), result.blocks[i]));
  }
  return ShardText(experiment, ManifestJson(experiment, result, {}), header, std::move(points),
                   shard, base, total, RunPart(result, command_line), std::move(blocks),
                   BlocksPerPoint(experiment.trials, kStatisticsBlockTrials));
}

std::string DetectShardText(const Experiment& experiment, const DetectRunResult& result,
                            const ShardSpec& shard, const std::string& base,
                            const std::string& command_line) {
  json points = json::array();
  std::string header;
  for (const DetectPointResult& p : result.points) {
    DetectRunResult one;
    one.points = {p};
    points.push_back(
        PointEntry(p.point, p.frames, 0, SplitRows(DetectResultsCsv(experiment, one), &header)));
  }
  if (header.empty()) SplitRows(DetectResultsCsv(experiment, DetectRunResult{}), &header);
  // Trial-range shares: each block with the header of its point (as KnownShardText).
  json blocks = json::array();
  size_t h = 0;
  for (size_t i = 0; i < result.blocks.size(); ++i) {
    if (i > 0 && result.blocks[i].work.point != result.blocks[i - 1].work.point) ++h;
    blocks.push_back(DetectBlockEntry(result.block_headers.at(h), result.blocks[i]));
  }
  return ShardText(experiment, DetectManifestJson(experiment, result, {}), header,
                   std::move(points), shard, base, NumDetectPoints(experiment),
                   RunPart(result, command_line), std::move(blocks),
                   BlocksPerPoint(experiment.detect.frames, kStatisticsBlockFrames));
}

}  // namespace patlab::sim
