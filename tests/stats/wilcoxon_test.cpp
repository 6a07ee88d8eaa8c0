#include "patlab/stats/wilcoxon.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iomanip>
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

}  // namespace
}  // namespace patlab::stats
