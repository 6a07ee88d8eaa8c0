#include "patlab/estimate/estimators_many.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "../test_util.h"

namespace patlab::estimate {
namespace {

// Trials of random patches (near the pattern at a random pose, or anywhere), the awkward ones
// first: all patches at one point (atan2(0, 0)), a heading of exactly pi, exact patches.
std::vector<std::array<Vec2, kMaxPatches>> Trials(const Model& model, int count) {
  std::vector<std::array<Vec2, kMaxPatches>> trials(static_cast<size_t>(count));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-1400, 1400), t(-std::numbers::pi, std::numbers::pi);
  std::normal_distribution<double> noise(0.0, 2.0), wild(0.0, 500.0);
  for (int k = 0; k < count; ++k) {
    const Pose2 pose{x(rng), x(rng), k == 1 ? std::numbers::pi : t(rng)};
    for (int i = 0; i < model.num_patches; ++i) {
      Vec2& v = trials[static_cast<size_t>(k)][static_cast<size_t>(i)];
      v = k == 0 ? Vec2(3, 4) : pose.Apply(model.model_mm[i]);
      if (k > 2) v += Vec2(noise(rng), noise(rng));
      if (k % 7 == 3) v = Vec2(wild(rng), wild(rng));
    }
  }
  return trials;
}

Pose2 OneTrial(const Model& model, Estimator method, const Vec2* v) {
  switch (method) {
    case Estimator::kKey:
      return KeyPatch(model, v);
    case Estimator::kLsq:
      return LeastSquares(model, v);
    default:
      return Fast(model, v);
  }
}

bool SameBits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

void ExpectOneTrialPoses(const Model& model, Estimator method,
                         const std::vector<std::array<Vec2, kMaxPatches>>& trials,
                         const std::vector<double>& poses, const char* name) {
  for (size_t k = 0; k < trials.size(); ++k) {
    const Pose2 p = OneTrial(model, method, trials[k].data());
    const double* q = poses.data() + 3 * k;
    ASSERT_TRUE(SameBits(q[0], p.x_mm) && SameBits(q[1], p.y_mm) && SameBits(q[2], p.theta_rad))
        << name << " " << EstimatorName(method) << " trial " << k << ": (" << q[0] << ", " << q[1]
        << ", " << q[2] << ") vs (" << p.x_mm << ", " << p.y_mm << ", " << p.theta_rad << ")";
  }
}

// EstimateMany on a (trials, patches, 2) array laid out as `layout` says gives, trial by trial,
// the one-trial estimator's pose to the last bit: C order, a wider buffer (x, y apart), trials in
// reverse (negative stride), patches and axes transposed; counts that are no multiple of the
// block, and a range that starts inside the array; and so does each instruction-set version.
TEST(EstimateMany, IsTheOneTrialEstimatorBitForBit) {
  for (const char* name : {"butterfly", "triangle", "ssl-standard", "linear", "simple"}) {
    const Model model = Model::FromPattern(testing::ShippedPattern(name));
    const int n = model.num_patches, count = 1000;
    const auto trials = Trials(model, count);
    // Layouts: {trial, patch, axis} strides in doubles, and the offset of trial 0.
    struct Layout {
      std::ptrdiff_t trial, patch, axis, offset;
    };
    const Layout layouts[] = {{2 * n, 2, 1, 0},
                              {4 * n, 4, 2, 0},
                              {-2 * n, 2, 1, 2 * n * (count - 1)},
                              {1, count, n * count, 0}};
    for (const Layout& layout : layouts) {
      std::vector<double> buffer(static_cast<size_t>(4 * n * count), -1.0);
      for (int k = 0; k < count; ++k) {
        for (int i = 0; i < n; ++i) {
          const std::ptrdiff_t at = layout.offset + k * layout.trial + i * layout.patch;
          buffer[static_cast<size_t>(at)] =
              trials[static_cast<size_t>(k)][static_cast<size_t>(i)].x();
          buffer[static_cast<size_t>(at + layout.axis)] =
              trials[static_cast<size_t>(k)][static_cast<size_t>(i)].y();
        }
      }
      const PatchArray array{reinterpret_cast<const unsigned char*>(buffer.data() + layout.offset),
                             layout.trial * 8, layout.patch * 8, layout.axis * 8};
      for (Estimator method : {Estimator::kFast, Estimator::kKey, Estimator::kLsq}) {
        ASSERT_TRUE(HasManyVersion(method));
        std::vector<double> poses(static_cast<size_t>(3 * count));
        EstimateMany(model, method, array, 0, 600, poses.data());
        EstimateMany(model, method, array, 600, count - 600, poses.data() + 3 * 600);
        ExpectOneTrialPoses(model, method, trials, poses, name);
        // Every instruction-set version the CPU runs gives the same bits as the dispatched one.
        for (ManyIsa isa : SupportedManyIsas()) {
          std::vector<double> with(poses.size(), -1.0);
          EstimateManyWith(isa, model, method, array, 0, count, with.data());
          ExpectOneTrialPoses(model, method, trials, with, name);
        }
      }
    }
  }
  EXPECT_FALSE(HasManyVersion(Estimator::kMl));
  EXPECT_FALSE(HasManyVersion(Estimator::kRobust));
}

}  // namespace
}  // namespace patlab::estimate
