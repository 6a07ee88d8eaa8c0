#include "patlab/estimate/estimators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "../test_util.h"
#include "patlab/core/geometry.h"

namespace patlab::estimate {
namespace {

using testing::kPi;

std::array<Vec2, kMaxPatches> Place(const Model& model, const Pose2& pose) {
  std::array<Vec2, kMaxPatches> v{};
  for (int i = 0; i < model.num_patches; ++i) v[i] = pose.Apply(model.model_mm[i]);
  return v;
}

// Poses at random plus the awkward headings: exactly +-pi, just inside, zero.
std::vector<Pose2> TestPoses() {
  std::vector<Pose2> poses = {{0, 0, 0},           {1400, -1150, kPi},     {-3, 7, -kPi + 1e-12},
                              {5, 5, kPi - 1e-12}, {-1400, 1150, kPi / 2}, {0.5, -0.5, -kPi / 2}};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> x(-1400, 1400), y(-1150, 1150), t(-kPi, kPi);
  for (int k = 0; k < 200; ++k) poses.push_back({x(rng), y(rng), t(rng)});
  return poses;
}

Pose2 RunEstimator(const Model& model, Estimator e, const Vec2* v, Summary* summary = nullptr) {
  switch (e) {
    case Estimator::kFast:
      return Fast(model, v);
    case Estimator::kMl:
      return MaximumLikelihood(model, v, Fast(model, v), Options{}, summary);
    case Estimator::kLsq:
      return LeastSquares(model, v);
    case Estimator::kKey:
      return KeyPatch(model, v);
    case Estimator::kRobust:  // tested in robust_test.cpp
      break;
  }
  return {};
}

TEST(Estimators, ExactPatchesGiveTheExactPoseForEveryPatternAndEstimator) {
  for (const std::string& name : testing::ShippedPatternNames()) {
    const Model model = Model::FromPattern(testing::ShippedPattern(name));
    for (const Pose2& truth : TestPoses()) {
      const auto v = Place(model, truth);
      for (Estimator e : kAllEstimators) {
        const Pose2 p = RunEstimator(model, e, v.data());
        SCOPED_TRACE(name + " " + std::string(EstimatorName(e)) + " theta " +
                     std::to_string(truth.theta_rad));
        EXPECT_NEAR(p.x_mm, truth.x_mm, 1e-9);
        EXPECT_NEAR(p.y_mm, truth.y_mm, 1e-9);
        EXPECT_NEAR(WrapAngle(p.theta_rad - truth.theta_rad), 0.0, 1e-12);
        EXPECT_GT(p.theta_rad, -kPi);  // reported in (-pi, pi]
        EXPECT_LE(p.theta_rad, kPi);
      }
    }
  }
}

TEST(Estimators, FastIsTheMeanProjectedWithTheSummedPairAngle) {
  // Hand-computed: Linear pattern (key at 0, patches at +-65 on x), pair (1 -> 2) has model
  // direction (-1, 0). Observed: patch 1 at (10, 2), patch 2 at (-10, -2), key at (0.3, 0).
  // Displacement (-20, -4) rotated by minus pi: (20, 4); angle atan2(4, 20); mean (0.1, 0);
  // centroid of the model is (0, 0), so the origin is the mean.
  const Model model = Model::FromPattern(testing::ShippedPattern("linear"));
  const std::array<Vec2, 3> v = {Vec2(0.3, 0.0), Vec2(10, 2), Vec2(-10, -2)};
  const Pose2 p = Fast(model, v.data());
  EXPECT_NEAR(p.theta_rad, std::atan2(4.0, 20.0), 1e-15);
  EXPECT_NEAR(p.x_mm, 0.1, 1e-15);
  EXPECT_NEAR(p.y_mm, 0.0, 1e-15);
}

TEST(Estimators, KeyPatchReportsTheKeyPositionWithTheFastAngle) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  auto v = Place(model, {100, 200, 0.3});
  v[0] += Vec2(0.5, -0.25);  // move only the key
  const Pose2 key = KeyPatch(model, v.data());
  const Pose2 fast = Fast(model, v.data());
  EXPECT_NEAR(key.x_mm, 100.5, 1e-12);
  EXPECT_NEAR(key.y_mm, 199.75, 1e-12);
  EXPECT_EQ(key.theta_rad, fast.theta_rad);
}

TEST(Estimators, MlAgreesWithTheClosedFormLeastSquaresOnNoisyPatches) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 3.0);
  for (const std::string& name : testing::ShippedPatternNames()) {
    const Model model = Model::FromPattern(testing::ShippedPattern(name));
    for (const Pose2& truth : TestPoses()) {
      auto v = Place(model, truth);
      for (int i = 0; i < model.num_patches; ++i) v[i] += Vec2(noise(rng), noise(rng));
      Summary summary;
      const Pose2 ml = RunEstimator(model, Estimator::kMl, v.data(), &summary);
      const Pose2 lsq = LeastSquares(model, v.data());
      ASSERT_EQ(summary.termination, Termination::kConverged) << name;
      EXPECT_LE(summary.iterations, 4) << name;
      EXPECT_NEAR(WrapAngle(ml.theta_rad - lsq.theta_rad), 0.0, 1e-9) << name;
      EXPECT_NEAR(ml.x_mm, lsq.x_mm, 1e-7) << name;
      EXPECT_NEAR(ml.y_mm, lsq.y_mm, 1e-7) << name;
      EXPECT_LE(summary.final_cost, summary.initial_cost + 1e-9);
      EXPECT_NEAR(summary.final_cost, SumSquaredError(model, v.data(), lsq), 1e-9);
    }
  }
}

