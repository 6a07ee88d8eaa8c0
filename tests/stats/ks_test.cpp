#include "patlab/stats/ks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "../expect_error.h"
#include "fixtures.h"
#include "patlab/core/error.h"
#include "patlab/stats/ks_internal.h"

namespace patlab::stats {
namespace {

using testing::Fixtures;
using testing::Sample;

TEST(Ks, MatchesScipyFixtures) {
  int checked = 0;
  for (const auto& c : Fixtures().at("ks")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::vector<double> x = Sample(c.at("x"));
    const std::vector<double> y = Sample(c.at("y"));
    KsOptions options;
    options.alternative = ParseAlternative(c.at("alternative").get<std::string>());
    options.method = ParseKsMethod(c.at("method").get<std::string>());
    const KsResult r = KsTwoSample(x, y, options);
    const auto& e = c.at("expect");
    EXPECT_EQ(r.d, e.at("d").get<double>());  // the statistic is compared exactly
    EXPECT_EQ(KsMethodName(r.method_used), e.at("method_used").get<std::string>());
    EXPECT_EQ(r.sign, e.at("sign").get<int>());
    EXPECT_REL_NEAR(r.p_value, e.at("p").get<double>(), 1e-9);
    if (e.contains("p_lattice_int")) {
      EXPECT_REL_NEAR(r.p_value, e.at("p_lattice_int").get<double>(), 1e-9);
    }
    const double n1 = static_cast<double>(x.size()), n2 = static_cast<double>(y.size());
    EXPECT_DOUBLE_EQ(r.d_scaled, std::sqrt(n1 * n2 / (n1 + n2)) * r.d);
    EXPECT_GE(r.p_value, 0.0);
    EXPECT_LE(r.p_value, 1.0);
    ++checked;
  }
  EXPECT_GE(checked, 70);
}

TEST(Ks, FixturesReachTinyPValuesAndLargeN) {
  double smallest = 1.0;
  std::size_t largest = 0;
  for (const auto& c : Fixtures().at("ks")) {
    smallest = std::min(smallest, c.at("expect").at("p").get<double>());
    const auto& x = c.at("x");
    largest = std::max(largest, x.contains("gen") ? x.at("gen").at("n").get<std::size_t>()
                                                  : x.at("values").size());
  }
  EXPECT_LT(smallest, 1e-200);
  EXPECT_EQ(largest, 100000u);
}

TEST(Ks, ComparesEcdfsAfterAllTiedValues) {
  // After value 2 both ECDFs have moved: F1 = 1, F2 = 1/2. Stepping one element at a time
  // would see F1 = 1, F2 = 0 and report D = 1.
  const std::vector<double> x = {1.0, 2.0};
  const std::vector<double> y = {2.0, 3.0};
  const KsResult r = KsTwoSample(x, y);
  EXPECT_EQ(r.d, 0.5);
  EXPECT_EQ(r.location, 1.0);
  // Every order of 2 + 2 values has |F1 - F2| = 1/2 after its first step, so p = 1.
  EXPECT_EQ(r.p_value, 1.0);
}

TEST(Ks, KolmogorovLimitMatchesScipy) {
  for (const auto& row : Fixtures().at("kolmogorov_limit")) {
    const double x = row.at(0).get<double>();
    SCOPED_TRACE(x);
    EXPECT_REL_NEAR(KolmogorovSurvival(x), row.at(1).get<double>(), 1e-10);
  }
  EXPECT_EQ(KolmogorovSurvival(0.0), 1.0);
  EXPECT_EQ(KolmogorovSurvival(-1.0), 1.0);
}

TEST(Ks, ExactFormsAgreeByHand) {
  // n1 = n2 = 2: 6 equally likely orders, D = 1 only for xxyy and yyxx.
  EXPECT_DOUBLE_EQ(KsExactEqualTwoSided(2, 2), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(KsExactEqualOneSided(2, 2), 1.0 / 6.0);
  EXPECT_DOUBLE_EQ(KsExactLattice(2, 2, 2, true), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(KsExactLattice(2, 2, 2, false), 1.0 / 6.0);
  // The reflection sum and the lattice recursion are independent algorithms.
  for (int n : {3, 10, 57}) {
    for (int h = 1; h <= n; h += 2) {
      SCOPED_TRACE(n * 1000 + h);
      EXPECT_REL_NEAR(KsExactLattice(n, n, h, true), KsExactEqualTwoSided(n, h), 1e-11);
      EXPECT_REL_NEAR(KsExactLattice(n, n, h, false), KsExactEqualOneSided(n, h), 1e-11);
    }
  }
  EXPECT_EQ(KsExactLattice(5, 7, 0, true), 1.0);
}

TEST(Ks, ExactFallsBackToAsymptoticBeyondTheLatticeLimit) {
  std::vector<double> x(20000), y(15001);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<double>(i) * 0.5;
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = static_cast<double>(i) * 0.6 + 0.1;
  KsOptions options;
  options.method = KsMethod::kExact;
  const KsResult r = KsTwoSample(x, y, options);
  EXPECT_EQ(r.method_used, KsMethod::kAsymptotic);
  EXPECT_REL_NEAR(r.p_value, KolmogorovSurvival(r.d_scaled), 1e-15);
}

TEST(Ks, RejectsEmptyAndNonFiniteInput) {
  const std::vector<double> empty;
  const std::vector<double> one = {1.0};
  const std::vector<double> bad = {1.0, std::nan("")};
  EXPECT_INPUT_ERROR(
      KsTwoSample(one, empty),
      "the KS test needs two non-empty samples, got 1 and 0 values; expected at least one "
      "value in each");
  EXPECT_INPUT_ERROR(KsTwoSample(one, bad), "sample 2 value 2 is NaN; expected finite numbers");
  // Equal sizes large enough for the paired walk, which checks the values in its own pass: the
  // same messages, also when both samples are the same array.
  std::vector<double> big(3000, 1.0), big_bad = big;
  big_bad[2500] = std::numeric_limits<double>::infinity();
  EXPECT_INPUT_ERROR(KsTwoSample(big, big_bad),
                     "sample 2 value 2501 is infinite; expected finite numbers");
  EXPECT_INPUT_ERROR(KsTwoSample(big_bad, big_bad),
                     "sample 1 value 2501 is infinite; expected finite numbers");
  EXPECT_INPUT_ERROR(ParseKsMethod("approx"),
                     "method is \"approx\"; expected \"auto\", \"exact\" or \"asymp\"");
  EXPECT_EQ(ParseKsMethod("asymp"), KsMethod::kAsymptotic);
  EXPECT_EQ(KsMethodName(KsMethod::kAsymptotic), "asymp");
}

}  // namespace
}  // namespace patlab::stats
