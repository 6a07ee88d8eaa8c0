#include "patlab/stats/wilcoxon.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <random>
#include <span>
#include <vector>

#include "../expect_error.h"
#include "fixtures.h"
#include "patlab/core/error.h"

namespace patlab::stats {
namespace {

using testing::Fixtures;
using testing::Sample;

TEST(Wilcoxon, MatchesScipyFixtures) {
  int checked = 0;
  double smallest = 1.0;
  for (const auto& c : Fixtures().at("wilcoxon")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::vector<double> x = Sample(c.at("x"));
    const std::vector<double> y = Sample(c.at("y"));
    WilcoxonOptions options;
    options.alternative = ParseAlternative(c.at("alternative").get<std::string>());
    options.zero_method = ParseZeroMethod(c.at("zero_method").get<std::string>());
    options.correction = c.at("correction").get<bool>();
    options.method = ParseWilcoxonMethod(c.at("method").get<std::string>());
    const WilcoxonResult r = WilcoxonSignedRank(x, y, options);
    const auto& e = c.at("expect");
    EXPECT_EQ(r.statistic, e.at("statistic").get<double>());  // exact: sums of half-integers
    EXPECT_EQ(WilcoxonMethodName(r.method_used), e.at("method_used").get<std::string>());
    EXPECT_REL_NEAR(r.p_value, e.at("p").get<double>(), 1e-9);
    if (e.contains("z")) {
      EXPECT_NEAR(r.z, e.at("z").get<double>(), 1e-9 * std::max(1.0, std::fabs(r.z)));
    } else {
      EXPECT_TRUE(std::isnan(r.z));
    }
    smallest = std::min(smallest, e.at("p").get<double>());
    ++checked;
  }
  EXPECT_GE(checked, 60);
  EXPECT_LT(smallest, 1e-200);
}

TEST(Wilcoxon, HandComputedExactCase) {
  // d = 1, -2, 3, 4, 5: R+ = 1+3+4+5 = 13, R- = 2. Subsets of {1..5} with sum <= 2: {}, {1},
  // {2}, so P(R+ <= 2) = 3/32 and the two-sided p = 6/32.
  const std::vector<double> d = {1.0, -2.0, 3.0, 4.0, 5.0};
  const WilcoxonResult r = WilcoxonSignedRank(d);
  EXPECT_EQ(r.r_plus, 13.0);
  EXPECT_EQ(r.r_minus, 2.0);
  EXPECT_EQ(r.statistic, 2.0);
  EXPECT_EQ(r.method_used, WilcoxonMethod::kExact);
  EXPECT_DOUBLE_EQ(r.p_value, 6.0 / 32.0);
  WilcoxonOptions less;
  less.alternative = Alternative::kLess;
  EXPECT_DOUBLE_EQ(WilcoxonSignedRank(d, less).p_value, 30.0 / 32.0);  // P(R+ <= 13)
}

TEST(Wilcoxon, HandComputedTiesAndZeros) {
  // d = 0, 1, -1, 2, 2: wilcox drops the zero, ranks of |d| = 1.5 1.5 3.5 3.5;
  // R+ = 1.5 + 7 = 8.5, R- = 1.5; variance (4*5*9 - 0.5*(6 + 6)) / 24 = 174/24.
  const std::vector<double> d = {0.0, 1.0, -1.0, 2.0, 2.0};
  WilcoxonOptions options;
  options.alternative = Alternative::kGreater;
  const WilcoxonResult r = WilcoxonSignedRank(d, options);
  EXPECT_EQ(r.method_used, WilcoxonMethod::kApprox);
  EXPECT_EQ(r.r_plus, 8.5);
  EXPECT_EQ(r.r_minus, 1.5);
  EXPECT_DOUBLE_EQ(r.z, (8.5 - 5.0) / std::sqrt(174.0 / 24.0));
  EXPECT_DOUBLE_EQ(r.p_value, 0.5 * std::erfc(r.z / std::sqrt(2.0)));
  // zsplit: ranks 1, 2.5, 2.5, 4.5, 4.5; the zero's rank 1 is split.
  options.zero_method = ZeroMethod::kZsplit;
  const WilcoxonResult z = WilcoxonSignedRank(d, options);
  EXPECT_EQ(z.r_plus, 2.5 + 9.0 + 0.5);
  EXPECT_EQ(z.r_minus, 2.5 + 0.5);
}

TEST(Wilcoxon, ExactRequestWithTiesFallsBackToApprox) {
  const std::vector<double> d = {1.0, -1.0, 2.0, 3.0, 4.0, 5.0};
  WilcoxonOptions options;
  options.method = WilcoxonMethod::kExact;
  const WilcoxonResult r = WilcoxonSignedRank(d, options);
  EXPECT_TRUE(r.has_ties);
  EXPECT_EQ(r.method_used, WilcoxonMethod::kApprox);
}

TEST(Wilcoxon, TinyTailSurvivesThroughComplements) {
  // 2000 positive differences: z ~ 38.7, p ~ 1e-327 underflows to 0 but never to a negative
  // or NaN; 1500 gives a representable p ~ 1e-246 with full relative accuracy.
  std::vector<double> d(1500);
  for (std::size_t i = 0; i < d.size(); ++i) d[i] = 1.0 + static_cast<double>(i);
  WilcoxonOptions options;
  options.alternative = Alternative::kGreater;
  const WilcoxonResult r = WilcoxonSignedRank(d, options);
  const double n = 1500.0;
  const double z = (n * (n + 1) / 2 - n * (n + 1) / 4) / std::sqrt(n * (n + 1) * (2 * n + 1) / 24);
  EXPECT_DOUBLE_EQ(r.z, z);
  EXPECT_REL_NEAR(r.p_value, 0.5 * std::erfc(z / std::sqrt(2.0)), 1e-12);
  EXPECT_GT(r.p_value, 0.0);
  EXPECT_LT(r.p_value, 1e-200);
}

TEST(Wilcoxon, RejectsBadInput) {
  const std::vector<double> a = {1.0, 2.0, 3.0};
  const std::vector<double> b = {1.0, 2.0};
  EXPECT_INPUT_ERROR(WilcoxonSignedRank(a, b),
                     "the Wilcoxon test needs paired samples of equal length, got 3 and 2 "
                     "values; expected one value of each sample per pair");
  EXPECT_INPUT_ERROR(WilcoxonSignedRank(std::span<const double>()),
                     "the Wilcoxon test needs at least one pair, got none; expected at least one "
                     "pair");
  EXPECT_INPUT_ERROR(WilcoxonSignedRank(a, a),
                     "every difference is zero, so zero method 'wilcox' leaves nothing to "
                     "rank; expected at least one non-zero difference (or use zsplit)");
  EXPECT_THROW(WilcoxonSignedRank(std::vector<double>{}), InputError);
  const std::vector<double> inf = {1.0, INFINITY, 3.0};
  EXPECT_INPUT_ERROR(WilcoxonSignedRank(a, inf),
                     "sample 2 value 2 is infinite; expected finite numbers");
  EXPECT_INPUT_ERROR(ParseZeroMethod("none"),
                     "zero_method is \"none\"; expected \"wilcox\", \"pratt\" or \"zsplit\"");
}

// The in-place test with the caller's scratch (the runner's dead sample arrays) gives the bits of
// the copying one on every kind of difference: ties, zeros, signed zeros, subnormals beside 1e300,
// all equal, one pair, and samples large enough for the bucket sort and for the radix sort
// (clustered magnitudes).
TEST(Wilcoxon, InPlaceWithScratchGivesTheBitsOfTheCopyingTest) {
  uint64_t state = 99;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) * 0x1p-53;
  };
  for (int kind = 0; kind < 6; ++kind) {
    for (const size_t n : {1u, 2u, 60u, 5000u, 100000u}) {
      SCOPED_TRACE(::testing::Message() << "kind " << kind << " n " << n);
      std::vector<double> d(n);
      for (size_t k = 0; k < n; ++k) {
        const double u = uniform() - 0.45;
        d[k] = u;
        if (kind == 1) d[k] = std::round(u * 16.0) / 16.0;              // ties and zeros
        if (kind == 2) d[k] = k % 3 == 0 ? (k % 2 ? -0.0 : 0.0) : u;    // signed zeros
        if (kind == 3) d[k] = k % 2 ? u * 1e-310 : u * 1e300;           // subnormal, huge
        if (kind == 4) d[k] = -1.5;                                     // all equal
        if (kind == 5) d[k] = k % 7 == 0 ? u : (k % 2 ? 0.25 : -0.25);  // clustered: radix
      }
      for (const ZeroMethod zero : {ZeroMethod::kWilcox, ZeroMethod::kPratt, ZeroMethod::kZsplit}) {
        WilcoxonOptions options;
        options.zero_method = zero;
        const bool all_zero = std::all_of(d.begin(), d.end(), [](double v) { return v == 0.0; });
        if (all_zero && zero != ZeroMethod::kZsplit) continue;
        const WilcoxonResult want = WilcoxonSignedRank(std::span<const double>(d), options);
        std::vector<double> in_place = d, scratch(n + 5, std::nan(""));
        const WilcoxonResult got = WilcoxonSignedRankInPlace(in_place, scratch, options);
        EXPECT_EQ(got.r_plus, want.r_plus);
        EXPECT_EQ(got.r_minus, want.r_minus);
        EXPECT_EQ(got.statistic, want.statistic);
        EXPECT_EQ(std::bit_cast<uint64_t>(got.p_value), std::bit_cast<uint64_t>(want.p_value));
        EXPECT_EQ(got.n_zero, want.n_zero);
        EXPECT_EQ(got.has_ties, want.has_ties);
      }
    }
  }
}

