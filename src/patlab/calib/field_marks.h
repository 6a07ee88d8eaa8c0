// The painted marks of a field (calib/field.h) as drawable, matchable geometry: each painted
// straight line a segment between its ends (the goal walls' inner faces, lines named goal_side_*
// and goal_back_*, are walls, not paint, and left out), each circle the arc of it that is painted.
// An arc with its extent in the model (from_deg, to_deg) is painted as given. For a full circle
// the painted arc is inferred: the part inside the rectangle spanned by the painted lines, and,
// for a circle that continues a line smoothly (it passes through the line's end with the line's
// direction as its tangent), only the part beyond that end. Used to render field
// lines (render/field_render.h) and to match found line pixels to the field (auto_calibrate.h).
#pragma once

#include <vector>

#include "patlab/calib/field.h"
#include "patlab/core/geometry.h"

namespace patlab::calib {

struct MarkSegment {
  int line = 0;  // index into Field::lines
  Vec2 from_mm = Vec2::Zero(), to_mm = Vec2::Zero();
};

struct MarkArc {
  int circle = 0;  // index into Field::circles
  Vec2 centre_mm = Vec2::Zero();
  double radius_mm = 0.0;
  double start_rad = 0.0;  // the arc runs counter-clockwise from start_rad ...
  double sweep_rad = 0.0;  // ... through sweep_rad, in (0, 2 pi]
};

struct FieldMarks {
  std::vector<MarkSegment> segments;
  std::vector<MarkArc> arcs;
};

FieldMarks PaintedMarks(const Field& field);

// Whether a line of a field model is painted on the floor (not a goal wall's face).
bool IsPaintedLine(const FieldLine& line);

// The distance (mm) from `p` to a mark (to its nearest point, ends included).
double DistanceToMark(const MarkSegment& s, const Vec2& p);
double DistanceToMark(const MarkArc& a, const Vec2& p);

// Points along every mark, about `step_mm` apart (ends included); `mark` receives each point's
// mark: segments first (0 .. segments - 1), then arcs.
std::vector<Vec2> SampleMarks(const FieldMarks& marks, double step_mm, std::vector<int>* mark);

// SampleMarks over a run of steps: its points depend on the step only through each mark's number
// of samples, so a step that gives every mark the counts of the previous one gives the previous
// points, kept here (a search scores hundreds of cameras of nearly one scale). `marks` must
// outlive the sampler.
class MarkSampler {
 public:
  explicit MarkSampler(const FieldMarks& marks) : marks_(marks) {}
  explicit MarkSampler(const FieldMarks&& marks) = delete;  // a temporary would not outlive it
  const std::vector<Vec2>& Sample(double step_mm);

 private:
  const FieldMarks& marks_;
  std::vector<int> counts_;
  std::vector<Vec2> points_;
};

}  // namespace patlab::calib
