#include "patlab/stats/smoothing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <vector>

#include "../expect_error.h"
#include "fixtures.h"
#include "patlab/core/error.h"
#include "patlab/core/rng.h"
#include "patlab/stats/summary.h"

namespace patlab::stats {
namespace {

using testing::Fixtures;
using testing::Sample;

TEST(Smoothing, MatchesScipyNdimageGaussianFilter1d) {
  int checked = 0;
  for (const auto& c : Fixtures().at("smoothing")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::vector<double> x = Sample(c.at("x"));
    SmoothingOptions options;
    options.sigma_samples = c.at("sigma").get<double>();
    const std::vector<double> expected = c.at("expect").at("smoothed").get<std::vector<double>>();
    const std::vector<double> got = GaussianSmooth(x, options);
    const std::vector<double> residual = SmoothingResiduals(x, options);
    ASSERT_EQ(got.size(), expected.size());
    double scale = 0.0;
    for (double v : x) scale = std::max(scale, std::fabs(v));
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_NEAR(got[i], expected[i], 1e-13 * scale) << "i = " << i;
      EXPECT_NEAR(residual[i], x[i] - expected[i], 1e-13 * scale) << "i = " << i;
    }
    ++checked;
  }
  EXPECT_GE(checked, 6);
}

TEST(Smoothing, PreservesConstantsAndLines) {
  // Weights sum to 1, so constants survive; the kernel is symmetric, so a line survives away
  // from the edges (within the radius 40 of the edge the reflection bends it).
  std::vector<double> c(100, 3.25), line(200);
  for (std::size_t i = 0; i < line.size(); ++i) line[i] = 0.5 * static_cast<double>(i);
  for (double v : GaussianSmooth(c)) EXPECT_NEAR(v, 3.25, 1e-14);
  const std::vector<double> s = GaussianSmooth(line);
  for (std::size_t i = 40; i + 40 < line.size(); ++i) EXPECT_NEAR(s[i], line[i], 1e-12);
  EXPECT_GT(s[0], line[0]);  // the reflected neighbours of sample 0 are all >= it
}

TEST(Smoothing, ValidatesOptions) {
  SmoothingOptions bad;
  bad.sigma_samples = -1.0;
  EXPECT_INPUT_ERROR(Validate(bad), "sigma_samples is -1; expected a finite number >= 0");
  SmoothingOptions no_kernel;
  no_kernel.truncate_sigmas = 0.0;
  EXPECT_INPUT_ERROR(Validate(no_kernel), "truncate_sigmas is 0; expected a finite number > 0");
  SmoothingOptions huge;
  huge.sigma_samples = 1e300;
  EXPECT_INPUT_ERROR(Validate(huge),
                     "sigma_samples is 1e+300; expected at most 100000 samples (the kernel's size "
                     "is bounded)");
  huge.sigma_samples = 100000.0;
  EXPECT_EQ(Check(huge).size(), 0u);
  huge.truncate_sigmas = 11.0;
  EXPECT_INPUT_ERROR(Validate(huge), "truncate_sigmas is 11; expected at most 10");
  EXPECT_EQ(Check(SmoothingOptions{}).size(), 0u);
  EXPECT_THROW(GaussianSmooth(std::vector<double>{}), InputError);
}

TEST(Smoothing, KernelIsNormalisedSymmetricHalfOfScipys) {
  SmoothingOptions options;
  options.sigma_samples = 2.0;  // radius floor(4 * 2 + 0.5) = 8
  const std::vector<double> w = GaussianKernel(options);
  ASSERT_EQ(w.size(), 9u);
  double sum = w[0];
  for (std::size_t k = 1; k < w.size(); ++k) sum += 2.0 * w[k];
  EXPECT_NEAR(sum, 1.0, 1e-15);
  EXPECT_NEAR(w[1] / w[0], std::exp(-1.0 / 8.0), 1e-15);
  EXPECT_NEAR(w[8] / w[0], std::exp(-64.0 / 8.0), 1e-15);
  // sigma 0: the identity, and a residual that is exactly zero.
  options.sigma_samples = 0.0;
  EXPECT_EQ(GaussianKernel(options), std::vector<double>{1.0});
  EXPECT_EQ(ResidualStdFactor(options), 0.0);
}

TEST(Smoothing, ResidualsRecoverTheStdOfWhiteNoiseUpToTheKernelFactor) {
  // A linear track (the platform's constant speed) plus iid Gaussian noise of std sigma.
  constexpr int kN = 200000;
  constexpr double kSigma = 0.5;
  RandomStream rng(11, 0, 0);
  std::vector<double> x(kN);
  for (int i = 0; i < kN; ++i) x[i] = 0.77 * i + kSigma * rng.Normal();
  const SmoothingOptions smoothing;  // sigma = 10 samples, as in the paper
  const std::vector<double> r = SmoothingResiduals(x, smoothing);
  const std::vector<double> kept(r.begin() + 40, r.end() - 40);
  const double s = SampleStd(kept);
  const double se = kSigma / std::sqrt(2.0 * kept.size());  // standard error of a std
  const double factor = ResidualStdFactor(smoothing);
  EXPECT_NEAR(factor, 0.974, 0.001);
  EXPECT_NEAR(s / factor, kSigma, 4 * se);
  // Uncorrected, the paper's estimate is low by 2.6%: far more than 4 standard errors here.
  EXPECT_GT(std::abs(s - kSigma), 4 * se);
}

TEST(Autocorrelation, MatchesNumpyFixtures) {
  for (const auto& c : Fixtures().at("autocorrelation")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::vector<double> x = Sample(c.at("x"));
    const double expected = c.at("expect").get<double>();
    EXPECT_NEAR(Autocorrelation(x, c.at("lag").get<std::size_t>()), expected, 1e-13);
  }
}

TEST(Autocorrelation, HandComputed) {
  // x = 1, 2, 3, 4: m = 2.5, deviations -1.5 -0.5 0.5 1.5, sum of squares 5;
  // lag 1: (0.75 - 0.25 + 0.75) / 5 = 0.25.
  const std::vector<double> x = {1.0, 2.0, 3.0, 4.0};
  EXPECT_DOUBLE_EQ(Autocorrelation(x, 0), 1.0);
  EXPECT_DOUBLE_EQ(Autocorrelation(x, 1), 0.25);
  EXPECT_TRUE(std::isnan(Autocorrelation(std::vector<double>{2.0, 2.0}, 1)));
  EXPECT_INPUT_ERROR(
      Autocorrelation(x, 4),
      "autocorrelation at lag 4 needs more than 4 samples, got 4; expected a lag shorter "
      "than the series");
}

}  // namespace
}  // namespace patlab::stats
