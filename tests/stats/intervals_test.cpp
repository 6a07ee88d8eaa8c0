// Tests of the count intervals (src/patlab/stats/intervals.h) against closed forms and quantiles.
#include "patlab/stats/intervals.h"

#include <gtest/gtest.h>

#include <cmath>

namespace patlab::stats {
namespace {

TEST(WilsonInterval, MatchesTheClosedForm) {
  // k = 5, n = 10: centre 1/2, half-width z / (1 + z^2/n) sqrt(1/40 + z^2/400)
  // (statsmodels proportion_confint(5, 10, method="wilson") = (0.236593, 0.763407)).
  Proportion p = WilsonInterval(5, 10);
  EXPECT_EQ(p.rate, 0.5);
  EXPECT_NEAR(p.lower, 0.2365931, 1e-7);
  EXPECT_NEAR(p.upper, 0.7634069, 1e-7);
  // k = 0: [0, z^2 / (n + z^2)]; k = n: [n / (n + z^2), 1].
  const double z2 = 1.959963984540054 * 1.959963984540054;
  p = WilsonInterval(0, 10);
  EXPECT_EQ(p.lower, 0.0);
  EXPECT_NEAR(p.upper, z2 / (10 + z2), 1e-12);
  p = WilsonInterval(10, 10);
  EXPECT_NEAR(p.lower, 10 / (10 + z2), 1e-12);
  EXPECT_EQ(p.upper, 1.0);
  EXPECT_TRUE(std::isnan(WilsonInterval(0, 0).rate));
}

TEST(GarwoodInterval, MatchesPoissonQuantiles) {
  // K = 10 in one frame: (chi2_20^-1(0.025) / 2, chi2_22^-1(0.975) / 2) = (4.795389, 18.390356).
  PoissonRate r = GarwoodInterval(10, 1);
  EXPECT_EQ(r.rate, 10.0);
  EXPECT_NEAR(r.lower, 4.795389, 1e-5);
  EXPECT_NEAR(r.upper, 18.390356, 1e-5);
  // K = 0: upper = -ln(0.025) / F.
  r = GarwoodInterval(0, 100);
  EXPECT_EQ(r.lower, 0.0);
  EXPECT_NEAR(r.upper, -std::log(0.025) / 100, 1e-12);
}

}  // namespace
}  // namespace patlab::stats
