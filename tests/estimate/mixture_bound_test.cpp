// The outlier mixture's location information i(p, k) (estimate/mixture_bound.h) against scipy's
// adaptive quadrature, a Monte-Carlo estimate of E[score^2], and its limits.
#include "patlab/estimate/mixture_bound.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "../test_util.h"

namespace patlab::estimate {
namespace {

TEST(MixtureLocationInformation, MatchesScipyQuadrature) {
  // Computed once with /usr/bin/python3, scipy.integrate.quad of pi r^3 w(r)^2 f(r) on
  // [0, 60 max(1, k)] (epsabs 1e-15, epsrel 1e-13): an independent integrator of the same formula.
  struct Case {
    double p, k, i;
  };
  for (const Case& c :
       {Case{0.05, 10.0, 0.9362510063669567}, Case{0.05, 8.0, 0.9314732187609964},
        Case{0.1, 5.0, 0.8493786654835961}, Case{0.2, 3.0, 0.7025738844138343},
        Case{0.5, 2.0, 0.4818675120354894}, Case{0.0, 3.0, 1.0}, Case{0.3, 1.0, 1.0}}) {
    EXPECT_NEAR(MixtureLocationInformation(c.p, c.k), c.i, 1e-10) << c.p << " " << c.k;
  }
}

TEST(MixtureLocationInformation, IsTheMeanSquaredScoreOfSampledErrors) {
  // E[(d/dx log f(e))^2] over errors drawn from the mixture, sigma = 1: the score is
  // -x ((1 - p) phi_1 + p phi_k / k^2) / f, written here in Cartesian form from the densities.
  const double p = 0.05, k = 10.0;
  std::mt19937_64 rng(77);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform;
  const int n = 400000;
  double sum = 0.0, sum2 = 0.0;
  for (int t = 0; t < n; ++t) {
    const double s = uniform(rng) < p ? k : 1.0;
    const double x = s * normal(rng), y = s * normal(rng);
    const double r2 = x * x + y * y;
    const double f1 = (1 - p) * std::exp(-r2 / 2) / (2 * std::numbers::pi);
    const double fk = p * std::exp(-r2 / (2 * k * k)) / (2 * std::numbers::pi * k * k);
    const double score = -x * (f1 + fk / (k * k)) / (f1 + fk);
    sum += score * score;
    sum2 += score * score * score * score;
  }
  const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
  EXPECT_NEAR(MixtureLocationInformation(p, k), mean, 4.0 * se);
}

TEST(MixtureLocationInformation, LiesBetweenTheGaussianOfItsVarianceAndKnownLabels) {
  for (double p : {0.01, 0.05, 0.2, 0.5}) {
    for (double k : {0.5, 2.0, 8.0, 20.0}) {
      const double i = MixtureLocationInformation(p, k);
      EXPECT_GE(i, 1.0 / (1 - p + p * k * k)) << p << " " << k;
      EXPECT_LE(i, 1 - p + p / (k * k)) << p << " " << k;
    }
  }
}

TEST(MixtureCramerRaoBound, IsTheIsotropicBoundOverTheRootOfTheInformation) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  const StdPerSigma iso = CramerRaoBound(model);
  const StdPerSigma mix = MixtureCramerRaoBound(model, 0.05, 10.0);
  const double i = MixtureLocationInformation(0.05, 10.0);
  EXPECT_NEAR(mix.theta, iso.theta / std::sqrt(i), 1e-15);
  EXPECT_NEAR(mix.position_per_axis, iso.position_per_axis / std::sqrt(i), 1e-15);
}

}  // namespace
}  // namespace patlab::estimate
