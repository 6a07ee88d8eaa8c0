#include "patlab/stats/wilcoxon.h"

#include "patlab/stats/sort.h"

#include <algorithm>
#include <array>
#include <bit>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <cstdint>
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

void RequireDifferences(std::span<const double> d) {
  if (d.empty()) {
    throw InputError(
        "the Wilcoxon test needs at least one pair, got none; expected at least one pair");
  }
  detail::RequireFinite(d, "difference");
}

std::size_t CountZeros(std::span<const double> d) {
  return static_cast<std::size_t>(std::count(d.begin(), d.end(), 0.0));
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
detail::SignedRankSums RankSumsInPlace(std::span<double> d, std::size_t n_zero,
                                       ZeroMethod zero_method, std::span<double> scratch) {
  detail::SignedRankSums sums;
  if (detail::SignedRankSumsByBuckets(d, n_zero, zero_method, scratch, &sums)) return sums;
  SortByMagnitude(d, scratch);
  return SortedRankSums(d, n_zero, zero_method);
}

}  // namespace

WilcoxonResult WilcoxonSignedRank(std::span<const double> d_in, const WilcoxonOptions& options) {
  RequireDifferences(d_in);
  const std::size_t n_zero = CountZeros(d_in);
  const std::span<double> buffer = ThreadBuffer(d_in.size());
  detail::SignedRankSums sums;
  if (!detail::SignedRankSumsByBuckets(d_in, n_zero, options.zero_method, buffer, &sums)) {
    std::copy(d_in.begin(), d_in.end(), buffer.begin());
    SortByMagnitude(buffer);
    sums = SortedRankSums(buffer, n_zero, options.zero_method);
  }
  return FromSums(d_in.size(), n_zero, sums, options);
}

WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, const WilcoxonOptions& options) {
  RequireDifferences(d);
  const std::size_t n_zero = CountZeros(d);
  const detail::SignedRankSums sums =
      RankSumsInPlace(d, n_zero, options.zero_method, ThreadBuffer(d.size()));
  return FromSums(d.size(), n_zero, sums, options);
}

WilcoxonResult WilcoxonSignedRankInPlace(std::span<double> d, std::span<double> scratch,
                                         const WilcoxonOptions& options) {
  RequireDifferences(d);
  PATLAB_CHECK(scratch.size() >= d.size());
  const std::size_t n_zero = CountZeros(d);
  const detail::SignedRankSums sums =
      RankSumsInPlace(d, n_zero, options.zero_method, scratch.first(d.size()));
  return FromSums(d.size(), n_zero, sums, options);
}

