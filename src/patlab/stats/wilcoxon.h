// Wilcoxon signed-rank test for paired samples, following scipy.stats.wilcoxon (scipy 1.10)
// except where docs/stats.md lists a deliberate difference. The paper (section II)
// uses it to compare paired absolute errors of patch sizes and of patterns.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

#include "patlab/stats/hypothesis.h"

namespace patlab::stats {

// What to do with zero differences x_i - y_i == 0 (scipy's zero_method).
enum class ZeroMethod {
  kWilcox,  // drop the zeros before ranking (Wilcoxon 1945); the default
  kPratt,   // rank the zeros with the rest, then drop their ranks (Pratt 1959; Cureton 1967
            // for the adjusted normal approximation)
  kZsplit,  // rank the zeros and give half of their rank sum to each side
};
inline constexpr EnumNames<ZeroMethod, 3> kZeroMethodNames{{{
    {ZeroMethod::kWilcox, "wilcox"},
    {ZeroMethod::kPratt, "pratt"},
    {ZeroMethod::kZsplit, "zsplit"},
}}};
// "wilcox", "pratt", "zsplit".
inline std::string_view ZeroMethodName(ZeroMethod method) {
  return NameOf(method, kZeroMethodNames);
}
// Throws InputError "zero_method is \"x\"; expected \"wilcox\", \"pratt\" or \"zsplit\"".
inline ZeroMethod ParseZeroMethod(std::string_view name) {
  return ParseName(name, kZeroMethodNames, "zero_method");
}

enum class WilcoxonMethod {
  kAuto,    // kExact when n <= kWilcoxonMaxAutoExactN and there are no zeros and no ties
  kExact,   // exact null distribution of R+; falls back to kApprox with zeros, ties or
            // n > kWilcoxonMaxExactN (reported in WilcoxonResult::method_used)
  kApprox,  // normal approximation with tie-corrected variance (optional continuity correction)
};
inline constexpr EnumNames<WilcoxonMethod, 3> kWilcoxonMethodNames{{{
    {WilcoxonMethod::kAuto, "auto"},
    {WilcoxonMethod::kExact, "exact"},
    {WilcoxonMethod::kApprox, "approx"},
}}};
// "auto", "exact", "approx".
inline std::string_view WilcoxonMethodName(WilcoxonMethod method) {
  return NameOf(method, kWilcoxonMethodNames);
}
// Throws InputError "method is \"x\"; expected \"auto\", \"exact\" or \"approx\"".
inline WilcoxonMethod ParseWilcoxonMethod(std::string_view name) {
  return ParseName(name, kWilcoxonMethodNames, "method");
}

inline constexpr std::size_t kWilcoxonMaxAutoExactN = 50;  // scipy 1.10's auto rule
// The exact distribution costs ~n^3/4 additions: 3e7 at n = 500.
inline constexpr std::size_t kWilcoxonMaxExactN = 500;

struct WilcoxonOptions {
  Alternative alternative = Alternative::kTwoSided;
  ZeroMethod zero_method = ZeroMethod::kWilcox;
  // Continuity correction of the normal approximation: shifts R+ by 0.5 towards the mean.
  // Ignored by the exact method.
  bool correction = false;
  WilcoxonMethod method = WilcoxonMethod::kAuto;
};

struct WilcoxonResult {
  // two-sided: min(R+, R-); one-sided: R+ (scipy's convention).
  double statistic = 0.0;
  double r_plus = 0.0;   // sum of the (average) ranks of |d| over d > 0 (+ half the zeros' ranks
                         // for kZsplit)
  double r_minus = 0.0;  // likewise over d < 0
  double z = 0.0;        // standardised statistic of the normal approximation; NaN when exact
  double p_value = 1.0;  // always in [0, 1]; tails computed directly, not as 1 - cdf
  WilcoxonMethod method_used = WilcoxonMethod::kApprox;  // never kAuto
  std::size_t n = 0;                                     // number of pairs
  std::size_t n_zero = 0;                                // pairs with x_i == y_i
  bool has_ties = false;                                 // tied non-zero |d| values
};

// Paired samples x, y (equal lengths, finite, non-empty, otherwise InputError); d = x - y.
// Also InputError when every difference is zero under kWilcox or kPratt (nothing to rank).
// O(n log n) for the normal approximation.
WilcoxonResult WilcoxonSignedRank(std::span<const double> x, std::span<const double> y,
                                  const WilcoxonOptions& options = {});
// The same on the differences d directly.
WilcoxonResult WilcoxonSignedRank(std::span<const double> d, const WilcoxonOptions& options = {});
// The same on differences the caller no longer needs: d is overwritten (the sort-free path below
// writes its keys over it; d is sorted by magnitude when that path does not apply; no copy of the
// sample is made), with bit-identical results.
WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, const WilcoxonOptions& options = {});
// The same with the caller's scratch (at least d.size() long, overwritten): no memory that grows
// with n is allocated.
WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, std::span<double> scratch,
                                         const WilcoxonOptions& options = {});

namespace detail {

// The signed-rank sums the test is computed from: midranks of |d| (ties averaged, zeros ranked
// first), r_plus / r_minus over d > 0 / d < 0 (plus half the zeros' ranks for kZsplit), and the
// tie term: the sum of t^3 - t over the groups that stay ranked, added in ascending |d| order.
struct SignedRankSums {
  double r_plus = 0.0, r_minus = 0.0;
  double tie_sum = 0.0;
  bool has_ties = false;
};

// The sums without sorting d, bit for bit those of the sorted walk: the non-zero |d| are counted
// into about n / 2 buckets by a non-decreasing map of equal-frequency buckets (coarse bins on the
// bits of |d|, each split into buckets by its share of a sample; equal values share a bucket),
// and a bucket's ranks follow from the counts before it; only the order inside each bucket (a
// few values) is looked at. The ranks are summed as integers, exact. d is only read; `scratch`
// (at least d.size() long) is overwritten. Returns false, computing nothing, when the path does
// not apply: fewer than kSignedRanksMinN differences, no non-zero one, more than
// kSignedRanksMaxN (sums would pass 2^53), non-zero magnitudes spread over more than 2^7 binades
// (1e-300 beside 1e300), or a bucket too full (many ties of one value, or values a few ulps
// apart); the caller then sorts.
inline constexpr std::size_t kSignedRanksMinN = 1024;
inline constexpr std::size_t kSignedRanksMaxN = std::size_t{1} << 25;
bool SignedRankSumsByBuckets(std::span<const double> d, std::size_t n_zero, ZeroMethod zero_method,
                             std::span<double> scratch, SignedRankSums* sums);

}  // namespace detail

}  // namespace patlab::stats
