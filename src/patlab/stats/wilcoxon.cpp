#include "patlab/stats/wilcoxon.h"

#include "patlab/stats/sort.h"

#include <algorithm>
#include <array>
#include <bit>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon_internal.h"

namespace patlab::stats {

namespace {

// Exact null distribution of R+ for n untied, non-zero differences: each rank k enters R+
// with probability 1/2 independently, so pmf_n(r) = (pmf_{n-1}(r) + pmf_{n-1}(r - n)) / 2
// (scipy _get_wilcoxon_distr). Returns P(R+ <= r) and P(R+ >= r).
std::pair<double, double> ExactTails(std::size_t n, std::size_t r) {
  const std::size_t total = n * (n + 1) / 2;
  std::vector<double> pmf(total + 1, 0.0);
  pmf[0] = 1.0;
  std::size_t top = 0;
  for (std::size_t k = 1; k <= n; ++k) {
    top += k;
    for (std::size_t s = top; s >= k; --s) pmf[s] = 0.5 * (pmf[s] + pmf[s - k]);
    for (std::size_t s = std::min(k, top + 1); s-- > 0;) pmf[s] *= 0.5;
  }
  double lower = 0.0, upper = 0.0;
  for (std::size_t s = 0; s <= r; ++s) lower += pmf[s];
  for (std::size_t s = total + 1; s-- > r;) upper += pmf[s];
  return {lower, upper};
}

// The signed-rank sums of the sorted differences d (average ranks for ties, scipy rankdata
// 'average'; zeros first), with the tie term sum of t^3 - t over the groups that stay ranked.
detail::SignedRankSums SortedRankSums(std::span<const double> d, std::size_t n_zero,
                                      ZeroMethod zero_method) {
  detail::SignedRankSums sums;
  double r_zero = 0.0;
  const bool drop_zero_ranks = zero_method != ZeroMethod::kZsplit;
  // Under kWilcox the zeros are removed before ranking: ranks start after them.
  const double offset = zero_method == ZeroMethod::kWilcox ? static_cast<double>(n_zero) : 0.0;
  for (std::size_t start = 0; start < d.size();) {
    std::size_t end = start + 1;
    while (end < d.size() && std::fabs(d[end]) == std::fabs(d[start])) ++end;
    const double t = static_cast<double>(end - start);
    if (d[start] != 0.0) {
      if (t > 1) sums.has_ties = true;
      sums.tie_sum += t * t * t - t;
    } else if (!drop_zero_ranks) {
      sums.tie_sum += t * t * t - t;
    }
    const double rank = 0.5 * static_cast<double>(start + 1 + end) - offset;
    for (std::size_t k = start; k < end; ++k) {
      if (d[k] > 0) {
        sums.r_plus += rank;
      } else if (d[k] < 0) {
        sums.r_minus += rank;
      } else {
        r_zero += rank;
      }
    }
    start = end;
  }
  if (zero_method == ZeroMethod::kZsplit) {
    sums.r_plus += r_zero / 2.0;
    sums.r_minus += r_zero / 2.0;
  }
  return sums;
}

WilcoxonMethod ChooseMethod(WilcoxonMethod method, std::size_t n, std::size_t n_zero,
                            bool has_ties) {
  if (method == WilcoxonMethod::kAuto) {
    method = n <= kWilcoxonMaxAutoExactN ? WilcoxonMethod::kExact : WilcoxonMethod::kApprox;
  }
  if (method == WilcoxonMethod::kExact && (n_zero > 0 || has_ties || n > kWilcoxonMaxExactN)) {
    method = WilcoxonMethod::kApprox;
  }
  return method;
}

double ExactPValue(std::size_t n, double r_plus, Alternative alt) {
  const auto r = static_cast<std::size_t>(r_plus);  // an integer: no ties, no zeros
  const auto [p_less, p_greater] = ExactTails(n, r);
  double p = 0.0;
  if (alt == Alternative::kTwoSided) {
    p = (r == n * (n + 1) / 4) ? 1.0 : 2.0 * std::min(p_less, p_greater);
  } else {
    p = alt == Alternative::kGreater ? p_greater : p_less;
  }
  return std::clamp(p, 0.0, 1.0);
}

// The normal approximation: z and its p-value into *result (statistic already set).
void ApproximatePValue(std::size_t n, std::size_t n_zero, double tie_sum,
                       const WilcoxonOptions& options, WilcoxonResult* result) {
  const Alternative alt = options.alternative;
  const double count =
      static_cast<double>(options.zero_method == ZeroMethod::kWilcox ? n - n_zero : n);
  double mean = count * (count + 1.0) * 0.25;
  double var24 = count * (count + 1.0) * (2.0 * count + 1.0);  // 24 Var(R+) without ties
  if (options.zero_method == ZeroMethod::kPratt) {
    // Cureton (1967): the zeros' ranks 1..n_zero are excluded from both moments.
    const double nz = static_cast<double>(n_zero);
    mean -= nz * (nz + 1.0) * 0.25;
    var24 -= nz * (nz + 1.0) * (2.0 * nz + 1.0);
  }
  var24 -= 0.5 * tie_sum;  // tie correction (e.g. Hollander & Wolfe, eq. 3.13)
  const double se = std::sqrt(var24 / 24.0);
  double shift = 0.0;
  if (options.correction) {
    if (alt == Alternative::kTwoSided) {
      const double diff = result->statistic - mean;
      shift = diff > 0 ? 0.5 : (diff < 0 ? -0.5 : 0.0);
    } else {
      shift = alt == Alternative::kLess ? -0.5 : 0.5;
    }
  }
  if (!(se > 0.0)) {  // cannot happen for n >= 1, but never feed NaN to Boost
    result->z = std::numeric_limits<double>::quiet_NaN();
    result->p_value = 1.0;
    return;
  }
  result->z = (result->statistic - mean - shift) / se;
  const boost::math::normal normal;
  // Tails straight from erfc (Boost complement), so p = 1e-270 keeps its digits.
  if (alt == Alternative::kTwoSided) {
    result->p_value = 2.0 * boost::math::cdf(boost::math::complement(normal, std::fabs(result->z)));
  } else if (alt == Alternative::kGreater) {
    result->p_value = boost::math::cdf(boost::math::complement(normal, result->z));
  } else {
    result->p_value = boost::math::cdf(normal, result->z);
  }
  result->p_value = std::clamp(result->p_value, 0.0, 1.0);
}

// This thread's buffer of n doubles (the sort-free path's scratch, or the copy that is sorted),
// grown to the largest sample seen and then reused (a fresh 100,000-element array costs more in
// page faults than the test). Only serial code uses it.
std::span<double> ThreadBuffer(std::size_t n) {
  thread_local std::vector<double> buffer;
  if (buffer.size() < n) buffer.resize(n);
  return {buffer.data(), n};
}

}  // namespace

WilcoxonResult WilcoxonSignedRank(std::span<const double> x, std::span<const double> y,
                                  const WilcoxonOptions& options) {
  if (x.size() != y.size()) {
    throw InputError("the Wilcoxon test needs paired samples of equal length, got " +
                     std::to_string(x.size()) + " and " + std::to_string(y.size()) +
                     " values; expected one value of each sample per pair");
  }
  detail::RequireFinite(x, "sample 1");
  detail::RequireFinite(y, "sample 2");
  thread_local std::vector<double> d;  // reused, as in ThreadBuffer
  if (d.size() < x.size()) d.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) d[i] = x[i] - y[i];
  return WilcoxonSignedRank(std::span<const double>(d.data(), x.size()), options);
}