namespace {

constexpr std::uint64_t kSignBit = std::uint64_t{1} << 63;
// At most 2^17 buckets (O(buckets) thread-local counters, docs/hardening.md "Bounded memory").
constexpr std::size_t kMaxRankBuckets = std::size_t{1} << 17;
// A value is ranked by comparing it with the kWindow keys either side of it in bucket order;
// buckets of up to kWindow + 1 values always fit in the window.
constexpr std::size_t kWindow = 7;
// Below this, a sum of the integers t^3 - t is exact in double whatever the order of additions.
constexpr std::uint64_t kExactTieSum = std::uint64_t{1} << 52;
// The zeros' tie term n0^3 - n0 fits in 64 bits up to here.
constexpr std::size_t kMaxZeroGroup = std::size_t{1} << 17;

// The magnitude bits shifted up, and 1 in the lowest bit for a positive value: keys order by |v|,
// and values of equal magnitude have equal key >> 1 (the bits of |v|).
inline std::uint64_t SignedMagnitudeKey(double v) {
  const auto u = std::bit_cast<std::uint64_t>(v);
  return ((u & ~kSignBit) << 1) | ((u >> 63) ^ 1);
}
inline std::uint64_t KeyAt(const double* keys, std::size_t i) {
  return std::bit_cast<std::uint64_t>(keys[i]);
}
inline std::uint64_t MagnitudeAt(const double* keys, std::size_t i) { return KeyAt(keys, i) >> 1; }

// Bucket 0 holds the zeros, bucket 1 + min(floor(|v| x scale), last) the other values: a
// non-decreasing function of |v| (every step rounds monotonically), so equal magnitudes share a
// bucket, and a value of a lower bucket is smaller than every value of a higher one. Takes the
// bits of |v|.
struct BucketOf {
  double scale;
  double last;
  std::uint32_t operator()(std::uint64_t magnitude_bits) const {
    const double magnitude = std::bit_cast<double>(magnitude_bits);
    return static_cast<std::uint32_t>(std::min(magnitude * scale, last)) +
           (magnitude_bits != 0 ? 1U : 0U);
  }
};

// Integer tallies: a value's rank0 is the number of non-zero |d| smaller than its |d|, and its
// group of t equal magnitudes shares the midrank rank0 + (t + 1) / 2, summed twice over so that
// it is an integer.
struct RankTally {
  std::uint64_t twice_r_plus = 0;  // sum over d > 0 of 2 x midrank
  std::uint64_t positives = 0;
  std::uint64_t tie_terms = 0;  // sum of t^3 - t over the groups: t^2 - 1 for each value
};

inline void AddValue(std::uint64_t key, std::uint64_t rank0, std::uint64_t group,
                     RankTally* tally) {
  const std::uint64_t positive = key & 1;
  tally->twice_r_plus += positive * (2 * rank0 + group + 1);
  tally->positives += positive;
  tally->tie_terms += group * group - 1;
}

// Ranks the values at positions [lo, hi) of the keys in bucket order (kWindow < lo,
// hi + kWindow < n) whose bucket lies inside the window of kWindow positions either side: every
// key before the window is then of a smaller magnitude, every key after it of a larger one, so
// rank0 = (start of the window) + (smaller magnitudes in it) - n_zero. The other values are left
// to TallyRest. No branch on the data: the loop vectorises across positions.
void TallyWindowed(const double* keys, std::size_t lo, std::size_t hi, std::size_t n_zero,
                   BucketOf bucket_of, RankTally* tally) {
  std::uint64_t twice = 0, positives = 0, ties = 0;
  for (std::size_t p = lo; p < hi; ++p) {
    const std::uint64_t key = KeyAt(keys, p), magnitude = key >> 1;
    std::uint64_t less = 0, group = 0;
#pragma GCC unroll 16
    for (std::size_t o = 0; o <= 2 * kWindow; ++o) {  // positions p - kWindow ... p + kWindow
      const std::uint64_t other = MagnitudeAt(keys, p - kWindow + o);
      less += other < magnitude ? 1 : 0;
      group += other == magnitude ? 1 : 0;
    }
    const std::uint32_t bucket = bucket_of(magnitude);
    const std::uint64_t inside = bucket_of(MagnitudeAt(keys, p - kWindow - 1)) != bucket &&
                                         bucket_of(MagnitudeAt(keys, p + kWindow + 1)) != bucket
                                     ? 1
                                     : 0;
    const std::uint64_t positive = key & inside;
    twice += positive * (2 * (p + less - kWindow - n_zero) + group + 1);
    positives += positive;
    ties += inside * (group * group - 1);
  }
  tally->twice_r_plus += twice;
  tally->positives += positives;
  tally->tie_terms += ties;
}

// The keys[0, count), sorted, the first at rank0 `base`: each group of equal magnitudes [a, b)
// has rank0 base + a.
void TallySortedGroups(const double* keys, std::size_t count, std::uint64_t base,
                       RankTally* tally) {
  for (std::size_t a = 0; a < count;) {
    const std::uint64_t magnitude = MagnitudeAt(keys, a);
    std::uint64_t positives = KeyAt(keys, a) & 1;
    std::size_t b = a + 1;
    for (; b < count && MagnitudeAt(keys, b) == magnitude; ++b) positives += KeyAt(keys, b) & 1;
    const std::uint64_t t = b - a;
    tally->twice_r_plus += positives * (2 * (base + a) + t + 1);
    tally->positives += positives;
    tally->tie_terms += t * t * t - t;
    a = b;
  }
}

// The values of the bucket [begin, end) that TallyWindowed did not rank (it ranked the positions
// in [lo, hi) within kWindow of both ends of the bucket).
void TallyBucketRest(double* keys, std::size_t begin, std::size_t end, std::size_t lo,
                     std::size_t hi, std::size_t n_zero, RankTally* tally) {
  const std::uint64_t base = begin - n_zero;
  if (end - begin >= 2 * kWindow + 2) {  // too wide: none of it was ranked
    if (std::all_of(keys + begin, keys + end, [&](double k) {
          return std::bit_cast<std::uint64_t>(k) >> 1 == MagnitudeAt(keys, begin);
        })) {  // one group (quantised values): no sort
      TallySortedGroups(keys + begin, end - begin, base, tally);
      return;
    }
    std::sort(keys + begin, keys + end, [](double p, double q) {
      return std::bit_cast<std::uint64_t>(p) < std::bit_cast<std::uint64_t>(q);
    });
    TallySortedGroups(keys + begin, end - begin, base, tally);
    return;
  }
  const std::size_t done_lo = std::max(lo, end > kWindow + 1 ? end - kWindow - 1 : 0);
  const std::size_t done_hi = std::min(hi, begin + kWindow + 1);
  for (std::size_t p = begin; p < end; ++p) {
    if (p >= done_lo && p < done_hi) continue;
    const std::uint64_t magnitude = MagnitudeAt(keys, p);
    std::uint64_t less = 0, group = 0;
    for (std::size_t j = begin; j < end; ++j) {
      less += MagnitudeAt(keys, j) < magnitude ? 1 : 0;
      group += MagnitudeAt(keys, j) == magnitude ? 1 : 0;
    }
    AddValue(KeyAt(keys, p), base + less, group, tally);
  }
}

// The buckets 1.. (ends[k] is the end of bucket k) that TallyWindowed did not rank completely:
// those wider than its window and those near either end of the keys. They are found 64 buckets at
// a time with a mask (a loop that vectorises), since most buckets need nothing.
void TallyRest(double* keys, const std::vector<std::uint32_t>& ends, std::size_t lo, std::size_t hi,
               std::size_t n_zero, RankTally* tally) {
  const std::size_t last = ends.size() - 2;  // buckets 1..last
  for (std::size_t k0 = 1; k0 <= last; k0 += 64) {
    const std::size_t count = std::min<std::size_t>(64, last + 1 - k0);
    std::uint64_t mask = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t begin = ends[k0 + i - 1], end = ends[k0 + i];
      const bool rest = end - begin > kWindow + 1 || (end > begin && (begin < lo || end > hi));
      mask |= static_cast<std::uint64_t>(rest ? 1 : 0) << i;
    }
    for (; mask != 0; mask &= mask - 1) {
      const std::size_t k = k0 + static_cast<std::size_t>(std::countr_zero(mask));
      TallyBucketRest(keys, ends[k - 1], ends[k], lo, hi, n_zero, tally);
    }
  }
}