TEST(Estimators, LeastSquaresIsAMinimumOfTheSumSquaredError) {
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 2.0);
  const Model model = Model::FromPattern(testing::ShippedPattern("triangle"));
  auto v = Place(model, {3, 4, 1.0});
  for (int i = 0; i < model.num_patches; ++i) v[i] += Vec2(noise(rng), noise(rng));
  const Pose2 best = LeastSquares(model, v.data());
  const double e0 = SumSquaredError(model, v.data(), best);
  for (double d : {-1e-3, 1e-3}) {
    EXPECT_GT(SumSquaredError(model, v.data(), {best.x_mm + d, best.y_mm, best.theta_rad}), e0);
    EXPECT_GT(SumSquaredError(model, v.data(), {best.x_mm, best.y_mm + d, best.theta_rad}), e0);
    EXPECT_GT(SumSquaredError(model, v.data(), {best.x_mm, best.y_mm, best.theta_rad + d}), e0);
  }
}

TEST(Estimators, MlReportsNumericalFailureOnNonFiniteInput) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  auto v = Place(model, {0, 0, 0});
  v[2] = Vec2(std::nan(""), 0.0);
  Summary summary;
  MaximumLikelihood(model, v.data(), Pose2{}, Options{}, &summary);
  EXPECT_EQ(summary.termination, Termination::kNumericalFailure);
}

TEST(Estimators, MlReportsMaxIterationsWhenStoppedEarly) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  const auto v = Place(model, {10, 20, 2.0});
  Options options;
  options.max_iterations = 1;
  Summary summary;
  // Started far away (1 rad off): one step cannot meet the tolerances.
  MaximumLikelihood(model, v.data(), Pose2{0, 0, 1.0}, options, &summary);
  EXPECT_EQ(summary.termination, Termination::kMaxIterations);
  EXPECT_EQ(summary.iterations, 1);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
}

TEST(Estimators, MlConvergesFromAFarStartThroughTheDampedSteps) {
  // Started 2.5 rad off the optimum the Hessian is indefinite; the damped steps must still
  // reach the least-squares optimum.
  const Model model = Model::FromPattern(testing::ShippedPattern("triangle"));
  const auto v = Place(model, {10, 20, 0.5});
  Options options;
  options.max_iterations = 200;
  Summary summary;
  const Pose2 p = MaximumLikelihood(model, v.data(), Pose2{10, 20, 3.0}, options, &summary);
  EXPECT_EQ(summary.termination, Termination::kConverged);
  EXPECT_NEAR(WrapAngle(p.theta_rad - 0.5), 0.0, 1e-9);
}