namespace {

using detail::internal::DifferenceScan;
using detail::internal::kInfinityBits;
using detail::internal::ScanDifferences;
using detail::internal::SumsByBuckets;

// The scan of d after the checks of the input: InputError for no pair, or (with the message of
// detail::RequireFinite, which names the first one) for a NaN or infinite difference.
DifferenceScan CheckedScan(std::span<const double> d) {
  if (d.empty()) {
    throw InputError(
        "the Wilcoxon test needs at least one pair, got none; expected at least one pair");
  }
  const DifferenceScan scan = ScanDifferences(d);
  if (scan.largest >= kInfinityBits) detail::RequireFinite(d, "difference");
  return scan;
}

// The test from the rank sums of n differences, n_zero of them zero.
WilcoxonResult FromSums(std::size_t n, std::size_t n_zero, const detail::SignedRankSums& sums,
                        const WilcoxonOptions& options) {
  WilcoxonResult result;
  result.n = n;
  result.n_zero = n_zero;
  result.has_ties = sums.has_ties;
  result.r_plus = sums.r_plus;
  result.r_minus = sums.r_minus;
  const Alternative alt = options.alternative;
  result.statistic =
      alt == Alternative::kTwoSided ? std::min(sums.r_plus, sums.r_minus) : sums.r_plus;
  result.method_used = ChooseMethod(options.method, n, n_zero, result.has_ties);
  if (result.method_used == WilcoxonMethod::kExact) {
    result.z = std::numeric_limits<double>::quiet_NaN();
    result.p_value = ExactPValue(n, sums.r_plus, alt);
    return result;
  }
  if (options.zero_method != ZeroMethod::kZsplit && n_zero == n) {
    throw InputError("every difference is zero, so zero method '" +
                     std::string(ZeroMethodName(options.zero_method)) +
                     "' leaves nothing to rank; expected at least one non-zero difference "
                     "(or use zsplit)");
  }
  ApproximatePValue(n, n_zero, sums.tie_sum, options, &result);
  return result;
}

// The sums of d without sorting where the bucket path applies; otherwise d is sorted by magnitude
// in place with `scratch`, and walked.
detail::SignedRankSums RankSumsInPlace(std::span<double> d, const DifferenceScan& scan,
                                       ZeroMethod zero_method, std::span<double> scratch) {
  detail::SignedRankSums sums;
  if (SumsByBuckets(d, d.data(), scan, zero_method, scratch, &sums)) return sums;
  SortByMagnitude(d, scratch);
  return SortedRankSums(d, scan.n_zero, zero_method);
}

}  // namespace

