// Merging shards (shard.h): reading and checking every shard, then the merged results.
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

struct ShardFile {
  std::string path;
  json content;
};

[[noreturn]] void Fail(const std::string& path, const std::string& message) {
  throw InputError(EscapeForMessage(path, 1024) + ": " + message);
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
  if (const std::vector<std::string> problems = ShardProblems(s); !problems.empty()) {
    Fail(path, CappedList(problems));
  }
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
  std::vector<std::string> missing;
  for (int k = 1; k <= count; ++k) {
    if (by_share[k - 1] == nullptr) {
      missing.push_back(std::to_string(k) + "/" + std::to_string(count));
    }
  }
  if (!missing.empty()) {
    std::string list = CappedList(missing);
    std::replace(list.begin(), list.end(), ';', ',');
    throw InputError("missing shards " + list + " of " + Describe(files.front().content) +
                     "; expected one file for each share 1.." + std::to_string(count) +
                     "; nothing written");
  }
  return by_share;
}

// The blocks of each point, over every share, must tile its trials: block 0 starts at trial 0,
// each next block where the one before ends, and the counts add up to the point's trials. A
// share whose ranges were forged (each range alone within the point) is named with the block.
void CheckBlockSums(const std::vector<const ShardFile*>& shards) {
  std::map<int64_t, std::map<int64_t, std::pair<const json*, const ShardFile*>>> by_point;
  for (const ShardFile* f : shards) {
    for (const json& b : f->content["blocks"]) {
      by_point[b["index"].get<int64_t>()][b["block"].get<int64_t>()] = {&b, f};
    }
  }
  const json& m = shards.front()->content["manifest"];
  const bool known = shards.front()->content["mode"] == "known";
  const int64_t per_point = m[known ? "trials_per_point" : "frames_per_point"].get<int64_t>();
  for (const auto& [index, blocks] : by_point) {
    int64_t next = 0;
    for (const auto& [block, entry] : blocks) {
      const json& b = *entry.first;
      if (b["first"].get<int64_t>() != next) {
        Fail(entry.second->path,
             "block " + std::to_string(block) + " of point " + std::to_string(index) +
                 " starts at trial " + b["first"].dump() + "; expected " + std::to_string(next) +
                 (block == 0 ? " (a point's first trial)"
                             : ", where block " + std::to_string(block - 1) + " ends"));
      }
      next += b["count"].get<int64_t>();
    }
    if (next != per_point) {
      Fail(blocks.rbegin()->second.second->path,
           "the blocks of point " + std::to_string(index) + " add up to " + std::to_string(next) +
               " trials; expected the " + std::to_string(per_point) + " of every point");
    }
  }
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
                          const std::string& name, const std::function<void(int, int)>& progress) {
  const std::vector<std::string> paths = ExpandInputs(inputs);
  if (paths.empty()) throw InputError("no shard files given; expected SHARD... (files or dirs)");
  std::vector<ShardFile> files;
  std::vector<std::string> problems;
  for (const std::string& path : paths) {
    try {
      files.push_back(ReadShard(path));
    } catch (const InputError& e) {
      problems.push_back(e.what());
    }
    if (progress)
      progress(static_cast<int>(files.size() + problems.size()), static_cast<int>(paths.size()));
  }
  if (problems.size() == 1) throw InputError(problems.front());
  if (!problems.empty()) {
    throw InputError(std::to_string(problems.size()) + " of " + std::to_string(paths.size()) +
                     " shard files are not intact: " + CappedList(problems) + "; nothing written");
  }
  for (const ShardFile& f : files) {
    CheckSameExperiment(files.front(), f);
    CheckPoints(f);
  }
  const std::vector<const ShardFile*> shards = ByShare(files);
  CheckBlockSums(shards);

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
