// The JSON form of a shard's entries (shard_internal.h).
#include <cmath>
#include <string_view>

#include "patlab/core/format.h"
#include "patlab/core/rng.h"
#include "patlab/io/csv.h"
#include "patlab/sim/point_key.h"
#include "patlab/sim/shard_internal.h"

namespace patlab::sim::shard_detail {

std::string Hex(uint64_t v) { return StringPrintf("%016llx", static_cast<unsigned long long>(v)); }

std::vector<std::string> SplitRows(const std::string& csv, std::string* header) {
  std::vector<std::string> rows;
  for (const std::vector<std::string>& record : io::ParseCsvRecords(csv, "results")) {
    std::string row = io::CsvRow(record);
    row.pop_back();  // its "\n"
    rows.push_back(std::move(row));
  }
  *header = rows.empty() ? "" : rows.front();
  if (!rows.empty()) rows.erase(rows.begin());
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

}  // namespace patlab::sim::shard_detail
