// Stage 3's pseudo-angle (detector_internal.h) against atan2, whose order it stands in for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "patlab/detect/detector_internal.h"

namespace patlab::detect::internal {
namespace {

std::vector<Vec2> Directions() {
  std::vector<Vec2> d = {{1, 0},     {-1, 0},     {0, 1},       {0, -1},      {1, 1},   {-1, 1},
                         {-1, -1},   {1, -1},     {-1, 0.0},    {-1, -0.0},   {0.0, 1}, {-0.0, 1},
                         {-0.0, -1}, {3, 1e-300}, {-3, 1e-300}, {-3, -1e-300}};
  uint64_t state = 99;
  for (int i = 0; i < 20000; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const double a = (static_cast<double>(state >> 11) * 0x1p-53 * 2.0 - 1.0) * 3.141592653589793;
    const double r = 1.0 + static_cast<double>(state & 1023);
    d.emplace_back(r * std::cos(a), r * std::sin(a));
    if (i % 100 == 0) d.emplace_back(2.0 * d.back());  // exactly the same direction, farther
  }
  return d;
}

TEST(PseudoAngle, OrdersDirectionsAsAtan2WithTheSameCut) {
  const std::vector<Vec2> d = Directions();
  for (const Vec2& v : d) {
    const double p = PseudoAngle(v);
    EXPECT_GE(p, -2.0);
    EXPECT_LE(p, 2.0);
  }
  EXPECT_EQ(PseudoAngle(Vec2(-1, 0.0)), 2.0);    // atan2 = pi
  EXPECT_EQ(PseudoAngle(Vec2(-1, -0.0)), -2.0);  // atan2 = -pi
  EXPECT_EQ(PseudoAngle(Vec2(1, 0)), 0.0);
  EXPECT_EQ(PseudoAngle(Vec2(0, 1)), 1.0);
  EXPECT_EQ(PseudoAngle(Vec2(0, -1)), -1.0);
  EXPECT_TRUE(std::isnan(PseudoAngle(Vec2(0, 0))));
  // Every pair: pseudo-angles more than the stage's slack apart order as atan2 does, strictly;
  // equal atan2 values never have pseudo-angles that far apart.
  int checked = 0;
  for (size_t i = 0; i < d.size(); i += 7) {
    for (size_t j = 0; j < d.size(); j += 13) {
      const double pi = PseudoAngle(d[i]), pj = PseudoAngle(d[j]);
      const double ti = std::atan2(d[i].y(), d[i].x()), tj = std::atan2(d[j].y(), d[j].x());
      if (std::fabs(pi - pj) > 1e-9) {
        ASSERT_EQ(pi < pj, ti < tj) << i << " " << j;
        ASSERT_NE(ti, tj);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 1000000);
}

}  // namespace
}  // namespace patlab::detect::internal