// A plain reference for the property test below: sort by |d| with std::sort, then give every
// group of equal |d| its midrank (zeros first; under 'wilcox' ranks start after the zeros),
// summing in the sorted order, and the tie term t^3 - t of every group that stays ranked.
struct ReferenceSums {
  double r_plus = 0.0, r_minus = 0.0, tie_sum = 0.0;
  bool has_ties = false;
  std::size_t n_zero = 0;
};
ReferenceSums TextbookSums(std::vector<double> d, ZeroMethod zero_method) {
  std::sort(d.begin(), d.end(), [](double a, double b) { return std::fabs(a) < std::fabs(b); });
  ReferenceSums s;
  for (const double v : d) s.n_zero += v == 0.0 ? 1 : 0;
  const double offset = zero_method == ZeroMethod::kWilcox ? static_cast<double>(s.n_zero) : 0.0;
  double r_zero = 0.0;
  for (std::size_t start = 0; start < d.size();) {
    std::size_t end = start;
    while (end < d.size() && std::fabs(d[end]) == std::fabs(d[start])) ++end;
    const double t = static_cast<double>(end - start);
    const bool zeros = d[start] == 0.0;
    if (!zeros || zero_method == ZeroMethod::kZsplit) s.tie_sum += t * t * t - t;
    if (!zeros && end - start > 1) s.has_ties = true;
    const double midrank = 0.5 * static_cast<double>(start + 1 + end) - offset;
    for (std::size_t k = start; k < end; ++k) {
      if (d[k] > 0) s.r_plus += midrank;
      if (d[k] < 0) s.r_minus += midrank;
      if (d[k] == 0) r_zero += midrank;
    }
    start = end;
  }
  if (zero_method == ZeroMethod::kZsplit) {
    s.r_plus += r_zero / 2.0;
    s.r_minus += r_zero / 2.0;
  }
  return s;
}

