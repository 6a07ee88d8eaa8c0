#include "patlab/stats/wilcoxon.h"

#include "patlab/stats/sort.h"

#include <algorithm>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/stats/summary.h"

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
struct RankSums {
  double r_plus = 0.0, r_minus = 0.0;
  double tie_sum = 0.0;
  bool has_ties = false;
};
RankSums SignedRankSums(std::span<const double> d, std::size_t n_zero, ZeroMethod zero_method) {
  RankSums sums;
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

// The differences sorted by magnitude in this thread's buffer, grown to the largest sample seen
// and then reused (a fresh 100,000-element array costs more in page faults than the sort). Only
// serial code uses it.
std::span<double> SortedCopy(std::span<const double> d_in) {
  thread_local std::vector<double> buffer;
  if (buffer.size() < d_in.size()) buffer.resize(d_in.size());
  const std::span<double> d(buffer.data(), d_in.size());
  std::copy(d_in.begin(), d_in.end(), d.begin());
  SortByMagnitude(d);
  return d;
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
  thread_local std::vector<double> d;  // reused, as in SortedCopy
  if (d.size() < x.size()) d.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) d[i] = x[i] - y[i];
  return WilcoxonSignedRank(std::span<const double>(d.data(), x.size()), options);
}

namespace {

void RequireDifferences(std::span<const double> d) {
  if (d.empty()) {
    throw InputError(
        "the Wilcoxon test needs at least one pair, got none; expected at least one pair");
  }
  detail::RequireFinite(d, "difference");
}

// The test on the differences d, already sorted by magnitude, n_zero of them zero.
WilcoxonResult FromSorted(std::span<const double> d, std::size_t n_zero,
                          const WilcoxonOptions& options) {
  WilcoxonResult result;
  result.n = d.size();
  result.n_zero = n_zero;
  const RankSums sums = SignedRankSums(d, n_zero, options.zero_method);
  result.has_ties = sums.has_ties;
  result.r_plus = sums.r_plus;
  result.r_minus = sums.r_minus;
  const Alternative alt = options.alternative;
  result.statistic =
      alt == Alternative::kTwoSided ? std::min(sums.r_plus, sums.r_minus) : sums.r_plus;
  result.method_used = ChooseMethod(options.method, d.size(), n_zero, result.has_ties);
  if (result.method_used == WilcoxonMethod::kExact) {
    result.z = std::numeric_limits<double>::quiet_NaN();
    result.p_value = ExactPValue(d.size(), sums.r_plus, alt);
    return result;
  }
  if (options.zero_method != ZeroMethod::kZsplit && n_zero == d.size()) {
    throw InputError("every difference is zero, so zero method '" +
                     std::string(ZeroMethodName(options.zero_method)) +
                     "' leaves nothing to rank; expected at least one non-zero difference "
                     "(or use zsplit)");
  }
  ApproximatePValue(d.size(), n_zero, sums.tie_sum, options, &result);
  return result;
}

}  // namespace

WilcoxonResult WilcoxonSignedRank(std::span<const double> d_in, const WilcoxonOptions& options) {
  RequireDifferences(d_in);
  const auto n_zero = static_cast<std::size_t>(std::count(d_in.begin(), d_in.end(), 0.0));
  return FromSorted(SortedCopy(d_in), n_zero, options);
}

WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, const WilcoxonOptions& options) {
  RequireDifferences(d);
  const auto n_zero = static_cast<std::size_t>(std::count(d.begin(), d.end(), 0.0));
  SortByMagnitude(d);
  return FromSorted(d, n_zero, options);
}

WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, std::span<double> scratch,
                                         const WilcoxonOptions& options) {
  RequireDifferences(d);
  const auto n_zero = static_cast<std::size_t>(std::count(d.begin(), d.end(), 0.0));
  SortByMagnitude(d, scratch);
  return FromSorted(d, n_zero, options);
}

}  // namespace patlab::stats
