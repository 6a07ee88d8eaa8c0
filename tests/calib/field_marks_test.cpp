// The painted marks of a field file: the arcs' extents inferred from the lines.
#include "patlab/calib/field_marks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "patlab/formats/field_file.h"

namespace patlab::calib {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(FieldMarks, Ssl2009DefenseArcsAreQuartersContinuingTheFrontLine) {
  const Field f = formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2009.toml");
  const FieldMarks m = PaintedMarks(f);
  // The painted lines: the field's 7, not the goal walls' 6 faces.
  ASSERT_EQ(f.lines.size(), 13u);
  ASSERT_EQ(m.segments.size(), 7u);
  for (const MarkSegment& s : m.segments) {
    EXPECT_TRUE(IsPaintedLine(f.lines[static_cast<size_t>(s.line)]));
  }
  ASSERT_EQ(m.arcs.size(), 5u);
  // The centre circle whole; defense_arc_left_pos (centre (3025, 175)) from 90 to 180 deg.
  EXPECT_DOUBLE_EQ(m.arcs[0].sweep_rad, 2 * kPi);
  const MarkArc& left_pos = m.arcs[1];
  EXPECT_EQ(f.circles[static_cast<size_t>(left_pos.circle)].name, "defense_arc_left_pos");
  EXPECT_NEAR(left_pos.start_rad, 0.5 * kPi, 0.01);
  EXPECT_NEAR(left_pos.sweep_rad, 0.5 * kPi, 0.01);
  // defense_arc_right_pos (centre (3025, -175)) from 180 to 270 deg.
  EXPECT_NEAR(m.arcs[2].start_rad, kPi, 0.01);
  EXPECT_NEAR(m.arcs[2].sweep_rad, 0.5 * kPi, 0.01);
  // Distances: on the arc 0, beyond its end to the nearer end point.
  EXPECT_NEAR(DistanceToMark(left_pos, Vec2(3025 - 500, 175 + 0)), 0.0, 1.0);
  EXPECT_NEAR(DistanceToMark(left_pos, Vec2(2525, -175)), 350.0, 1.0);
  EXPECT_NEAR(DistanceToMark(m.segments[4], Vec2(10, 3000)), std::hypot(10.0, 975.0), 1e-9);
}

TEST(FieldMarks, SamplesCoverEveryMarkAtTheStep) {
  const Field f = formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/vss.toml");
  const FieldMarks m = PaintedMarks(f);
  std::vector<int> mark;
  const std::vector<Vec2> pts = SampleMarks(m, 10.0, &mark);
  ASSERT_EQ(pts.size(), mark.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    const size_t k = static_cast<size_t>(mark[i]);
    const double d = k < m.segments.size() ? DistanceToMark(m.segments[k], pts[i])
                                           : DistanceToMark(m.arcs[k - m.segments.size()], pts[i]);
    EXPECT_LT(d, 1e-6);
  }
  EXPECT_EQ(mark.back(), static_cast<int>(m.segments.size() + m.arcs.size()) - 1);
}

TEST(FieldMarks, ASamplerGivesSampleMarksPointsAtEveryStep) {
  // Steps that keep every mark's count (10.0 -> 10.001), change some (12, 30) and come back: each
  // time the sampler's points are SampleMarks' own, bit for bit.
  const Field f = formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2009.toml");
  const FieldMarks m = PaintedMarks(f);
  MarkSampler sampler(m);
  for (const double step : {10.0, 10.001, 12.0, 30.0, 10.0, 9.999, 250.0, 10.0}) {
    const std::vector<Vec2> want = SampleMarks(m, step, nullptr);
    const std::vector<Vec2>& got = sampler.Sample(step);
    ASSERT_EQ(got.size(), want.size()) << step;
    for (size_t i = 0; i < want.size(); ++i) {
      EXPECT_EQ(got[i].x(), want[i].x()) << step << " " << i;
      EXPECT_EQ(got[i].y(), want[i].y()) << step << " " << i;
    }
  }
  const FieldMarks no_marks;
  MarkSampler none(no_marks);
  EXPECT_TRUE(none.Sample(10.0).empty());
}

}  // namespace
}  // namespace patlab::calib