// Scatters the keys of d into `keys` by bucket; on return ends[k] is the end of bucket k (and
// the start of bucket k + 1). Returns false when one bucket is too full for the path to pay.
bool ScatterByBucket(std::span<const double> d, BucketOf bucket_of, std::size_t buckets,
                     std::vector<std::uint32_t>* ends_out, double* keys) {
  std::vector<std::uint32_t>& ends = *ends_out;
  ends.assign(buckets + 2, 0);
  // The buckets of kIdBlock values at a time (a loop that vectorises), then the counts.
  constexpr std::size_t kIdBlock = 256;
  std::array<std::uint32_t, kIdBlock> ids{};
  const auto block_ids = [&](std::size_t i0, std::size_t len) {
    for (std::size_t i = 0; i < len; ++i) {
      ids[i] = bucket_of(std::bit_cast<std::uint64_t>(d[i0 + i]) & ~kSignBit);
    }
  };
  const std::size_t n = d.size();
  for (std::size_t i0 = 0; i0 < n; i0 += kIdBlock) {
    const std::size_t len = std::min(kIdBlock, n - i0);
    block_ids(i0, len);
    for (std::size_t i = 0; i < len; ++i) ++ends[ids[i] + 1];
  }
  std::uint32_t fullest = 0;
  for (std::size_t k = 2; k < ends.size(); ++k) {
    fullest = std::max(fullest, ends[k]);
    ends[k] += ends[k - 1];
  }
  if (fullest > 32 && fullest > n / 64) return false;  // clustered: sorting pays
  for (std::size_t i0 = 0; i0 < n; i0 += kIdBlock) {
    const std::size_t len = std::min(kIdBlock, n - i0);
    block_ids(i0, len);
    for (std::size_t i = 0; i < len; ++i) {
      keys[ends[ids[i]]++] = std::bit_cast<double>(SignedMagnitudeKey(d[i0 + i]));
    }
  }
  return true;
}

}  // namespace