TEST(Estimators, GradientAndHessianMatchFiniteDifferencesOfTheCost) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  auto v = Place(model, {5, -3, 0.7});
  v[1] += Vec2(0.4, -0.9);
  const Pose2 r{4.0, -2.0, 0.6};
  double g[3], hess[3][3];
  SumSquaredErrorDerivatives(model, v.data(), r, g, hess);
  const double h = 1e-4;
  auto shifted = [&](int axis, double d) {
    Pose2 p = r;
    (axis == 0 ? p.x_mm : axis == 1 ? p.y_mm : p.theta_rad) += d;
    return p;
  };
  for (int a = 0; a < 3; ++a) {
    const double numeric = (SumSquaredError(model, v.data(), shifted(a, h)) -
                            SumSquaredError(model, v.data(), shifted(a, -h))) /
                           (2 * h);
    EXPECT_NEAR(g[a], numeric, 1e-5 * (1 + std::abs(numeric))) << "gradient " << a;
    double gp[3], gm[3], unused[3][3];
    SumSquaredErrorDerivatives(model, v.data(), shifted(a, h), gp, unused);
    SumSquaredErrorDerivatives(model, v.data(), shifted(a, -h), gm, unused);
    for (int b = 0; b < 3; ++b) {
      const double numeric_h = (gp[b] - gm[b]) / (2 * h);
      EXPECT_NEAR(hess[b][a], numeric_h, 1e-5 * (1 + std::abs(numeric_h)))
          << "hessian " << b << "," << a;
    }
  }
}

TEST(Estimators, NamesRoundTrip) {
  for (Estimator e : kEveryEstimator) {
    Estimator parsed;
    ASSERT_TRUE(ParseEstimator(EstimatorName(e), &parsed));
    EXPECT_EQ(parsed, e);
  }
  Estimator unused;
  EXPECT_FALSE(ParseEstimator("newton", &unused));
}

TEST(Estimators, TerminationNames) {
  EXPECT_EQ(TerminationName(Termination::kConverged), "converged");
  EXPECT_EQ(TerminationName(Termination::kMaxIterations), "max_iterations");
  EXPECT_EQ(TerminationName(Termination::kNumericalFailure), "numerical_failure");
}

TEST(EstimatorOptions, DefaultsAreValid) {
  EXPECT_TRUE(Check(Options{}).empty());
  Validate(Options{});
}

TEST(EstimatorOptions, MaxIterationsIsOneToAThousand) {
  Options o;
  o.max_iterations = 1000;
  EXPECT_TRUE(Check(o).empty());
  o.max_iterations = 0;
  EXPECT_INPUT_ERROR(Validate(o), "max_iterations is 0; expected an integer in [1, 1000]");
  o.max_iterations = 1001;
  EXPECT_INPUT_ERROR(Validate(o), "max_iterations is 1001; expected an integer in [1, 1000]");
}

TEST(EstimatorOptions, EveryProblemIsListedWithTheFieldPrefix) {
  Options o;
  o.max_iterations = 0;
  o.step_tolerance_mm = -1.0;
  o.step_tolerance_rad = std::nan("");
  o.gradient_tolerance = std::numeric_limits<double>::infinity();
  const std::vector<OptionsProblem> problems = Check(o, "ml_");
  ASSERT_EQ(problems.size(), 4u);
  EXPECT_EQ(problems[0].field, "ml_max_iterations");
  EXPECT_EQ(problems[0].message, "ml_max_iterations is 0; expected an integer in [1, 1000]");
  EXPECT_EQ(problems[1].message, "ml_step_tolerance_mm is -1; expected a finite number >= 0 (mm)");
  EXPECT_EQ(problems[2].message,
            "ml_step_tolerance_rad is nan; expected a finite number >= 0 (rad)");
  EXPECT_EQ(problems[3].message, "ml_gradient_tolerance is inf; expected a finite number >= 0");
}

}  // namespace
}  // namespace patlab::estimate
