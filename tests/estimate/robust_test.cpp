// The robust estimator (estimate/robust.h): exact on exact patches, a maximum of the mixture's
// likelihood, unmoved by a gross outlier, least squares when nothing is far.
#include "patlab/estimate/robust.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "../test_util.h"

namespace patlab::estimate {
namespace {

std::array<Vec2, kMaxPatches> Noisy(const Model& model, const Pose2& truth, double sigma,
                                    std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, sigma);
  std::array<Vec2, kMaxPatches> v{};
  for (int i = 0; i < model.num_patches; ++i) {
    v[i] = truth.Apply(model.model_mm[i]) + Vec2(normal(rng), normal(rng));
  }
  return v;
}

const RobustModel kMixture{1.0, 0.05, 10.0};
const RobustModel kHuber{1.0, 0.0, 10.0};

TEST(Robust, ExactPatchesGiveTheExactPose) {
  for (const std::string& name : testing::ShippedPatternNames()) {
    const Model model = Model::FromPattern(testing::ShippedPattern(name));
    for (const Pose2& truth : {Pose2{0, 0, 0}, Pose2{1200, -800, 3.0}, Pose2{-5, 5, -2.0}}) {
      std::mt19937_64 rng(1);
      const auto v = Noisy(model, truth, 0.0, rng);
      for (const RobustModel& r : {kMixture, kHuber}) {
        const Pose2 p = Robust(model, v.data(), r, nullptr);
        EXPECT_NEAR(p.x_mm, truth.x_mm, 1e-9) << name;
        EXPECT_NEAR(p.y_mm, truth.y_mm, 1e-9) << name;
        EXPECT_NEAR(WrapAngle(p.theta_rad - truth.theta_rad), 0.0, 1e-12) << name;
      }
    }
  }
}

TEST(Robust, UnitWeightsAreLeastSquares) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  std::mt19937_64 rng(2);
  const auto v = Noisy(model, {100, 200, 1.0}, 3.0, rng);
  const std::array<double, kMaxPatches> ones = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
  const Pose2 w = WeightedLeastSquares(model, v.data(), ones.data());
  const Pose2 l = LeastSquares(model, v.data());
  EXPECT_NEAR(w.x_mm, l.x_mm, 1e-9);
  EXPECT_NEAR(w.y_mm, l.y_mm, 1e-9);
  EXPECT_NEAR(WrapAngle(w.theta_rad - l.theta_rad), 0.0, 1e-12);
}

TEST(Robust, MixturePoseIsAMaximumOfTheMixtureLikelihood) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  std::mt19937_64 rng(3);
  for (int t = 0; t < 50; ++t) {
    auto v = Noisy(model, {0, 0, 0.3 * t}, 1.0, rng);
    v[t % model.num_patches] += Vec2(8.0, -6.0);  // an outlier-sized error
    Summary summary;
    const Pose2 p = Robust(model, v.data(), kMixture, &summary);
    ASSERT_EQ(summary.termination, Termination::kConverged);
    const double best = RobustObjective(model, v.data(), kMixture, p);
    EXPECT_NEAR(-summary.final_cost, best, 1e-12 * std::abs(best));
    EXPECT_LE(summary.final_cost, summary.initial_cost + 1e-12);
    // No pose nearby is more likely (steps along each axis and diagonals).
    for (double h : {1e-3, 1e-2}) {
      for (const Pose2& d : {Pose2{h, 0, 0}, Pose2{0, h, 0}, Pose2{0, 0, h / 100},
                             Pose2{h, h, h / 100}, Pose2{-h, h, -h / 100}}) {
        for (double sign : {-1.0, 1.0}) {
          const Pose2 q{p.x_mm + sign * d.x_mm, p.y_mm + sign * d.y_mm,
                        p.theta_rad + sign * d.theta_rad};
          EXPECT_LE(RobustObjective(model, v.data(), kMixture, q), best + 1e-12) << t;
        }
      }
    }
  }
}

TEST(Robust, AGrossOutlierDoesNotMoveThePose) {
  const Model model = Model::FromPattern(testing::ShippedPattern("butterfly"));
  std::mt19937_64 rng(4);
  const Pose2 truth{300, -100, 2.0};
  auto v = Noisy(model, truth, 1.0, rng);
  v[2] += Vec2(40.0, 30.0);  // 50 sigma
  for (const RobustModel& r : {kMixture, kHuber}) {
    const Pose2 p = Robust(model, v.data(), r, nullptr);
    EXPECT_LT((Vec2(p.x_mm, p.y_mm) - Vec2(truth.x_mm, truth.y_mm)).norm(), 2.5);
    EXPECT_LT(std::abs(WrapAngle(p.theta_rad - truth.theta_rad)), 0.05);
  }
  const Pose2 l = LeastSquares(model, v.data());
  EXPECT_GT((Vec2(l.x_mm, l.y_mm) - Vec2(truth.x_mm, truth.y_mm)).norm(), 5.0);
}

TEST(Robust, HuberIsLeastSquaresWhenEveryResidualIsWithinTheTuningConstant) {
  const Model model = Model::FromPattern(testing::ShippedPattern("triangle"));
  std::mt19937_64 rng(5);
  const auto v = Noisy(model, {10, 20, -1.0}, 0.3, rng);  // residuals ~0.3 sigma of 1 mm
  const Pose2 h = Robust(model, v.data(), kHuber, nullptr);
  const Pose2 l = LeastSquares(model, v.data());
  EXPECT_NEAR(h.x_mm, l.x_mm, 1e-9);
  EXPECT_NEAR(h.y_mm, l.y_mm, 1e-9);
  EXPECT_NEAR(WrapAngle(h.theta_rad - l.theta_rad), 0.0, 1e-12);
}

}  // namespace
}  // namespace patlab::estimate
