#include "patlab/estimate/bounds.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_util.h"

namespace patlab::estimate {
namespace {

Model ModelOf(const std::string& name) { return Model::FromPattern(testing::ShippedPattern(name)); }

TEST(CramerRaoBound, MatchesHandComputedValues) {
  // Simple: patches (0,0), (65,0). Centroid (32.5, 0), S = 2 * 32.5^2 = 2112.5 mm^2.
  // theta: 1/sqrt(2112.5); origin per axis: sqrt(1/2 + 32.5^2 / (2 * 2112.5)) = sqrt(3/4).
  const StdPerSigma simple = CramerRaoBound(ModelOf("simple"));
  EXPECT_NEAR(simple.theta, 1.0 / std::sqrt(2112.5), 1e-15);
  EXPECT_NEAR(simple.position_per_axis, std::sqrt(0.75), 1e-15);
  // Linear: centroid at the origin, S = 2 * 65^2: theta 1/(65 sqrt 2), position 1/sqrt(3).
  const StdPerSigma linear = CramerRaoBound(ModelOf("linear"));
  EXPECT_NEAR(linear.theta, 1.0 / (65.0 * std::sqrt(2.0)), 1e-15);
  EXPECT_NEAR(linear.position_per_axis, 1.0 / std::sqrt(3.0), 1e-15);
  // Triangle: centroid at the origin, S = 3 * 65^2.
  const StdPerSigma triangle = CramerRaoBound(ModelOf("triangle"));
  EXPECT_NEAR(triangle.theta, 1.0 / (65.0 * std::sqrt(3.0)), 1e-12);
  EXPECT_NEAR(triangle.position_per_axis, 0.5, 1e-12);
}

TEST(PredictedStd, FastOnSimpleIsThePapersPairFormula) {
  // Paper section III: sigma_theta ~ sqrt(2 sigma^2) / d for one pair of separation d = 65.
  const StdPerSigma fast = PredictedStd(ModelOf("simple"), Estimator::kFast);
  EXPECT_NEAR(fast.theta, std::sqrt(2.0) / 65.0, 1e-9);
  // Linear's pair is twice as long: half the angular error (paper section IV).
  const StdPerSigma linear = PredictedStd(ModelOf("linear"), Estimator::kFast);
  EXPECT_NEAR(linear.theta, std::sqrt(2.0) / 130.0, 1e-9);
}

TEST(PredictedStd, MlAndLeastSquaresAttainTheBound) {
  for (const std::string& name : testing::ShippedPatternNames()) {
    const Model model = ModelOf(name);
    const StdPerSigma bound = CramerRaoBound(model);
    for (Estimator e : {Estimator::kMl, Estimator::kLsq}) {
      const StdPerSigma p = PredictedStd(model, e);
      EXPECT_NEAR(p.theta, bound.theta, 1e-7 * bound.theta) << name;
      EXPECT_NEAR(p.position_per_axis, bound.position_per_axis, 1e-7) << name;
    }
  }
}

TEST(PredictedStd, NoEstimatorBeatsTheBound) {
  for (const std::string& name : testing::ShippedPatternNames()) {
    const Model model = ModelOf(name);
    const StdPerSigma bound = CramerRaoBound(model);
    for (Estimator e : kAllEstimators) {
      const StdPerSigma p = PredictedStd(model, e);
      EXPECT_GE(p.theta, bound.theta * (1 - 1e-7)) << name << " " << EstimatorName(e);
      EXPECT_GE(p.position_per_axis, bound.position_per_axis * (1 - 1e-7))
          << name << " " << EstimatorName(e);
    }
  }
}

TEST(PredictedStd, KeyPatchPositionIsOnePatchWorth) {
  // The key estimator's position is the key patch (at the origin): std sigma per axis,
  // whatever the pattern.
  for (const std::string& name : testing::ShippedPatternNames()) {
    EXPECT_NEAR(PredictedStd(ModelOf(name), Estimator::kKey).position_per_axis, 1.0, 1e-7) << name;
  }
}

}  // namespace
}  // namespace patlab::estimate
