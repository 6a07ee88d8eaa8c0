#include "patlab/stats/summary.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "../expect_error.h"
#include "fixtures.h"
#include "patlab/core/error.h"

namespace patlab::stats {
namespace {

using testing::Fixtures;
using testing::Sample;

TEST(Summary, MatchesScipyFixtures) {
  int checked = 0;
  for (const auto& c : Fixtures().at("std_ci")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::vector<double> x = Sample(c.at("x"));
    const double level = c.at("level").get<double>();
    const auto& e = c.at("expect");
    const StdWithCi s = StdWithConfidence(x, level);
    EXPECT_REL_NEAR(s.std, e.at("std").get<double>(), 1e-13);
    EXPECT_REL_NEAR(s.lower, e.at("lower").get<double>(), 1e-9);
    EXPECT_REL_NEAR(s.upper, e.at("upper").get<double>(), 1e-9);
    EXPECT_EQ(s.n, x.size());
    const MeanWithCi m = MeanWithConfidence(x, level);
    EXPECT_REL_NEAR(m.mean, e.at("mean").get<double>(), 1e-13);
    EXPECT_REL_NEAR(m.lower, e.at("mean_lower").get<double>(), 1e-9);
    EXPECT_REL_NEAR(m.upper, e.at("mean_upper").get<double>(), 1e-9);
    ++checked;
  }
  EXPECT_GE(checked, 5);
}

TEST(Summary, HandComputed) {
  const std::vector<double> x = {1.0, 2.0, 3.0, 4.0};
  EXPECT_DOUBLE_EQ(Mean(x), 2.5);
  EXPECT_DOUBLE_EQ(SampleStd(x), std::sqrt(5.0 / 3.0));
  // n = 2: chi^2_1 quantiles; level -> 0 squeezes the interval around... a point inside it.
  const StdWithCi s = StdWithConfidence(x, 0.95);
  EXPECT_LT(s.lower, s.std);
  EXPECT_GT(s.upper, s.std);
  const StdWithCi wide = StdWithConfidence(x, 0.99);
  EXPECT_LT(wide.lower, s.lower);
  EXPECT_GT(wide.upper, s.upper);
}

TEST(Summary, RejectsBadInput) {
  const std::vector<double> one = {1.0};
  EXPECT_INPUT_ERROR(StdWithConfidence(one),
                     "the standard deviation needs at least 2 samples, got 1; expected at least 2");
  const std::vector<double> x = {1.0, 2.0};
  EXPECT_INPUT_ERROR(StdWithConfidence(x, 1.0), "level is 1; expected a number in (0, 1)");
  const std::vector<double> nan = {1.0, std::nan("")};
  EXPECT_THROW(MeanWithConfidence(nan), InputError);
}

TEST(Summary, IntervalFromAStdAndItsDegreesOfFreedom) {
  // The interval of a std estimated elsewhere equals the sample one with dof = n - 1.
  const std::vector<double> x = {1.0, 2.5, -0.5, 4.0, 3.25, 0.75};
  const StdWithCi sample = StdWithConfidence(x, 0.9);
  const StdWithCi direct = StdConfidenceInterval(sample.std, 5.0, 0.9);
  EXPECT_EQ(direct.lower, sample.lower);
  EXPECT_EQ(direct.upper, sample.upper);
  // More degrees of freedom, a narrower interval around the same std.
  const StdWithCi pooled = StdConfidenceInterval(sample.std, 10.0, 0.9);
  EXPECT_GT(pooled.lower, sample.lower);
  EXPECT_LT(pooled.upper, sample.upper);
  EXPECT_INPUT_ERROR(StdConfidenceInterval(1.0, 0.0),
                     "the std interval needs degrees of freedom > 0, got 0; expected a positive "
                     "number of degrees of freedom");
}

TEST(Summary, MeanAndStdOfEachIsBitIdenticalToMeanAndSampleStd) {
  // Five samples (one group of four and one of one), values of very different scales so that a
  // different order of additions would round differently.
  std::vector<std::vector<double>> samples(5, std::vector<double>(1001));
  uint64_t state = 1;
  for (size_t c = 0; c < samples.size(); ++c) {
    for (double& v : samples[c]) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      v = (static_cast<double>(state >> 11) * 0x1p-53 - 0.3) * std::pow(10.0, c * 3.0 - 6.0);
    }
  }
  for (size_t count = 1; count <= samples.size(); ++count) {
    std::vector<std::span<const double>> spans(samples.begin(), samples.begin() + count);
    std::vector<MeanAndStd> out(count);
    MeanAndStdOfEach(spans, out);
    for (size_t c = 0; c < count; ++c) {
      EXPECT_EQ(out[c].mean, Mean(samples[c])) << count << " " << c;
      EXPECT_EQ(out[c].std, SampleStd(samples[c])) << count << " " << c;
    }
  }
  const std::vector<double> one = {1.0}, nan = {1.0, std::nan("")}, two = {1.0, 2.0};
  std::vector<MeanAndStd> out(2);
  EXPECT_INPUT_ERROR(MeanAndStdOfEach(std::vector<std::span<const double>>{one},
                                      std::span<MeanAndStd>(out.data(), 1)),
                     "the standard deviation needs at least 2 samples, got 1; expected at least 2");
  EXPECT_INPUT_ERROR(MeanAndStdOfEach(std::vector<std::span<const double>>{two, nan}, out),
                     "sample value 2 is NaN; expected finite numbers");
}

TEST(Summary, RepeatedIntervalsAreTheSame) {
  // The quantiles are cached per thread; alternating between more (dof, level) pairs than the
  // cache holds must give the values of the first computation every time.
  const StdWithCi first = StdConfidenceInterval(2.0, 99999.0);
  for (int round = 0; round < 3; ++round) {
    for (double dof : {5.0, 99999.0, 199998.0, 7.0, 11.0, 13.0}) {
      const StdWithCi again = StdConfidenceInterval(2.0, dof);
      if (dof == 99999.0) {
        EXPECT_EQ(again.lower, first.lower);
        EXPECT_EQ(again.upper, first.upper);
      }
    }
  }
  EXPECT_NEAR(first.lower, 2.0 * (1.0 - 1.96 / std::sqrt(2.0 * 99999.0)), 1e-4);
}

}  // namespace
}  // namespace patlab::stats

