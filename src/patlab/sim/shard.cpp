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

namespace patlab::sim {

namespace {

using nlohmann::json;

constexpr const char* kFormat = "patlab shard";
constexpr int kFormatVersion = 2;  // 2: trial-range shares (blocks)
// The manifest key that describes where a run wrote rather than the experiment: the fingerprint
// leaves it out (a manifest records no other run fact; shards keep theirs under "run").
constexpr const char* kRunKeys[] = {"outputs"};
// The manifest keys that sum over points: each shard holds its part, the merge sums them.
constexpr const char* kTotalKeys[] = {"total_trials", "total_frames", "ml_nonconverged_trials"};

std::string Hex(uint64_t v) { return StringPrintf("%016llx", static_cast<unsigned long long>(v)); }

// The rows of `csv` after its header line, one string per row (without the newline).
std::vector<std::string> SplitRows(const std::string& csv, std::string* header) {
  std::vector<std::string> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, *header);
  while (std::getline(in, line)) rows.push_back(line);
  return rows;
}

// The checksum of a shard: a StreamKey over the dump of everything but the checksum itself.
std::string Checksum(json shard) {
  shard.erase("checksum");
  return Hex(StreamKey(0).Add(std::string_view(shard.dump())).value());
}

// The fingerprint: what the experiment is, by content. The manifest's run-independent part
// without the paths of the files as typed (the experiment, pattern and detector settings files:
// `./exp.toml`, `exp.toml` and an absolute path are one experiment), the content of every
// pattern, and in detect mode every detector pattern's codebook, key colours and the palette
// (what the settings file held; point_key.h).
std::string Fingerprint(json manifest, const Experiment& experiment) {
  if (manifest.contains("experiment")) manifest["experiment"].erase("file");
  if (manifest.contains("patterns")) {
    for (json& p : manifest["patterns"]) p.erase("file");
  }
  if (manifest.contains("detect")) manifest["detect"].erase("settings");
  StreamKey key(0);
  key.Add(std::string_view(manifest.dump()));
  for (const Pattern& p : experiment.patterns) AddPattern(p, &key);
  if (experiment.correspondence == Correspondence::kDetect) {
    const detect::DetectorConfig& config = experiment.detect.detector;
    for (const int index : experiment.detect.detector_pattern) {
      AddDetectorPattern(config.patterns.at(index), config.palette, &key);
      key.Add(config.patterns.at(index).symmetry_tolerance_mm);
    }
  }
  return Hex(key.value());
}

// The manifest without its run keys and totals.
json ExperimentPart(const std::string& manifest_text) {
  json manifest = json::parse(manifest_text);
  for (const char* key : kRunKeys) manifest.erase(key);
  for (const char* key : kTotalKeys) manifest.erase(key);
  return manifest;
}

// One point of a shard: its grid index, trials or frames, ML non-converged trials and CSV rows.
json PointEntry(int64_t index, int64_t count, int64_t nonconverged, std::vector<std::string> rows) {
  return json{{"index", index},
              {"count", count},
              {"ml_nonconverged", nonconverged},
              {"rows", std::move(rows)}};
}

// A number that may be NaN (a bound of a non-isotropic model): JSON has no NaN, so null.
json Number(double v) { return std::isnan(v) ? json(nullptr) : json(v); }
double NumberOf(const json& j) {
  return j.is_null() ? std::nan("") : j.get<double>();  // json::type_error if not a number
}

json MomentsJson(const stats::Moments& m) { return json::array({m.n, m.mean, m.m2}); }
stats::Moments MomentsOf(const json& j) {
  return stats::Moments{j.at(0).get<int64_t>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

// One block of a trial-range share: the point's header (identity and bounds, for FinishPoint)
// and each estimator's block statistics, every number as JSON keeps it (17 significant digits,
// so the merge reads back the runner's bits).
json BlockEntry(const PointResult& header, const PointBlock& block) {
  json estimators = json::array(), bounds = json::array();
  for (const EstimatorResult& r : header.estimators) {
    bounds.push_back({std::string(estimate::EstimatorName(r.estimator)), Number(r.crlb_position_mm),
                      Number(r.crlb_theta_rad), Number(r.predicted_position_mm),
                      Number(r.predicted_theta_rad)});
  }
  for (const EstimatorBlock& b : block.estimators) {
    json e = {{"moments",
               {MomentsJson(b.x), MomentsJson(b.y), MomentsJson(b.theta), MomentsJson(b.radial)}},
              {"sum_sq", b.sum_sq},
              {"ml", {b.iterations, b.nonconverged, b.first_nonconverged_trial}},
              {"vs_fast", nullptr}};
    const Comparison& c = b.vs_fast;
    if (c.computed) {
      e["vs_fast"] = {{"trials", c.trials},
                      {"ks",
                       {{c.ks_x.d, c.ks_x.p_value},
                        {c.ks_y.d, c.ks_y.p_value},
                        {c.ks_theta.d, c.ks_theta.p_value}}},
                      {"wilcoxon", {c.wilcoxon_position.p_value, c.wilcoxon_theta.p_value}}};
    }
    estimators.push_back(std::move(e));
  }
  return json{{"index", block.work.point},
              {"block", block.work.block},
              {"first", block.work.first},
              {"count", block.work.count},
              {"header",
               {{"pattern_index", header.pattern_index},
                {"pattern", header.pattern},
                {"sigma_mm", header.sigma_mm},
                {"trials", header.trials},
                {"bounds", std::move(bounds)}}},
              {"estimators", std::move(estimators)}};
}

// The inverse of BlockEntry; throws json exceptions on a malformed entry.
void ReadBlockEntry(const json& j, PointResult* header, PointBlock* block) {
  block->work = WorkBlock{j.at("index").get<int64_t>(), j.at("block").get<int64_t>(),
                          j.at("first").get<int64_t>(), j.at("count").get<int64_t>()};
  const json& h = j.at("header");
  header->pattern_index = h.at("pattern_index").get<int>();
  header->pattern = h.at("pattern").get<std::string>();
  header->sigma_mm = h.at("sigma_mm").get<double>();
  header->trials = h.at("trials").get<int64_t>();
  header->point = static_cast<uint32_t>(block->work.point);
  header->estimators.clear();
  for (const json& b : h.at("bounds")) {
    EstimatorResult& r = header->estimators.emplace_back();
    if (!estimate::ParseEstimator(b.at(0).get<std::string>(), &r.estimator)) {
      throw json::other_error::create(501, "unknown estimator", nullptr);
    }
    r.crlb_position_mm = NumberOf(b.at(1));
    r.crlb_theta_rad = NumberOf(b.at(2));
    r.predicted_position_mm = NumberOf(b.at(3));
    r.predicted_theta_rad = NumberOf(b.at(4));
  }
  block->estimators.clear();
  for (const json& e : j.at("estimators")) {
    EstimatorBlock& b = block->estimators.emplace_back();
    const json& m = e.at("moments");
    b.x = MomentsOf(m.at(0));
    b.y = MomentsOf(m.at(1));
    b.theta = MomentsOf(m.at(2));
    b.radial = MomentsOf(m.at(3));
    b.sum_sq = e.at("sum_sq").get<double>();
    b.iterations = e.at("ml").at(0).get<int64_t>();
    b.nonconverged = e.at("ml").at(1).get<int64_t>();
    b.first_nonconverged_trial = e.at("ml").at(2).get<int64_t>();
    const json& c = e.at("vs_fast");
    if (c.is_null()) continue;
    b.vs_fast.computed = true;
    b.vs_fast.trials = c.at("trials").get<int64_t>();
    stats::KsResult* ks[3] = {&b.vs_fast.ks_x, &b.vs_fast.ks_y, &b.vs_fast.ks_theta};
    for (int a = 0; a < 3; ++a) {
      ks[a]->d = c.at("ks").at(a).at(0).get<double>();
      ks[a]->p_value = c.at("ks").at(a).at(1).get<double>();
    }
    b.vs_fast.wilcoxon_position.p_value = c.at("wilcoxon").at(0).get<double>();
    b.vs_fast.wilcoxon_theta.p_value = c.at("wilcoxon").at(1).get<double>();
  }
  if (block->estimators.size() != header->estimators.size()) {
    throw json::other_error::create(501, "estimators and bounds differ in number", nullptr);
  }
}

// The detector's counters of a block, in DetectStats order.
json DetectStatsJson(const detect::DetectStats& d) {
  return json::array({d.key_candidates, d.neighbours, d.neighbours_cut, d.correspondences,
                      d.geometry_passed, d.colour_rejected, d.ambiguous, d.missing_fits,
                      d.conflicts, d.detections});
}
detect::DetectStats DetectStatsOf(const json& j) {
  detect::DetectStats d;
  long* fields[] = {&d.key_candidates,  &d.neighbours,      &d.neighbours_cut, &d.correspondences,
                    &d.geometry_passed, &d.colour_rejected, &d.ambiguous,      &d.missing_fits,
                    &d.conflicts,       &d.detections};
  if (j.size() != std::size(fields)) {
    throw json::other_error::create(501, "detector counters: wrong number", nullptr);
  }
  for (size_t k = 0; k < std::size(fields); ++k) *fields[k] = j.at(k).get<long>();
  return d;
}

// One block of a detect-mode trial-range share: the point's header (identity, detector sigma and
// bounds, for FinishDetectPoint), the block's counters and the moments of its pose errors.
json DetectBlockEntry(const DetectPointResult& header, const DetectBlock& b) {
  return json{{"index", b.work.point},
              {"block", b.work.block},
              {"first", b.work.first},
              {"count", b.work.count},
              {"header",
               {{"pattern_index", header.pattern_index},
                {"pattern", header.pattern},
                {"sigma_mm", header.sigma_mm},
                {"false_blob_rate_per_m2", header.false_blob_rate_per_m2},
                {"frames", header.frames},
                {"detector_sigma_mm", header.detector_sigma_mm},
                {"crlb", {Number(header.crlb_position_mm), Number(header.crlb_theta_rad)}}}},
              {"counters",
               {b.robots, b.correct, b.wrong_id, b.unknown_id, b.ambiguous, b.missed,
                b.false_positives, b.false_blobs, b.missing_patches, b.colour_errors}},
              {"detector", DetectStatsJson(b.stats)},
              {"moments", {MomentsJson(b.x), MomentsJson(b.y), MomentsJson(b.theta)}},
              {"tolerance_mm2", Number(b.tolerance_mm2)}};
}

// The inverse of DetectBlockEntry; throws json exceptions on a malformed entry.
void ReadDetectBlockEntry(const json& j, DetectPointResult* header, DetectBlock* b) {
  b->work = WorkBlock{j.at("index").get<int64_t>(), j.at("block").get<int64_t>(),
                      j.at("first").get<int64_t>(), j.at("count").get<int64_t>()};
  const json& h = j.at("header");
  header->pattern_index = h.at("pattern_index").get<int>();
  header->pattern = h.at("pattern").get<std::string>();
  header->sigma_mm = h.at("sigma_mm").get<double>();
  header->false_blob_rate_per_m2 = h.at("false_blob_rate_per_m2").get<double>();
  header->frames = h.at("frames").get<int64_t>();
  header->detector_sigma_mm = h.at("detector_sigma_mm").get<double>();
  header->crlb_position_mm = NumberOf(h.at("crlb").at(0));
  header->crlb_theta_rad = NumberOf(h.at("crlb").at(1));
  header->point = static_cast<uint32_t>(b->work.point);
  const json& c = j.at("counters");
  int64_t* counters[] = {
      &b->robots, &b->correct,         &b->wrong_id,    &b->unknown_id,      &b->ambiguous,
      &b->missed, &b->false_positives, &b->false_blobs, &b->missing_patches, &b->colour_errors};
  if (c.size() != std::size(counters)) {
    throw json::other_error::create(501, "counters: wrong number", nullptr);
  }
  for (size_t k = 0; k < std::size(counters); ++k) *counters[k] = c.at(k).get<int64_t>();
  b->stats = DetectStatsOf(j.at("detector"));
  const json& m = j.at("moments");
  b->x = MomentsOf(m.at(0));
  b->y = MomentsOf(m.at(1));
  b->theta = MomentsOf(m.at(2));
  b->tolerance_mm2 = NumberOf(j.at("tolerance_mm2"));
}

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

namespace {

struct ShardFile {
  std::string path;
  json content;
};

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw InputError(path + ": " + message);
}

std::string Describe(const json& s) {
  return "experiment '" + s["name"].get<std::string>() + "', seed " +
         s["manifest"].value("seed", json()).dump() + ", patlab " +
         s["version"].get<std::string>() + ", fingerprint " + s["fingerprint"].get<std::string>();
}

// A block entry's integer fields (the rest is read when the block is folded: ReadBlockEntry).
bool HasBlockFields(const json& b) {
  if (!b.is_object()) return false;
  for (const char* key : {"index", "block", "first", "count"}) {
    if (!b.contains(key) || !b[key].is_number_integer()) return false;
  }
  return true;
}

// Every field the merge reads, with its type (a shard whose checksum was recomputed after an
// edit still has to be well formed).
bool HasShardFields(const json& s) {
  for (const char* key : {"version", "name", "mode", "fingerprint", "csv_header", "noise"}) {
    if (!s.contains(key) || !s[key].is_string()) return false;
  }
  for (const char* key : {"shard", "shards", "points_total", "blocks_per_point"}) {
    if (!s.contains(key) || !s[key].is_number_integer()) return false;
  }
  if (!s.contains("manifest") || !s["manifest"].is_object() || !s.contains("run") ||
      !s["run"].is_object() || !s.contains("points") || !s["points"].is_array() ||
      !s.contains("blocks") || !s["blocks"].is_array()) {
    return false;
  }
  const json& run = s["run"];
  if (!run.contains("threads") || !run["threads"].is_number_integer() ||
      !run.contains("timings_s") || !run["timings_s"].is_object()) {
    return false;
  }
  for (const char* key : {"simulate", "statistics", "wall"}) {
    if (!run["timings_s"].contains(key) || !run["timings_s"][key].is_number()) return false;
  }
  for (const json& p : s["points"]) {
    if (!p.is_object() || !p.contains("rows") || !p["rows"].is_array()) return false;
    for (const char* key : {"index", "count", "ml_nonconverged"}) {
      if (!p.contains(key) || !p[key].is_number_integer()) return false;
    }
    for (const json& row : p["rows"]) {
      if (!row.is_string()) return false;
    }
  }
  if (!std::all_of(s["blocks"].begin(), s["blocks"].end(), HasBlockFields)) return false;
  return s["shards"].get<int64_t>() >= 1 && s["shards"].get<int64_t>() <= kMaxShards &&
         s["blocks_per_point"].get<int64_t>() >= 1 && s["points_total"].get<int64_t>() >= 0;
}

// Reads one shard file and checks it on its own: JSON, the format, the checksum, the fields.
ShardFile ReadShard(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail(path, "cannot read; expected a shard file written by 'patlab simulate --shard'");
  std::ostringstream text;
  text << in.rdbuf();
  ShardFile file{path, json::parse(text.str(), nullptr, false)};
  const json& s = file.content;
  const std::string expected = "; expected a shard file as 'patlab simulate --shard K/N' wrote it";
  if (s.is_discarded()) Fail(path, "not JSON (truncated or edited?)" + expected);
  if (!s.is_object() || s.value("format", "") != kFormat) {
    Fail(path, "not a patlab shard file (no \"format\": \"patlab shard\")" + expected);
  }
  if (s.value("format_version", 0) != kFormatVersion) {
    Fail(path, "shard format version " + s.value("format_version", json()).dump() + "; expected " +
                   std::to_string(kFormatVersion));
  }
  if (!s.contains("checksum") || s["checksum"] != Checksum(s)) {
    Fail(path, "checksum " + s.value("checksum", json()).dump() + " does not match the content (" +
                   Checksum(s) + "): the file was edited or truncated" + expected);
  }
  if (!HasShardFields(s)) Fail(path, "a field is missing or has the wrong type" + expected);
  if (s.value("version", "") != PATLAB_VERSION) {
    Fail(path, "written by patlab " + s.value("version", json()).dump() + "; expected " +
                   PATLAB_VERSION + " (this patlab): rerun the shard with this version");
  }
  return file;
}

// Every shard against the first: the same experiment (fingerprint), mode and share count.
void CheckSameExperiment(const ShardFile& first, const ShardFile& f) {
  const json &a = first.content, &b = f.content;
  if (a["fingerprint"] != b["fingerprint"] || a["mode"] != b["mode"] ||
      a["points_total"] != b["points_total"] || a["csv_header"] != b["csv_header"]) {
    Fail(f.path, "shard of " + Describe(b) + "; expected a shard of " + Describe(a) + " like " +
                     first.path);
  }
  if (a["shards"] != b["shards"]) {
    Fail(f.path, "shard " + b["shard"].dump() + "/" + b["shards"].dump() +
                     "; expected a share of N = " + a["shards"].dump() + " like " + first.path);
  }
}

// A trial-range share's blocks must be exactly the items ShareBlocks assigns to it (item =
// point x blocks_per_point + block), each the block ShareBlocks makes of its point's trials.
void CheckBlocks(const ShardFile& f) {
  const json& s = f.content;
  const ShardSpec spec{s["shard"].get<int>(), s["shards"].get<int>()};
  const int64_t per = s["blocks_per_point"].get<int64_t>();
  if (!s["points"].empty()) Fail(f.path, "holds whole points and blocks; expected only blocks");
  int64_t next = spec.index - 1;
  for (const json& b : s["blocks"]) {
    const int64_t item = b["index"].get<int64_t>() * per + b["block"].get<int64_t>();
    if (b["block"].get<int64_t>() < 0 || b["block"].get<int64_t>() >= per || item != next) {
      Fail(f.path, "holds block " + b["block"].dump() + " of point " + b["index"].dump() +
                       "; expected item " + std::to_string(next) + " (point " +
                       std::to_string(next / per) + ", block " + std::to_string(next % per) +
                       ") of share " + std::to_string(spec.index) + "/" +
                       std::to_string(spec.count));
    }
    next += spec.count;
  }
  if (next < s["points_total"].get<int64_t>() * per) {
    Fail(f.path, "ends before item " + std::to_string(next) + " of " +
                     std::to_string(s["points_total"].get<int64_t>() * per) +
                     "; expected every block of its share");
  }
}

// The share's points must be exactly those ShardSpec::Holds assigns to it.
void CheckPoints(const ShardFile& f) {
  const json& s = f.content;
  // With more than one share and points of more than one block, no share holds a whole point.
  if (s["blocks_per_point"].get<int64_t>() > 1 && s["shards"].get<int64_t>() > 1) {
    return CheckBlocks(f);
  }
  if (!s["blocks"].empty()) Fail(f.path, "holds blocks of one-block points; expected none");
  const ShardSpec spec{s["shard"].get<int>(), s["shards"].get<int>()};
  int64_t next = spec.index - 1;
  for (const json& p : s["points"]) {
    if (p["index"].get<int64_t>() != next) {
      Fail(f.path, "holds point " + p["index"].dump() + "; expected point " + std::to_string(next) +
                       " of share " + std::to_string(spec.index) + "/" +
                       std::to_string(spec.count));
    }
    next += spec.count;
  }
  if (next < s["points_total"].get<int64_t>()) {
    Fail(f.path, "ends before point " + std::to_string(next) + " of " + s["points_total"].dump() +
                     "; expected every point of its share");
  }
}

std::vector<std::string> ExpandInputs(const std::vector<std::string>& inputs) {
  std::vector<std::string> paths;
  for (const std::string& input : inputs) {
    std::error_code ec;
    if (!std::filesystem::is_directory(input, ec)) {
      paths.push_back(input);
      continue;
    }
    std::vector<std::string> found;
    for (const auto& entry : std::filesystem::directory_iterator(input, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.find(".shard-") != std::string::npos && name.ends_with(".json")) {
        found.push_back(entry.path().string());
      }
    }
    if (found.empty()) Fail(input, "no *.shard-K-of-N.json files; expected shard files");
    std::sort(found.begin(), found.end());
    paths.insert(paths.end(), found.begin(), found.end());
  }
  return paths;
}

// Orders the shards by K, refusing repeats and naming every missing share.
std::vector<const ShardFile*> ByShare(const std::vector<ShardFile>& files) {
  const int count = files.front().content["shards"].get<int>();
  std::vector<const ShardFile*> by_share(count, nullptr);
  for (const ShardFile& f : files) {
    const int k = f.content["shard"].get<int>();
    if (k < 1 || k > count) Fail(f.path, "shard " + std::to_string(k) + "; expected 1..N");
    if (by_share[k - 1] != nullptr) {
      Fail(f.path, "share " + std::to_string(k) + "/" + std::to_string(count) + " again (also " +
                       by_share[k - 1]->path + "); expected each share once");
    }
    by_share[k - 1] = &f;
  }
  std::string missing;
  for (int k = 1; k <= count; ++k) {
    if (by_share[k - 1] == nullptr) {
      missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(count);
    }
  }
  if (!missing.empty()) {
    throw InputError("missing shards " + missing + " of " + Describe(files.front().content) +
                     "; expected one file for each share 1.." + std::to_string(count) +
                     "; nothing written");
  }
  return by_share;
}

// The merged manifest: the experiment part, the totals summed over points, and the files
// written: the bytes a single process writes (report.h).
std::string MergedManifest(const std::vector<const ShardFile*>& shards,
                           const std::vector<std::string>& out) {
  json m = shards.front()->content["manifest"];
  const bool known = shards.front()->content["mode"] == "known";
  int64_t total = 0, nonconverged = 0;
  for (const ShardFile* f : shards) {
    for (const json& p : f->content["points"]) {
      total += p["count"].get<int64_t>();
      nonconverged += p["ml_nonconverged"].get<int64_t>();
    }
    for (const json& b : f->content["blocks"]) {
      total += b["count"].get<int64_t>();
      if (!known) continue;  // detect-mode blocks have no estimators
      for (const json& e : b["estimators"]) nonconverged += e["ml"][1].get<int64_t>();
    }
  }
  if (known) {
    m["ml_nonconverged_trials"] = nonconverged;
    m["total_trials"] = total;
  } else {
    m["total_frames"] = total;
  }
  m["outputs"] = io::OutputNames(out);
  return m.dump(2) + "\n";
}

// A finished point's trials (frames).
int64_t CountOf(const PointResult& p) { return p.trials; }
int64_t CountOf(const DetectPointResult& p) { return p.frames; }

// Reads one block entry of a trial-range share with `read`, naming the file and the block when
// it is malformed.
template <typename Header, typename Block, typename Read>
void ReadBlock(const json& entry, const ShardFile& file, Read read, Header* header, Block* block) {
  try {
    read(entry, header, block);
  } catch (const json::exception& e) {
    // Appended piece by piece: GCC 12's -Wrestrict misfires on "literal" + std::string.
    std::string message = "block ";
    message.append(entry.value("block", json()).dump()).append(" of point ");
    message.append(entry.value("index", json()).dump());
    message.append(" is malformed (").append(e.what());
    message.append("); expected a shard as 'patlab simulate --shard' wrote it");
    Fail(file.path, message);
  }
}

// One point of trial-range shares from its blocks (in block order): read with `read`, finished
// with `finish` as the runner finishes it, written as its CSV rows with `rows`.
template <typename Header, typename Block, typename Read, typename Finish, typename Rows>
json FinishOnePoint(int64_t index,
                    const std::map<int64_t, std::pair<const json*, const ShardFile*>>& entries,
                    Read read, Finish finish, Rows rows) {
  Header header;
  std::vector<Block> blocks;
  for (const auto& [block, entry] : entries) {
    Header h;
    ReadBlock(*entry.first, *entry.second, read, &h, &blocks.emplace_back());
    if (block == 0) header = h;
  }
  const auto point = finish(header, std::span<const Block>(blocks));
  std::string unused, csv = "\n";  // SplitRows skips a header line
  csv.append(rows({&point, 1}));
  std::vector<std::string> lines = SplitRows(csv, &unused);
  return PointEntry(index, CountOf(point), 0, std::move(lines));
}

// The points of trial-range shares: each point's blocks from every share, in block order,
// finished as the runner finishes them (FinishPoint, FinishDetectPoint) and written as its CSV
// rows.
json FinishBlockPoints(const std::vector<const ShardFile*>& shards) {
  std::map<int64_t, std::map<int64_t, std::pair<const json*, const ShardFile*>>> by_point;
  for (const ShardFile* f : shards) {
    for (const json& b : f->content["blocks"]) {
      by_point[b["index"].get<int64_t>()][b["block"].get<int64_t>()] = {&b, f};
    }
  }
  json points = json::array();
  const std::string noise = shards.front()->content["noise"].get<std::string>();
  const bool known = shards.front()->content["mode"] == "known";
  for (const auto& [index, blocks] : by_point) {
    if (known) {
      points.push_back(FinishOnePoint<PointResult, PointBlock>(
          index, blocks, ReadBlockEntry, FinishPoint,
          [&noise](std::span<const PointResult> p) { return ResultsCsvRows(noise, p); }));
    } else {
      points.push_back(FinishOnePoint<DetectPointResult, DetectBlock>(
          index, blocks, ReadDetectBlockEntry, FinishDetectPoint,
          [&noise](std::span<const DetectPointResult> p) {
            return DetectResultsCsvRows(noise, p);
          }));
    }
  }
  return points;
}

}  // namespace

MergedOutputs MergeShards(const std::vector<std::string>& inputs, const std::string& out_dir,
                          const std::string& name) {
  const std::vector<std::string> paths = ExpandInputs(inputs);
  if (paths.empty()) throw InputError("no shard files given; expected SHARD... (files or dirs)");
  std::vector<ShardFile> files;
  for (const std::string& path : paths) files.push_back(ReadShard(path));
  for (const ShardFile& f : files) {
    CheckSameExperiment(files.front(), f);
    CheckPoints(f);
  }
  const std::vector<const ShardFile*> shards = ByShare(files);

  std::map<int64_t, const json*> rows_by_point;
  for (const ShardFile* f : shards) {
    for (const json& p : f->content["points"]) rows_by_point[p["index"].get<int64_t>()] = &p;
  }
  const json finished = FinishBlockPoints(shards);
  for (const json& p : finished) rows_by_point[p["index"].get<int64_t>()] = &p;
  MergedOutputs out;
  const json& first = shards.front()->content;
  const std::string base = name.empty() ? first["name"].get<std::string>() : name;
  out.csv_path = (std::filesystem::path(out_dir) / (base + ".csv")).string();
  out.json_path = (std::filesystem::path(out_dir) / (base + ".json")).string();
  out.csv = first["csv_header"].get<std::string>() + "\n";
  for (const auto& [index, point] : rows_by_point) {
    for (const json& row : (*point)["rows"]) out.csv += row.get<std::string>() + "\n";
  }
  out.json = MergedManifest(shards, {out.csv_path, out.json_path});
  return out;
}

}  // namespace patlab::sim