WilcoxonResult WilcoxonSignedRank(std::span<const double> d_in, const WilcoxonOptions& options) {
  const DifferenceScan scan = CheckedScan(d_in);
  const std::span<double> buffer = ThreadBuffer(d_in.size());
  detail::SignedRankSums sums;
  if (!SumsByBuckets(d_in, nullptr, scan, options.zero_method, buffer, &sums)) {
    std::copy(d_in.begin(), d_in.end(), buffer.begin());
    SortByMagnitude(buffer);
    sums = SortedRankSums(buffer, scan.n_zero, options.zero_method);
  }
  return FromSums(d_in.size(), scan.n_zero, sums, options);
}

WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, const WilcoxonOptions& options) {
  const DifferenceScan scan = CheckedScan(d);
  const detail::SignedRankSums sums =
      RankSumsInPlace(d, scan, options.zero_method, ThreadBuffer(d.size()));
  return FromSums(d.size(), scan.n_zero, sums, options);
}

WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, std::span<double> scratch,
                                         const WilcoxonOptions& options) {
  const DifferenceScan scan = CheckedScan(d);
  PATLAB_CHECK(scratch.size() >= d.size());
  const detail::SignedRankSums sums =
      RankSumsInPlace(d, scan, options.zero_method, scratch.first(d.size()));
  return FromSums(d.size(), scan.n_zero, sums, options);
}

}  // namespace patlab::stats
