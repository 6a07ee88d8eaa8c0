#include "patlab/core/pattern.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace patlab {

double Patch::Area() const {
  if (shape == PatchShape::kRectangle) return size_mm.x() * size_mm.y();
  return std::numbers::pi * radius_mm * radius_mm;
}

double Patch::BoundingRadius() const {
  if (shape == PatchShape::kRectangle) return 0.5 * size_mm.norm();
  return radius_mm;
}

namespace {

Vec2 AxisX(const Patch& p) { return {std::cos(p.angle_rad), std::sin(p.angle_rad)}; }
Vec2 AxisY(const Patch& p) { return {-std::sin(p.angle_rad), std::cos(p.angle_rad)}; }

// Half the extent of patch p projected on unit axis u.
double HalfExtent(const Patch& p, const Vec2& u) {
  if (p.shape == PatchShape::kDisc) return p.radius_mm;
  return 0.5 *
         (p.size_mm.x() * std::abs(AxisX(p).dot(u)) + p.size_mm.y() * std::abs(AxisY(p).dot(u)));
}

// The point of rectangle r nearest to q.
Vec2 NearestOnRectangle(const Patch& r, const Vec2& q) {
  const Vec2 d = q - r.position_mm;
  const double lx = std::clamp(d.dot(AxisX(r)), -0.5 * r.size_mm.x(), 0.5 * r.size_mm.x());
  const double ly = std::clamp(d.dot(AxisY(r)), -0.5 * r.size_mm.y(), 0.5 * r.size_mm.y());
  return r.position_mm + lx * AxisX(r) + ly * AxisY(r);
}

}  // namespace

bool Patch::Contains(const Vec2& q) const {
  if (shape == PatchShape::kDisc) return (q - position_mm).squaredNorm() <= radius_mm * radius_mm;
  const Vec2 d = q - position_mm;
  return std::abs(d.dot(AxisX(*this))) <= 0.5 * size_mm.x() &&
         std::abs(d.dot(AxisY(*this))) <= 0.5 * size_mm.y();
}

Patch RectanglePatch(const Vec2& centre, const Vec2& size_mm, double angle_rad, PatchRole role,
                     std::string colour) {
  Patch p;
  p.position_mm = centre;
  p.shape = PatchShape::kRectangle;
  p.size_mm = size_mm;
  p.angle_rad = angle_rad;
  p.radius_mm = std::sqrt(size_mm.x() * size_mm.y() / std::numbers::pi);
  p.role = role;
  p.colour = std::move(colour);
  return p;
}

double PatchGap(const Patch& a, const Patch& b) {
  const Vec2 d = b.position_mm - a.position_mm;
  if (a.shape == PatchShape::kDisc && b.shape == PatchShape::kDisc) {
    return d.norm() - a.radius_mm - b.radius_mm;
  }
  if (a.shape == PatchShape::kDisc) return PatchGap(b, a);
  // a is a rectangle. A disc b: its distance to the rectangle, exact when b's centre is outside.
  if (b.shape == PatchShape::kDisc) {
    const Vec2 nearest = NearestOnRectangle(a, b.position_mm);
    const double outside = (b.position_mm - nearest).norm();
    if (outside > 0.0) return outside - b.radius_mm;
  }
  // Separating axes: the axes of both rectangles (a disc adds none: its centre is inside a).
  std::array<Vec2, 4> axes = {AxisX(a), AxisY(a), AxisX(b), AxisY(b)};
  const size_t count = b.shape == PatchShape::kRectangle ? 4 : 2;
  double gap = -std::numeric_limits<double>::infinity();
  for (size_t k = 0; k < count; ++k) {
    gap = std::max(gap, std::abs(d.dot(axes[k])) - HalfExtent(a, axes[k]) - HalfExtent(b, axes[k]));
  }
  if (gap > 0.0 && b.shape == PatchShape::kRectangle) {
    // Apart along some axis; the exact distance between two disjoint convex polygons is the least
    // distance from a corner of one to the other.
    double best = std::numeric_limits<double>::infinity();
    for (const Patch* p : {&a, &b}) {
      const Patch& other = p == &a ? b : a;
      for (const double sx : {-0.5, 0.5}) {
        for (const double sy : {-0.5, 0.5}) {
          const Vec2 corner =
              p->position_mm + sx * p->size_mm.x() * AxisX(*p) + sy * p->size_mm.y() * AxisY(*p);
          best = std::min(best, (corner - NearestOnRectangle(other, corner)).norm());
        }
      }
    }
    return best;
  }
  return gap;
}

Vec2 Pattern::Centroid() const {
  Vec2 sum = Vec2::Zero();
  for (const Patch& p : patches) sum += p.position_mm;
  return sum / static_cast<double>(patches.size());
}

double Pattern::Spread() const {
  const Vec2 c = Centroid();
  double s = 0.0;
  for (const Patch& p : patches) s += (p.position_mm - c).squaredNorm();
  return s;
}

std::vector<OrientationPair> DefaultOrientationPairs(const std::vector<Patch>& patches,
                                                     int key_index) {
  std::vector<int> others;
  for (int i = 0; i < static_cast<int>(patches.size()); ++i) {
    if (i != key_index) others.push_back(i);
  }
  std::vector<OrientationPair> pairs;
  if (others.size() == 1) {
    pairs.push_back({key_index, others[0]});
    return pairs;
  }
  for (size_t a = 0; a < others.size(); ++a) {
    for (size_t b = a + 1; b < others.size(); ++b) pairs.push_back({others[a], others[b]});
  }
  return pairs;
}

}  // namespace patlab
