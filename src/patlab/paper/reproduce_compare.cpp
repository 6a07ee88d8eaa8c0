#include "patlab/paper/reproduce_compare.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/csv.h"
#include "patlab/stats/ks.h"

namespace patlab::paper {

RankAllowance KnifeEdgeAllowance(std::span<const double> abs_a, std::span<const double> abs_b) {
  PATLAB_CHECK(abs_a.size() == abs_b.size());
  struct Difference {
    double magnitude, scale;
    bool positive;
  };
  RankAllowance r;
  r.pairs = static_cast<double>(abs_a.size());
  std::vector<Difference> d;
  d.reserve(abs_a.size());
  for (size_t k = 0; k < abs_a.size(); ++k) {
    const double diff = abs_a[k] - abs_b[k];
    // The drift of |a| - |b| is at most kKnifeEdgeRelative (|a| + |b|).
    const double scale = kKnifeEdgeRelative * (std::abs(abs_a[k]) + std::abs(abs_b[k]));
    if (std::abs(diff) <= scale) {
      r.near_zero += 1.0;
    } else {
      d.push_back({std::abs(diff), scale, diff > 0.0});
    }
  }
  std::sort(d.begin(), d.end(),
            [](const Difference& x, const Difference& y) { return x.magnitude < y.magnitude; });
  // Clusters of consecutive |d| that lie within their drifts of each other: inside one, another
  // machine may order (or tie) the values in any way.
  for (size_t first = 0; first < d.size();) {
    size_t last = first;
    double positive = d[first].positive ? 1.0 : 0.0;
    while (last + 1 < d.size() &&
           d[last + 1].magnitude - d[last].magnitude <= d[last + 1].scale + d[last].scale) {
      ++last;
      positive += d[last].positive ? 1.0 : 0.0;
    }
    const auto m = static_cast<double>(last - first + 1);
    if (m > 1.0) {
      r.opposite_pairs += positive * (m - positive);
      r.tie_term += m * m * m - m;
    }
    first = last + 1;
  }
  return r;
}

CsvRules RulesForResultFile(const std::string& name) {
  using enum ColumnKind;
  CsvRules rules;
  const std::string base = name.substr(name.find_last_of('/') + 1);
  auto set = [&rules](std::initializer_list<const char*> columns, ColumnKind kind) {
    for (const char* c : columns) rules.columns[c] = kind;
  };
  if (base == "fig5.csv") {
    set({"pattern", "estimator", "sigma_mm", "trials", "noise"}, kText);
    set({"mean_x_mm",      "std_x_mm",        "std_x_lo_mm",      "std_x_hi_mm",
         "mean_y_mm",      "std_y_mm",        "std_y_lo_mm",      "std_y_hi_mm",
         "mean_theta_rad", "std_theta_rad",   "std_theta_lo_rad", "std_theta_hi_rad",
         "std_pos_mm",     "std_pos_lo_mm",   "std_pos_hi_mm",    "rms_radial_mm",
         "mean_radial_mm", "std_radial_mm",   "std_radial_lo_mm", "std_radial_hi_mm",
         "crlb_pos_mm",    "crlb_theta_rad",  "pred_pos_mm",      "pred_theta_rad",
         "efficiency_pos", "efficiency_theta"},
        kContinuous);
    set({"ml_nonconverged"}, kCount);
    set({"ml_first_nonconverged_trial"}, kFirstTrial);
    set({"ml_mean_iterations"}, kMeanCount);
    set({"ks_x_d", "ks_y_d", "ks_theta_d"}, kKsD);
    set({"ks_x_p", "ks_y_p", "ks_theta_p"}, kKsP);
    set({"wilcoxon_pos_p", "wilcoxon_theta_p"}, kWilcoxonP);
  } else if (base == "table1.csv") {
    set({"subject"}, kText);
    set({"n", "missed_frames"}, kCount);
    set({"est_sx_mm",       "est_sx_lo",       "est_sx_hi",      "est_sx_iid_lo",  "est_sx_iid_hi",
         "est_sy_mm",       "est_sy_lo",       "est_sy_hi",      "est_sy_iid_lo",  "est_sy_iid_hi",
         "true_sx_mm",      "true_sx_lo",      "true_sx_hi",     "true_sx_iid_lo", "true_sx_iid_hi",
         "true_sy_mm",      "true_sy_lo",      "true_sy_hi",     "true_sy_iid_lo", "true_sy_iid_hi",
         "est_over_true_x", "est_over_true_y", "true_mean_x_mm", "true_mean_y_mm", "est_lag1_x",
         "est_lag1_y",      "est_stheta_rad",  "true_stheta_rad"},
        kContinuous);
  } else if (base == "table1_tests.csv") {
    set({"error", "axis", "a", "b", "smaller"}, kText);
    set({"n"}, kCount);
    set({"median_abs_a_mm", "median_abs_b_mm"}, kContinuous);
    set({"r_plus", "r_minus"}, kRankSum);
    set({"z"}, kZ);
    set({"p_value"}, kNormalP);
  } else if (base == "track_errors.csv") {
    set({"subject", "run", "frame"}, kText);
    set({"t_s", "est_x_mm", "est_y_mm", "true_x_mm", "true_y_mm", "est_theta_rad",
         "true_theta_rad"},
        kContinuous);
  }
  return rules;
}

namespace {

constexpr const char* kKindNames[] = {"text",       "continuous", "count",   "first trial",
                                      "mean count", "KS D",       "KS p",    "Wilcoxon p",
                                      "rank sum",   "Wilcoxon z", "normal p"};

std::optional<double> Number(const std::string& cell) { return io::ParseDouble(cell); }

double Continuous(double x, double y) {
  return kRelativeDrift * std::max(std::abs(x), std::abs(y)) + kAbsoluteNoise;
}

// One unit in the last printed digit of the table1_tests.csv columns: z has 3 decimals, p 3
// significant digits.
double SignificantUnit(double v, int digits) {
  if (v == 0.0) return 0.0;
  return std::pow(10.0, std::floor(std::log10(std::abs(v))) - digits + 1);
}

// P(D >= d) of two samples of n each, as stats::KsTwoSample computes it (kAuto).
double KsP(double d, double n) {
  if (d <= 0.0) return 1.0;
  if (n > static_cast<double>(stats::kKsMaxAutoExactN)) {
    return std::min(1.0, stats::KolmogorovSurvival(std::sqrt(n / 2.0) * d));
  }
  return stats::KsExactEqualTwoSided(static_cast<int64_t>(n), std::llround(d * n));
}

double NormalP(double abs_z) { return std::erfc(std::max(0.0, abs_z) / std::sqrt(2.0)); }

// |z| of a two-sided normal p (bisection: erfc is decreasing).
double AbsZOf(double p) {
  if (p >= 1.0) return 0.0;
  double lo = 0.0, hi = 40.0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (NormalP(mid) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The move of a Wilcoxon z on n pairs when R+ - mu moves by `rank_move` and the variance's tie
// term by up to `tie_term` (and by 3/n relative per difference that becomes a zero).
double ZMove(double n, double abs_z, double rank_move, double tie_term, double near_zero) {
  const double var = n * (n + 1.0) * (2.0 * n + 1.0) / 24.0 - tie_term / 48.0;
  if (var <= 0.0) return INFINITY;
  const double relative_var = tie_term / 48.0 / var + 3.0 * near_zero / n;
  return rank_move / std::sqrt(var) + abs_z * relative_var;
}

struct Verdict {
  bool ok = true;
  std::string tolerance;  // what was allowed, for the message
};

Verdict Range(double committed, double lo, double hi, const std::string& why) {
  return {committed >= lo && committed <= hi, "allowed [" + FormatSignificant(lo, 6) + ", " +
                                                  FormatSignificant(hi, 6) + "] (" + why + ")"};
}

Verdict Plus(double x, double y, double tolerance, const std::string& why) {
  return {std::abs(x - y) <= tolerance, "+-" + FormatSignificant(tolerance, 6) + " (" + why + ")"};
}

// What the check knows of a row besides its cells.
struct Row {
  const std::vector<std::string>* regenerated = nullptr;
  const std::vector<std::string>* committed = nullptr;
  const std::vector<std::string>* header = nullptr;
  double trials = 0.0;
  bool rounding_start = false;  // an ML row whose start is the optimum up to rounding
  bool count_moved = false;
  const RankAllowance* allowance = nullptr;
  // The regenerated number in column `name` of this row (NaN if none).
  double Regenerated(const std::string& name) const {
    const auto it = std::find(header->begin(), header->end(), name);
    if (it == header->end()) return NAN;
    const auto k = static_cast<size_t>(it - header->begin());
    return k < regenerated->size() ? Number((*regenerated)[k]).value_or(NAN) : NAN;
  }
};

Verdict RankCell(ColumnKind kind, double x, double y, const Row& row) {
  using enum ColumnKind;
  const RankAllowance& a = *row.allowance;
  const double n = a.pairs;
  const double z_move = ZMove(n, std::abs(row.Regenerated("z")),
                              a.opposite_pairs + 1.5 * a.near_zero * n, a.tie_term, a.near_zero);
  const std::string why = FormatSignificant(a.opposite_pairs, 10) + " knife-edge opposite-sign " +
                          "pairs, " + FormatSignificant(a.near_zero, 10) + " near-zero differences";
  if (kind == kRankSum) {
    return Plus(x, y, a.RankSumMove(), why);
  }
  if (a.RankSumMove() == 0.0) return Plus(x, y, Continuous(x, y), "no knife edges: continuous");
  if (kind == kZ) {
    return Plus(x, y, z_move + 1e-3, why + "; plus one printed unit");
  }
  // The p of the regenerated z (printed to 3 decimals: +-0.0005) moved by z_move.
  const double abs_z = std::abs(row.Regenerated("z"));
  const double w = z_move + 5e-4;
  const double lo = NormalP(abs_z + w), hi = NormalP(abs_z - w);
  return Range(y, lo - SignificantUnit(lo, 3), hi + SignificantUnit(hi, 3),
               "z +-" + FormatSignificant(w, 3) + " from " + why + "; plus one printed unit");
}

Verdict KnifeEdgeCell(ColumnKind kind, const std::string& column, double x, double y,
                      const Row& row) {
  using enum ColumnKind;
  const double k = kKnifeEdgeEvents;
  const double n = row.trials;
  switch (kind) {
    case kCount:
      return Plus(x, y, k, "knife-edge events");
    case kMeanCount:
      if (row.rounding_start) {
        return {std::min(x, y) >= 0.0 && std::max(x, y) <= 1.0,
                "both in [0, 1] (the ML starts at its optimum up to rounding: 0 or 1 step)"};
      }
      return Plus(x, y, 1.0,
                  "each trial's last step is decided by a gradient at rounding level: one step");
    case kKsD:
      return Plus(x, y, k / n + Continuous(x, y), "knife-edge samples / trials");
    case kKsP: {
      const double d = row.Regenerated(column.substr(0, column.size() - 1) + "d");
      const double lo = KsP(d + k / n, n), hi = KsP(std::max(0.0, d - k / n), n);
      return Range(y, lo - Continuous(lo, lo), hi + Continuous(hi, hi),
                   "p of D +- " + FormatSignificant(k / n, 3));
    }
    case kWilcoxonP: {
      const double abs_z = AbsZOf(x);
      const double w = ZMove(n, abs_z, k * 1.5 * n, 0.0, k);
      const double lo = NormalP(abs_z + w), hi = x >= 1.0 ? 1.0 : NormalP(abs_z - w);
      return Range(y, lo - Continuous(lo, lo), hi + Continuous(hi, hi),
                   "z +-" + FormatSignificant(w, 3) + ": a difference crossing the zero threshold");
    }
    default:
      return Plus(x, y, Continuous(x, y), "continuous");
  }
}

Verdict Cell(ColumnKind kind, const std::string& column, const std::string& a, const std::string& b,
             const Row& row) {
  using enum ColumnKind;
  if (a == b) return {};
  const std::optional<double> x = Number(a), y = Number(b);
  if (kind == kText) return {false, "exact (text)"};
  if (!x || !y) return {false, "none: both cells must be numbers, or equal"};
  switch (kind) {
    case kContinuous:
      return Plus(*x, *y, Continuous(*x, *y), "relative drift 2e-9 + 1e-12");
    case kFirstTrial:
      return row.count_moved ? Range(*y, -1.0, row.trials - 1.0, "the count moved")
                             : Verdict{false, "exact unless the row's count moved"};
    case kRankSum:
    case kZ:
    case kNormalP:
      if (row.allowance == nullptr) return {false, "no rank allowance for this row"};
      return RankCell(kind, *x, *y, row);
    default:
      return KnifeEdgeCell(kind, column, *x, *y, row);
  }
}

// The rows of fig5.csv whose ML starts at its optimum up to rounding: sigma = 0, or the fast row
// of the same pattern and sigma has the same stds (the ML moved no trial measurably).
bool RoundingStart(const std::vector<std::vector<std::string>>& rows, size_t r,
                   const std::vector<std::string>& header) {
  const auto col = [&header](const char* name) {
    return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const size_t pattern = col("pattern"), estimator = col("estimator"), sigma = col("sigma_mm");
  if (estimator >= header.size() || rows[r].size() != header.size()) return false;
  if (rows[r][estimator] != "ml") return false;
  if (Number(rows[r][sigma]).value_or(1.0) == 0.0) return true;
  for (const auto& other : rows) {
    if (other.size() != header.size() || other[estimator] != "fast" ||
        other[pattern] != rows[r][pattern] || other[sigma] != rows[r][sigma]) {
      continue;
    }
    for (const char* c : {"std_x_mm", "std_y_mm", "std_theta_rad"}) {
      const auto u = Number(other[col(c)]), v = Number(rows[r][col(c)]);
      if (!u || !v || std::abs(*u - *v) > Continuous(*u, *v)) return false;
    }
    return true;
  }
  return false;
}

Row MakeRow(const CsvRules& rules, const std::vector<std::vector<std::string>>& regenerated,
            const std::vector<std::string>& committed, size_t r) {
  const std::vector<std::string>& header = regenerated[0];
  Row row;
  row.regenerated = &regenerated[r];
  row.committed = &committed;
  row.header = &header;
  row.trials = row.Regenerated("trials");
  if (std::isnan(row.trials)) row.trials = row.Regenerated("n");
  row.rounding_start = RoundingStart(regenerated, r, header);
  std::string key;
  for (size_t k = 0; k < header.size(); ++k) {
    const auto it = rules.columns.find(header[k]);
    if (it == rules.columns.end()) continue;
    if (it->second == ColumnKind::kCount && k < committed.size() &&
        regenerated[r][k] != committed[k]) {
      row.count_moved = true;
    }
  }
  for (size_t k = 0; k < header.size() && k < regenerated[r].size(); ++k) {
    if (rules.columns.at(header[k]) != ColumnKind::kText) break;
    key.append(key.empty() ? "" : ",").append(regenerated[r][k]);
  }
  const auto found = rules.rank_allowances.find(key);
  if (found != rules.rank_allowances.end()) row.allowance = &found->second;
  return row;
}

}  // namespace

std::string CompareResultCsv(const std::string& regenerated, const std::string& committed,
                             const CsvRules& rules) {
  const auto a = io::ParseCsvRecords(regenerated, "regenerated"),
             b = io::ParseCsvRecords(committed, "committed");
  if (a.empty() || b.empty() || a[0] != b[0]) return "line 1: the header differs";
  for (const std::string& column : a[0]) {
    if (!rules.columns.contains(column)) return "line 1: column " + column + " has no rule";
  }
  for (size_t r = 1; r < std::max(a.size(), b.size()); ++r) {
    std::string where = "line ";
    where.append(std::to_string(r + 1)).append(": ");
    if (r >= b.size()) return where + "extra line";
    if (r >= a.size()) return where + "missing line";
    if (a[r].size() != b[r].size()) return where + "the number of cells differs";
    const Row row = MakeRow(rules, a, b[r], r);
    for (size_t k = 0; k < a[r].size(); ++k) {
      const ColumnKind kind = rules.columns.at(a[0][k]);
      const Verdict v = Cell(kind, a[0][k], a[r][k], b[r][k], row);
      if (v.ok) continue;
      std::string message = "line ";
      message.append(std::to_string(r + 1))
          .append(", column ")
          .append(a[0][k])
          .append(" (")
          .append(kKindNames[static_cast<int>(kind)])
          .append("): ")
          .append(a[r][k].empty() ? "(empty)" : a[r][k])
          .append(" vs committed ")
          .append(b[r][k].empty() ? "(empty)" : b[r][k])
          .append("; tolerance ")
          .append(v.tolerance);
      return message;
    }
  }
  return "";
}

}  // namespace patlab::paper
