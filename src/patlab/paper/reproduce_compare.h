// How `patlab reproduce --check` compares a regenerated results CSV with the committed one made on
// another machine (docs/paper-reproduction.md, "Results on other machines"): per column, by what
// the column holds. A continuous estimate may move in its last bits; a discrete outcome (a count,
// a KS D, a rank sum) only by the knife-edge events the derivation allows, and a p-value or z by
// exactly what those moves imply; identifiers and text must match exactly.
#pragma once

#include <map>
#include <span>
#include <string>
#include <vector>

namespace patlab::paper {

// What a column holds, and so how far it may move on another machine.
enum class ColumnKind {
  kText,        // identifiers, names, settings (pattern, sigma_mm, trials, axis): exactly equal
  kContinuous,  // a mean, std, interval, RMS, efficiency, median: within kRelativeDrift
  kCount,       // a count of discrete outcomes (ml_nonconverged, n): +- kKnifeEdgeEvents
  kFirstTrial,  // the first trial of such an outcome: equal unless the row's count moved
  kMeanCount,   // the mean ML iteration count: +- 1 (every trial's last step is a rounding
                // decision); in rows whose ML starts at its optimum up to rounding, both in [0, 1]
  kKsD,         // a two-sample KS D on `trials` each: +- kKnifeEdgeEvents / trials
  kKsP,         // the KS p of the D column before it: the p range of D's allowed move
  kWilcoxonP,   // fig5's Wilcoxon p (no z printed): the p range of the z move implied by
                // kKnifeEdgeEvents differences crossing the zero threshold
  kRankSum,     // a Wilcoxon rank sum R+ or R-: +- the row's knife-edge allowance (RankAllowance)
  kZ,           // the Wilcoxon z of those rank sums: the implied move + one printed unit
  kNormalP,     // the two-sided normal p of that z: the p range of z's allowed move
};

// The continuous tolerance: |a - b| <= kRelativeDrift max(|a|, |b|) + kAbsoluteNoise.
inline constexpr double kRelativeDrift = 2e-9;
inline constexpr double kAbsoluteNoise = 1e-12;
// Knife-edge events (a decision within rounding of its threshold) allowed per cell of a row of
// continuously distributed trials: the expected number over all of results/ is ~3e-6 (derived in
// docs/paper-reproduction.md), so one is already a wide margin.
inline constexpr int kKnifeEdgeEvents = 1;
// A value's relative drift across machines is ~1e-14 (a few ulp through O(10) libm calls); two
// values are a knife edge when they lie within 100 times that of each other.
inline constexpr double kKnifeEdgeRelative = 1e-12;

// How far the rank sums of one Wilcoxon signed-rank test on paired |errors| may move: from the
// regenerated samples, the pairs whose order another machine may flip.
struct RankAllowance {
  double opposite_pairs = 0.0;  // pairs (d_i > 0, d_j < 0) with |d_i|, |d_j| a knife edge apart
  double near_zero = 0.0;       // differences within a knife edge of zero (could become zeros)
  double tie_term = 0.0;        // sum of m^3 - m over the clusters of such values (ties)
  double pairs = 0.0;           // n of the test
  // The move of R+ (and R-): a flipped opposite-sign pair moves one rank unit between them; a
  // difference that becomes zero removes its rank and shifts every rank above it down by one (at
  // most n in all). (z also sees the mean n(n+1)/4 move by n/2 then: 1.5 n per such difference.)
  double RankSumMove() const { return opposite_pairs + near_zero * pairs; }
};
// The allowance of the test on d = |a| - |b| (equal lengths).
RankAllowance KnifeEdgeAllowance(std::span<const double> abs_a, std::span<const double> abs_b);

// What the check knows about one CSV: every column's kind (by header name) and, for a file of
// Wilcoxon tests, each row's rank allowance keyed by its text cells joined with ','.
struct CsvRules {
  std::map<std::string, ColumnKind> columns;
  std::map<std::string, RankAllowance> rank_allowances;
};
// The kinds of the columns of the CSVs `patlab reproduce` writes (fig5.csv, table1.csv,
// table1_tests.csv, track_errors.csv, also under track_quantisation/); nullopt-like empty rules
// (no columns) for other files, which are compared by CompareResultText's generic rule.

CsvRules RulesForResultFile(const std::string& name);

// Compares by `rules`: "" when every cell is within its column's tolerance, else the first
// failing cell: "line 3, column ml_mean_iterations (mean count): 0.9 vs committed 0.1;
// tolerance 1e-05 (...)". A column of the file without a rule is a failure too.
std::string CompareResultCsv(const std::string& regenerated, const std::string& committed,
                             const CsvRules& rules);

}  // namespace patlab::paper
