#include "patlab/core/geometry.h"

#include <gtest/gtest.h>

#include <numbers>

namespace patlab {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(WrapAngle, MapsIntoHalfOpenIntervalMinusPiToPi) {
  EXPECT_EQ(WrapAngle(0.0), 0.0);
  EXPECT_EQ(WrapAngle(kPi), kPi);
  EXPECT_EQ(WrapAngle(-kPi), kPi);
  EXPECT_NEAR(WrapAngle(3 * kPi), kPi, 1e-15);
  EXPECT_NEAR(WrapAngle(-3 * kPi), kPi, 1e-15);
  EXPECT_NEAR(WrapAngle(2 * kPi + 0.25), 0.25, 1e-15);
  EXPECT_NEAR(WrapAngle(-2 * kPi - 0.25), -0.25, 1e-15);
  EXPECT_NEAR(WrapAngle(kPi + 0.1), -kPi + 0.1, 1e-15);
  EXPECT_EQ(WrapAngle(1.0), 1.0);  // exact inside the range
}

TEST(Pose2, AppliesRotationThenTranslation) {
  const Pose2 pose{10, 20, kPi / 2};
  const Vec2 p = pose.Apply(Vec2(1, 0));
  EXPECT_NEAR(p.x(), 10, 1e-15);
  EXPECT_NEAR(p.y(), 21, 1e-15);
}

}  // namespace
}  // namespace patlab