namespace patlab::stats {
namespace {

TEST(Moments, OneBlockHasTheBitsOfMeanAndSampleStd) {
  const std::vector<double> x = {2.0, 4.0, 4.0, 4.0, 5.0, 5.0, 7.0, 9.0};
  Moments m;
  MomentsOfEach(std::vector<std::span<const double>>{x}, std::span<Moments>(&m, 1));
  EXPECT_EQ(m.n, 8);
  EXPECT_EQ(m.mean, 5.0);  // hand computed: sum 40 / 8
  EXPECT_EQ(m.m2, 32.0);   // 9 + 1 + 1 + 1 + 0 + 0 + 4 + 16
  EXPECT_EQ(m.Std(), SampleStd(x));
  EXPECT_TRUE(std::isnan(Moments{1, 3.0, 0.0}.Std()));
}

TEST(Moments, CombiningBlocksGivesTheMomentsOfTheWhole) {
  // Chan et al.'s update against the two-pass moments of the concatenation, for splits of every
  // size, including values far from zero (where the naive sum of squares loses every digit).
  std::vector<double> x(997);
  uint64_t state = 7;
  for (double& v : x) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    v = 1e6 + static_cast<double>(state >> 11) * 0x1p-53;
  }
  Moments whole;
  MomentsOfEach(std::vector<std::span<const double>>{x}, std::span<Moments>(&whole, 1));
  for (size_t split : {size_t{1}, size_t{2}, size_t{100}, size_t{500}, size_t{996}}) {
    Moments a, b;
    MomentsOfEach(std::vector<std::span<const double>>{std::span<const double>(x).first(split)},
                  std::span<Moments>(&a, 1));
    MomentsOfEach(std::vector<std::span<const double>>{std::span<const double>(x).subspan(split)},
                  std::span<Moments>(&b, 1));
    const Moments c = CombineMoments(a, b);
    EXPECT_EQ(c.n, whole.n);
    EXPECT_NEAR(c.mean, whole.mean, 1e-15 * whole.mean) << split;
    EXPECT_NEAR(c.m2, whole.m2, 1e-9 * whole.m2) << split;
  }
  // Hand computed: {1, 2} and {3, 5}: n 4, mean 2.75, M2 = 0.5 + 2 + (4 - 1.5)^2 * 2 * 2 / 4.
  const Moments c = CombineMoments(Moments{2, 1.5, 0.5}, Moments{2, 4.0, 2.0});
  EXPECT_EQ(c.n, 4);
  EXPECT_EQ(c.mean, 2.75);
  EXPECT_EQ(c.m2, 8.75);
  // An empty side leaves the other unchanged, bit for bit.
  const Moments one{3, 0.1, 0.7};
  EXPECT_EQ(CombineMoments(one, Moments{}).m2, 0.7);
  EXPECT_EQ(CombineMoments(Moments{}, one).mean, 0.1);
}

}  // namespace
}  // namespace patlab::stats