// The z of the normal approximation from the reference sums (two-sided, no correction), with the
// operations of the library's formula: equal sums must give the same bits.
double TextbookZ(const ReferenceSums& s, std::size_t n, ZeroMethod zero_method) {
  const double count = static_cast<double>(zero_method == ZeroMethod::kWilcox ? n - s.n_zero : n);
  double mean = count * (count + 1.0) * 0.25;
  double var24 = count * (count + 1.0) * (2.0 * count + 1.0);
  if (zero_method == ZeroMethod::kPratt) {
    const double nz = static_cast<double>(s.n_zero);
    mean -= nz * (nz + 1.0) * 0.25;
    var24 -= nz * (nz + 1.0) * (2.0 * nz + 1.0);
  }
  var24 -= 0.5 * s.tie_sum;
  return (std::min(s.r_plus, s.r_minus) - mean) / std::sqrt(var24 / 24.0);
}

uint64_t Bits(double v) { return std::bit_cast<uint64_t>(v); }

// Differences of every kind the sort-free path must rank exactly: 0 continuous (normal), 1 heavy
// ties (quantised to 1/8), 2 a third zeros of both signs, 3 magnitudes from 1e-300 to 1e300,
// 4 half-normal piled up at 0 with outliers 1e6 times larger (uneven buckets), 5 all equal,
// 6 two values +-x (every bucket but two empty), 7 tiny subnormals only, 8 ties within buckets
// (quantised to 2^-12: up to ~15 copies of a value), 9 occasional ties among distinct values in
// a bucket (quantised to 2^-17), 10 heavy tails like the runner's differences of |errors|
// (log-normal magnitudes over ~40 binades), 11 nine zeros in ten, 12 every magnitude in one
// coarse bin (1 + 2^-40 u: the fine buckets split one bin), 13 heavy tails quantised to 2^-20
// (ties of many sizes, zeros), 14 every 4th value (the coarse bins' sample) from a narrow cluster
// and the others spread (buckets shared out wrongly: wide buckets, sorted), 15 magnitudes
// 2^-60..2^60 (the widest range the map takes is 2^13 coarse bins of 2^-6 binade), 16 the same
// over 2^-70..2^70 (too wide: sorted), 17 three values of one magnitude in each bucket-sized
// step (every group a tie of 3).
// Value k of PropertySample's kind from a normal draw x, a random sign and the generator.
double PropertyValue(int kind, std::size_t k, double x, double sign, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(-300.0, 300.0);
  const auto random_binade = [&](int half_width) {
    return static_cast<int>(rng() % static_cast<unsigned>(2 * half_width + 1)) - half_width;
  };
  switch (kind) {
    case 1:
      return std::round(x * 8.0) / 8.0;
    case 2:
      return k % 3 == 0 ? sign * 0.0 : x;
    case 3:
      return (x < 0 ? -1.0 : 1.0) * std::pow(10.0, uniform(rng));
    case 4:
      return k % 1000 == 7 ? x * 1e6 : x * std::fabs(x) * 1e-3;
    case 5:
      return -2.5;
    case 6:
      return sign * 0.75;
    case 7:
      return x * 1e-320;
    case 8:
      return std::round(x * 0x1p12) * 0x1p-12;
    case 9:
      return std::round(x * 0x1p17) * 0x1p-17;
    case 10:
      return sign * 1e-3 * std::exp(3.0 * x);
    case 11:
      return k % 10 == 0 ? x : sign * 0.0;
    case 12:
      return sign * (1.0 + std::fabs(x) * 0x1p-40);
    case 13:
      return std::round(sign * 1e-3 * std::exp(3.0 * x) * 0x1p20) * 0x1p-20;
    case 14:
      return k % 4 == 0 ? sign * (1.0 + 1e-6 * x) : x;
    case 15:
      return sign * std::ldexp(1.0 + std::fabs(x), random_binade(60));
    case 16:
      return sign * std::ldexp(1.0 + std::fabs(x), random_binade(70));
    case 17:
      return sign * static_cast<double>(k / 3 + 1) * 0x1p-30;
    default:
      return x;
  }
}

