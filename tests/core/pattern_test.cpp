#include "patlab/core/pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace patlab {
namespace {

Patch Disc(double x, double y, double r) {
  Patch p;
  p.position_mm = Vec2(x, y);
  p.radius_mm = r;
  return p;
}

Patch Rect(double x, double y, double sx, double sy, double angle_deg = 0.0) {
  return RectanglePatch(Vec2(x, y), Vec2(sx, sy), angle_deg * std::numbers::pi / 180.0,
                        PatchRole::kId);
}

TEST(Patch, AreaAndBoundsOfBothShapes) {
  EXPECT_DOUBLE_EQ(Disc(0, 0, 10).Area(), 100.0 * std::numbers::pi);
  const Patch r = Rect(0, 0, 70, 32);
  EXPECT_DOUBLE_EQ(r.Area(), 2240.0);
  // The equal-area radius: pi r^2 = 2240.
  EXPECT_NEAR(std::numbers::pi * r.radius_mm * r.radius_mm, 2240.0, 1e-9);
  EXPECT_DOUBLE_EQ(r.BoundingRadius(), 0.5 * std::hypot(70.0, 32.0));
  EXPECT_TRUE(r.Contains(Vec2(34.9, 15.9)));
  EXPECT_FALSE(r.Contains(Vec2(35.1, 0)));
  EXPECT_FALSE(r.Contains(Vec2(0, 16.1)));
  // Rotated by 90 degrees: the long side along y.
  const Patch q = Rect(0, 0, 70, 32, 90);
  EXPECT_TRUE(q.Contains(Vec2(0, 34.9)));
  EXPECT_FALSE(q.Contains(Vec2(16.1, 0)));
}

// Each gap computed by hand from the figures in the comments.
TEST(PatchGap, DiscsAreTheirCentreDistanceLessTheRadii) {
  EXPECT_DOUBLE_EQ(PatchGap(Disc(0, 0, 10), Disc(30, 40, 20)), 20.0);  // 50 - 30
  EXPECT_DOUBLE_EQ(PatchGap(Disc(0, 0, 10), Disc(25, 0, 20)), -5.0);   // overlap 5
  EXPECT_DOUBLE_EQ(PatchGap(Disc(0, 0, 10), Disc(30, 0, 20)), 0.0);    // touching
}

TEST(PatchGap, RectangleAndDisc) {
  const Patch r = Rect(0, 0, 20, 10);  // x in [-10, 10], y in [-5, 5]
  // Facing the long side: the disc's centre 12 above the edge y = 5, radius 4: gap 8.
  EXPECT_DOUBLE_EQ(PatchGap(r, Disc(0, 17, 4)), 8.0);
  EXPECT_DOUBLE_EQ(PatchGap(Disc(0, 17, 4), r), 8.0);  // symmetric
  // Off the corner (10, 5): centre at (13, 9), 5 away. Radius 4: gap 1. Radius 4.5 does not
  // reach the corner although along each axis alone (3 and 4 beyond the edges) it would overlap.
  EXPECT_NEAR(PatchGap(r, Disc(13, 9, 4)), 1.0, 1e-12);
  EXPECT_NEAR(PatchGap(r, Disc(13, 9, 4.5)), 0.5, 1e-12);
  // Centre inside the rectangle: overlap.
  EXPECT_LT(PatchGap(r, Disc(9, 0, 1)), 0.0);
  // Crossing the edge x = 10 by 2.
  EXPECT_DOUBLE_EQ(PatchGap(r, Disc(13, 0, 5)), -2.0);
  // Rotated 90 degrees: x in [-5, 5], y in [-10, 10]; disc at (12, 0), r 4: gap 3.
  EXPECT_NEAR(PatchGap(Rect(0, 0, 20, 10, 90), Disc(12, 0, 4)), 3.0, 1e-12);
}

TEST(PatchGap, RectangleAndRectangle) {
  // Side by side, as the VSS top: 70 x 32 at y = +-18 leave a 4 mm gap.
  EXPECT_NEAR(PatchGap(Rect(0, 18, 70, 32), Rect(0, -18, 70, 32)), 4.0, 1e-12);
  // Overlapping by 2 along y.
  EXPECT_NEAR(PatchGap(Rect(0, 15, 70, 32), Rect(0, -15, 70, 32)), -2.0, 1e-12);
  // Corner to corner: (10, 10)-(20, 20) squares of side 10 at (5, 5) and (25, 25): corners
  // (10, 10) and (20, 20) are sqrt(200) apart, though each axis alone separates them by 10.
  EXPECT_NEAR(PatchGap(Rect(5, 5, 10, 10), Rect(25, 25, 10, 10)), std::sqrt(200.0), 1e-12);
  // A square rotated 45 degrees (half diagonal 7.071) whose corner points at an axis-aligned
  // square's side: centres 20 apart on x, the side at x = 5 (square of side 10 at 0), the corner
  // at 20 - 7.071 = 12.929: gap 7.929. Its axes alone would give 20 - 5 - 7.071 = 7.929 too;
  // moved to 10 the corner pokes 2.071 into the square.
  const double h = 5.0 * std::sqrt(2.0);
  EXPECT_NEAR(PatchGap(Rect(0, 0, 10, 10), Rect(20, 0, 10, 10, 45)), 15.0 - h, 1e-12);
  EXPECT_NEAR(PatchGap(Rect(0, 0, 10, 10), Rect(10, 0, 10, 10, 45)), 5.0 - h, 1e-12);
  // Two thin rectangles crossing like a plus sign: overlap, though no corner is inside the other.
  EXPECT_LT(PatchGap(Rect(0, 0, 40, 4), Rect(0, 0, 40, 4, 90)), 0.0);
  // Touching edge to edge.
  EXPECT_NEAR(PatchGap(Rect(0, 0, 10, 10), Rect(10, 0, 10, 10)), 0.0, 1e-12);
}

}  // namespace
}  // namespace patlab
