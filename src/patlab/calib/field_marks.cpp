// The painted marks of a field: segments and the painted arcs of its circles (field_marks.h).
#include "patlab/calib/field_marks.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace patlab::calib {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kArcSteps = 1440;  // the resolution (0.25 deg) of the inferred arc extents

// Whether the point at angle `phi` of the circle is painted (field_marks.h).

bool Painted(const Field& field, const FieldCircle& c, double phi, const Vec2& lo, const Vec2& hi) {
  const Vec2 q = c.centre_mm + c.radius_mm * Vec2(std::cos(phi), std::sin(phi));
  constexpr double kSlackMm = 1.0;
  if (q.x() < lo.x() - kSlackMm || q.y() < lo.y() - kSlackMm || q.x() > hi.x() + kSlackMm ||
      q.y() > hi.y() + kSlackMm) {
    return false;
  }
  for (const FieldLine& l : field.lines) {
    if (!IsPaintedLine(l)) continue;
    for (int end = 0; end < 2; ++end) {
      const Vec2 e = end == 0 ? l.from_mm : l.to_mm;
      const Vec2 d = ((end == 0 ? l.from_mm - l.to_mm : l.to_mm - l.from_mm)).normalized();
      const Vec2 radial = e - c.centre_mm;
      if (std::abs(radial.norm() - c.radius_mm) > 1.0) continue;
      if (std::abs(d.dot(radial)) > 0.01 * c.radius_mm) continue;
      if ((q - e).dot(d) < -kSlackMm) return false;  // behind the end the arc continues
    }
  }
  return true;
}

}  // namespace

bool IsPaintedLine(const FieldLine& line) {
  return !line.name.starts_with("goal_side_") && !line.name.starts_with("goal_back_");
}

FieldMarks PaintedMarks(const Field& field) {
  FieldMarks marks;
  Vec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (size_t i = 0; i < field.lines.size(); ++i) {
    const FieldLine& l = field.lines[i];
    if (!IsPaintedLine(l)) continue;
    marks.segments.push_back({static_cast<int>(i), l.from_mm, l.to_mm});
    lo = lo.cwiseMin(l.from_mm).cwiseMin(l.to_mm);
    hi = hi.cwiseMax(l.from_mm).cwiseMax(l.to_mm);
  }
  if (marks.segments.empty()) {  // no rectangle: every circle whole
    lo = Vec2(-INFINITY, -INFINITY);
    hi = Vec2(INFINITY, INFINITY);
  }
  for (size_t i = 0; i < field.circles.size(); ++i) {
    const FieldCircle& c = field.circles[i];
    if (!c.IsFullCircle()) {  // the model gives the arc's extent: painted as given
      constexpr double kDegToRad = std::numbers::pi / 180.0;
      marks.arcs.push_back({static_cast<int>(i), c.centre_mm, c.radius_mm, c.from_deg * kDegToRad,
                            (c.to_deg - c.from_deg) * kDegToRad});
      continue;
    }
    std::vector<char> on(kArcSteps);
    int count = 0;
    for (int k = 0; k < kArcSteps; ++k) {
      on[k] = Painted(field, c, kTwoPi * k / kArcSteps, lo, hi);
      count += on[k];
    }
    if (count == 0) continue;
    MarkArc arc{static_cast<int>(i), c.centre_mm, c.radius_mm, 0.0, kTwoPi};
    if (count < kArcSteps) {
      // The longest run of painted steps, circularly: one arc per circle.
      int best_start = 0, best_length = 0;
      for (int k = 0; k < kArcSteps; ++k) {
        if (!on[k] || on[(k + kArcSteps - 1) % kArcSteps]) continue;
        int length = 0;
        while (length < kArcSteps && on[(k + length) % kArcSteps]) ++length;
        if (length > best_length) best_start = k, best_length = length;
      }
      arc.start_rad = kTwoPi * best_start / kArcSteps;
      arc.sweep_rad = kTwoPi * (best_length - 1) / kArcSteps;
      if (arc.sweep_rad <= 0.0) continue;
    }
    marks.arcs.push_back(arc);
  }
  return marks;
}

double DistanceToMark(const MarkSegment& s, const Vec2& p) {
  const Vec2 d = s.to_mm - s.from_mm;
  const double t = std::clamp((p - s.from_mm).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (s.from_mm + t * d - p).norm();
}

double DistanceToMark(const MarkArc& a, const Vec2& p) {
  const Vec2 r = p - a.centre_mm;
  double phi = std::atan2(r.y(), r.x()) - a.start_rad;
  phi -= kTwoPi * std::floor(phi / kTwoPi);
  if (phi <= a.sweep_rad) return std::abs(r.norm() - a.radius_mm);
  auto end = [&](double angle) -> Vec2 {
    return a.centre_mm + a.radius_mm * Vec2(std::cos(angle), std::sin(angle));
  };
  return std::min((end(a.start_rad) - p).norm(), (end(a.start_rad + a.sweep_rad) - p).norm());
}

namespace {

// Each mark's number of sample intervals at `step_mm`: segments first, then arcs.
std::vector<int> SampleCounts(const FieldMarks& marks, double step_mm) {
  std::vector<int> counts;
  counts.reserve(marks.segments.size() + marks.arcs.size());
  for (const MarkSegment& s : marks.segments)
    counts.push_back(
        std::max(1, static_cast<int>(std::ceil((s.to_mm - s.from_mm).norm() / step_mm))));
  for (const MarkArc& a : marks.arcs)
    counts.push_back(std::max(1, static_cast<int>(std::ceil(a.radius_mm * a.sweep_rad / step_mm))));
  return counts;
}

std::vector<Vec2> SamplePoints(const FieldMarks& marks, const std::vector<int>& counts,
                               std::vector<int>* mark) {
  std::vector<Vec2> out;
  if (mark != nullptr) mark->clear();
  int index = 0;
  for (const MarkSegment& s : marks.segments) {
    const int n = counts[static_cast<size_t>(index)];
    for (int k = 0; k <= n; ++k) {
      out.push_back(s.from_mm + (s.to_mm - s.from_mm) * (static_cast<double>(k) / n));
      if (mark != nullptr) mark->push_back(index);
    }
    ++index;
  }
  for (const MarkArc& a : marks.arcs) {
    const int n = counts[static_cast<size_t>(index)];
    for (int k = 0; k <= n; ++k) {
      const double phi = a.start_rad + a.sweep_rad * k / n;
      out.push_back(a.centre_mm + a.radius_mm * Vec2(std::cos(phi), std::sin(phi)));
      if (mark != nullptr) mark->push_back(index);
    }
    ++index;
  }
  return out;
}

}  // namespace

std::vector<Vec2> SampleMarks(const FieldMarks& marks, double step_mm, std::vector<int>* mark) {
  return SamplePoints(marks, SampleCounts(marks, step_mm), mark);
}

const std::vector<Vec2>& MarkSampler::Sample(double step_mm) {
  std::vector<int> counts = SampleCounts(marks_, step_mm);
  if (counts != counts_) {  // the first call too: no counts kept yet (none for no marks)
    points_ = SamplePoints(marks_, counts, nullptr);
    counts_ = std::move(counts);
  }
  return points_;
}

}  // namespace patlab::calib