std::vector<double> PropertySample(int kind, std::size_t n, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> d(n);
  for (std::size_t k = 0; k < n; ++k) {
    const double x = normal(rng);
    const double sign = rng() % 2 ? 1.0 : -1.0;
    d[k] = PropertyValue(kind, k, x, sign, rng);
  }
  return d;
}
constexpr int kPropertyKinds = 18;

// Whether the sort-free path must take a sample of PropertySample's kind (1) or must decline it
// (0), or either (-1: whether the clustered buckets pass the fullness test depends on n).
int TakesBucketPath(int kind, std::size_t n, ZeroMethod zero) {
  if (n < detail::kSignedRanksMinN) return 0;
  switch (kind) {
    case 1:  // clustered: one bucket of many ties
    case 3:  // magnitudes over 2000 binades
    case 5:
    case 6:
    case 16:  // 140 binades
      return 0;
    case 11:  // zsplit ranks at most 2^17 zeros without sorting
      return zero == ZeroMethod::kZsplit && n * 9 / 10 > (std::size_t{1} << 17) ? 0 : 1;
    case 13:
    case 14:
      return -1;
    default:
      return 1;
  }
}

// Property: for every kind of input and size, the sort-free rank sums (and the whole in-place
// test, which writes its keys over d and restores d when it declines) give the bits of the
// textbook sorted walk. The bucket path must actually run for the kinds it is meant for.
TEST(Wilcoxon, SortFreeRankSumsMatchTheTextbookSortedWalkBitForBit) {
  std::mt19937_64 rng(20261202);
  // Around the path's minimum n, past the 2^17 bucket cap (n / 2 buckets), and 1, 2, 3 values.
  std::vector<std::size_t> sizes = {1,    2,    3,    17,    1000,   1023,
                                    1024, 1025, 4096, 50000, 100000, 262145};
  for (int extra = 0; extra < 6; ++extra) sizes.push_back(1024 + rng() % 20000);
  int bucket_runs = 0, must_runs = 0;
  for (int kind = 0; kind < kPropertyKinds; ++kind) {
    for (const std::size_t n : sizes) {
      const std::vector<double> d = PropertySample(kind, n, rng);
      for (const ZeroMethod zero : {ZeroMethod::kWilcox, ZeroMethod::kPratt, ZeroMethod::kZsplit}) {
        SCOPED_TRACE(::testing::Message()
                     << "kind " << kind << " n " << n << " zero method " << ZeroMethodName(zero));
        const ReferenceSums want = TextbookSums(d, zero);
        std::vector<double> scratch(n + 3, std::nan(""));
        detail::SignedRankSums sums;
        const bool sort_free =
            detail::SignedRankSumsByBuckets(d, want.n_zero, zero, scratch, &sums);
        const int expected = TakesBucketPath(kind, n, zero);
        if (expected >= 0) {
          ASSERT_EQ(sort_free, expected == 1);
        }
        must_runs += expected == 1 ? 1 : 0;
        if (sort_free) {
          ++bucket_runs;
          ASSERT_EQ(Bits(sums.r_plus), Bits(want.r_plus));
          ASSERT_EQ(Bits(sums.r_minus), Bits(want.r_minus));
          ASSERT_EQ(Bits(sums.tie_sum), Bits(want.tie_sum));
          ASSERT_EQ(sums.has_ties, want.has_ties);
        }
        if (want.n_zero == n && zero != ZeroMethod::kZsplit) continue;  // an InputError
        WilcoxonOptions options;
        options.zero_method = zero;
        options.method = WilcoxonMethod::kApprox;
        std::vector<double> in_place = d;
        const WilcoxonResult got = WilcoxonSignedRankInPlace(in_place, scratch, options);
        ASSERT_EQ(Bits(got.r_plus), Bits(want.r_plus));
        ASSERT_EQ(Bits(got.r_minus), Bits(want.r_minus));
        ASSERT_EQ(got.n_zero, want.n_zero);
        ASSERT_EQ(got.has_ties, want.has_ties);
        ASSERT_EQ(Bits(got.z), Bits(TextbookZ(want, n, zero)));
        const WilcoxonResult copying = WilcoxonSignedRank(std::span<const double>(d), options);
        ASSERT_EQ(Bits(copying.z), Bits(got.z));
        ASSERT_EQ(Bits(copying.p_value), Bits(got.p_value));
      }
    }
  }
  EXPECT_GE(bucket_runs, must_runs);
  EXPECT_GT(must_runs, 10 * 12 * 3);
}

