// The values of a shard checked before a merge writes anything (shard_internal.h): names, the CSV
// header and rows, counts and their sums, finite numbers and sane timings.
#include <algorithm>
#include <cmath>
#include <string_view>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/csv.h"
#include "patlab/io/name.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/shard_internal.h"

namespace patlab::sim::shard_detail {

namespace {

// A run's timings above a year are not a run's.
constexpr double kMaxSeconds = 365.0 * 24 * 3600;
constexpr int64_t kMaxThreads = 1 << 20;

// 99990 -> "99,990".
std::string Thousands(int64_t n) {
  std::string digits = std::to_string(n), text;
  for (size_t k = 0; k < digits.size(); ++k) {
    if (k > 0 && (digits.size() - k) % 3 == 0) text += ',';
    text += digits[k];
  }
  return text;
}

bool HasControlByte(std::string_view text) {
  for (const char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return true;
  }
  return false;
}

// Every number of the tree `j` at `where`, non-finite ones named (a JSON parser may turn 1e999
// into infinity).
void CheckFinite(const json& j, const std::string& where, std::vector<std::string>* problems) {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    problems->push_back(where + " is " + j.dump() + "; expected a finite number");
  } else if (j.is_object()) {
    for (const auto& [key, value] : j.items()) CheckFinite(value, where + "." + key, problems);
  } else if (j.is_array()) {
    for (size_t k = 0; k < j.size(); ++k) {
      CheckFinite(j[k], where + "[" + std::to_string(k) + "]", problems);
    }
  }
}

// The trials (frames) of every point: the manifest's per-point count.
int64_t PerPoint(const json& s) {
  const json& m = s["manifest"];
  const char* key = s["mode"] == "known" ? "trials_per_point" : "frames_per_point";
  return m.contains(key) && m[key].is_number_integer() ? m[key].get<int64_t>() : -1;
}

void CheckRows(const json& p, size_t columns, const std::string& where,
               std::vector<std::string>* problems) {
  if (p["rows"].empty()) problems->push_back(where + " has no CSV rows; expected at least one");
  for (size_t r = 0; r < p["rows"].size(); ++r) {
    const std::string& row = p["rows"][r].get_ref<const std::string&>();
    const std::string at = where + " row " + std::to_string(r + 1);
    std::vector<std::vector<std::string>> records;
    try {
      records = io::ParseCsvRecords(row, "row");
    } catch (const InputError&) {
    }
    if (records.size() != 1 || records[0].size() != columns) {
      problems->push_back(at + " '" + EscapeForMessage(row, 60) + "' is not one CSV record of " +
                          std::to_string(columns) + " cells; expected a row as the header");
    }
  }
}

void CheckPointEntries(const json& s, int64_t per_point, std::vector<std::string>* problems) {
  const int64_t total = s["points_total"].get<int64_t>();
  const size_t columns =
      io::ParseCsvRecords(s["csv_header"].get<std::string>(), "header").at(0).size();
  for (const json& p : s["points"]) {
    const int64_t index = p["index"].get<int64_t>(), count = p["count"].get<int64_t>();
    const std::string where = "point " + std::to_string(index);
    if (index < 0 || index >= total) {
      problems->push_back(where + ": index out of range; expected 0.." + std::to_string(total - 1));
    }
    if (count != per_point) {
      problems->push_back(where + ": count " + std::to_string(count) + "; expected the " +
                          std::to_string(per_point) + " of every point of the experiment");
    }
    const int64_t nonconverged = p["ml_nonconverged"].get<int64_t>();
    if (nonconverged < 0 || nonconverged > std::max<int64_t>(count, 0)) {
      problems->push_back(where + ": ml_nonconverged " + std::to_string(nonconverged) +
                          "; expected 0.." + std::to_string(std::max<int64_t>(count, 0)));
    }
    CheckRows(p, columns, where, problems);
  }
}

void CheckBlockEntries(const json& s, int64_t per_point, std::vector<std::string>* problems) {
  const int64_t total = s["points_total"].get<int64_t>();
  for (const json& b : s["blocks"]) {
    const int64_t index = b["index"].get<int64_t>(), first = b["first"].get<int64_t>();
    const int64_t count = b["count"].get<int64_t>();
    const std::string where = "block " + b["block"].dump() + " of point " + std::to_string(index);
    if (index < 0 || index >= total) {
      problems->push_back(where + ": index out of range; expected 0.." + std::to_string(total - 1));
    }
    if (first < 0 || count < 1 || first > per_point || count > per_point - first) {
      problems->push_back(where + ": trials " + std::to_string(first) + " + " +
                          std::to_string(count) + "; expected a range within 0.." +
                          std::to_string(per_point));
    }
  }
}

void CheckRun(const json& run, std::vector<std::string>* problems) {
  const int64_t threads = run["threads"].get<int64_t>();
  if (threads < 0 || threads > kMaxThreads) {
    problems->push_back("run.threads " + std::to_string(threads) + "; expected 0.." +
                        std::to_string(kMaxThreads));
  }
  for (const auto& [key, value] : run["timings_s"].items()) {
    const double seconds = value.get<double>();
    if (!(seconds >= 0 && seconds <= kMaxSeconds)) {
      problems->push_back("run.timings_s." + key + " " + value.dump() +
                          "; expected seconds in [0, " + FormatNumber(kMaxSeconds) + "]");
    }
  }
}

}  // namespace

std::vector<std::string> ShardProblems(const json& s) {
  std::vector<std::string> problems;
  const std::string& name = s["name"].get_ref<const std::string&>();
  if (const std::string problem = io::NameProblem(name); !problem.empty()) {
    problems.push_back("name '" + EscapeForMessage(name) + "' " + problem + "; expected " +
                       io::kNameExpected);
  }
  const std::string& header = s["csv_header"].get_ref<const std::string&>();
  if (header.empty() || HasControlByte(header)) {
    problems.push_back("csv_header '" + EscapeForMessage(header) +
                       "'; expected one non-empty line without control characters");
    return problems;  // the rows are checked against it
  }
  CheckFinite(s, "shard", &problems);
  const int64_t per_point = PerPoint(s);
  if (per_point < 1 || per_point > kMaxTrials) {
    problems.push_back("manifest's trials (frames) per point " + std::to_string(per_point) +
                       "; expected 1.." + std::to_string(kMaxTrials));
    return problems;
  }
  CheckPointEntries(s, per_point, &problems);
  CheckBlockEntries(s, per_point, &problems);
  CheckRun(s["run"], &problems);
  return problems;
}

std::string CappedList(const std::vector<std::string>& items, size_t shown) {
  std::string text;
  for (size_t k = 0; k < items.size() && k < shown; ++k) {
    text += (k == 0 ? "" : "; ") + items[k];
  }
  if (items.size() > shown) {
    text += "; ... and " + Thousands(static_cast<int64_t>(items.size() - shown)) + " more";
  }
  return text;
}

}  // namespace patlab::sim::shard_detail