namespace detail {

bool SignedRankSumsByBuckets(std::span<const double> d, std::size_t n_zero, ZeroMethod zero_method,
                             std::span<double> scratch, SignedRankSums* sums) {
  const std::size_t n = d.size();
  if (n < kSignedRanksMinN || n > kSignedRanksMaxN || n_zero == n) return false;
  if (zero_method == ZeroMethod::kZsplit && n_zero > kMaxZeroGroup) return false;
  PATLAB_CHECK(scratch.size() >= n);
  std::uint64_t largest = 0;  // the bits of the largest |v|: a reduction that vectorises
  for (const double v : d) largest = std::max(largest, std::bit_cast<std::uint64_t>(v) & ~kSignBit);
  const std::size_t buckets = std::clamp<std::size_t>(n / 2, 1, kMaxRankBuckets);
  const double scale = static_cast<double>(buckets) / std::bit_cast<double>(largest);
  if (!(scale <= std::numeric_limits<double>::max())) return false;  // subnormal largest |v|
  thread_local std::vector<std::uint32_t> ends;                      // O(buckets), at most 2^17 + 2
  const BucketOf bucket_of{scale, static_cast<double>(buckets - 1)};
  double* const keys = scratch.data();
  if (!ScatterByBucket(d, bucket_of, buckets, &ends, keys)) return false;
  RankTally tally;
  const std::size_t lo = std::max(n_zero, kWindow + 1), hi = n - kWindow - 1;
  if (lo < hi) TallyWindowed(keys, lo, hi, n_zero, bucket_of, &tally);
  TallyRest(keys, ends, lo, hi, n_zero, &tally);
  std::uint64_t tie_terms = tally.tie_terms;
  if (zero_method == ZeroMethod::kZsplit) tie_terms += n_zero * n_zero * n_zero - n_zero;
  if (tie_terms >= kExactTieSum) return false;  // the sorted walk's rounding would matter
  // Ranks count the zeros before them unless 'wilcox' dropped the zeros.
  const std::uint64_t m = n - n_zero;
  const std::uint64_t shift = zero_method == ZeroMethod::kWilcox ? 0 : n_zero;
  const std::uint64_t twice_plus = tally.twice_r_plus + 2 * shift * tally.positives;
  const std::uint64_t twice_all = m * (m + 1) + 2 * shift * m;
  sums->r_plus = 0.5 * static_cast<double>(twice_plus);
  sums->r_minus = 0.5 * static_cast<double>(twice_all - twice_plus);
  if (zero_method == ZeroMethod::kZsplit) {
    const auto r_zero = static_cast<double>(n_zero * (n_zero + 1) / 2);
    sums->r_plus += r_zero / 2.0;
    sums->r_minus += r_zero / 2.0;
  }
  sums->tie_sum = static_cast<double>(tie_terms);
  sums->has_ties = tally.tie_terms > 0;
  return true;
}

}  // namespace detail

}  // namespace patlab::stats