// When the sort-free path declines after writing its keys over d (a bucket too full: one value
// repeated, or two), the in-place test restores every difference exactly before sorting: d
// ends up a permutation of what it was, signed zeros included.
TEST(Wilcoxon, InPlaceDeclineRestoresTheDifferences) {
  std::mt19937_64 rng(7);
  for (const int kind : {5, 6, 1}) {
    std::vector<double> d = PropertySample(kind, 5000, rng);
    d[10] = -0.0;
    d[11] = 0.0;
    d[12] = d[12] * (1.0 + 0x1p-52);  // a value beside the cluster, one ulp away
    std::vector<double> in_place = d, scratch(d.size());
    detail::SignedRankSums sums;
    const auto zeros = static_cast<std::size_t>(std::count(d.begin(), d.end(), 0.0));
    ASSERT_FALSE(detail::SignedRankSumsByBuckets(d, zeros, ZeroMethod::kWilcox, scratch, &sums));
    WilcoxonSignedRankInPlace(in_place, scratch);
    const auto order = [](double a, double b) { return Bits(a) < Bits(b); };
    std::sort(d.begin(), d.end(), order);
    std::sort(in_place.begin(), in_place.end(), order);
    for (std::size_t k = 0; k < d.size(); ++k) ASSERT_EQ(Bits(in_place[k]), Bits(d[k])) << k;
  }
}

}  // namespace
}  // namespace patlab::stats
