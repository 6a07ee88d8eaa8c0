#include "patlab/calib/field.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "patlab/core/format.h"
#include "patlab/core/portable_math.h"

namespace patlab::calib {

namespace {

template <typename T>
const T* FindByName(const std::vector<T>& items, std::string_view name) {
  const auto it =
      std::find_if(items.begin(), items.end(), [&](const T& t) { return t.name == name; });
  return it == items.end() ? nullptr : &*it;
}

template <typename T>
std::string JoinNames(const std::vector<T>& items) {
  std::string out;
  for (const T& t : items) out += (out.empty() ? "" : ", ") + t.name;
  return out.empty() ? "(none)" : out;
}

}  // namespace

const FieldLine* Field::FindLine(std::string_view n) const { return FindByName(lines, n); }
const FieldCircle* Field::FindCircle(std::string_view n) const { return FindByName(circles, n); }
const FieldPoint* Field::FindPoint(std::string_view n) const { return FindByName(points, n); }
std::string Field::LineNames() const { return JoinNames(lines); }
std::string Field::CircleNames() const { return JoinNames(circles); }
std::string Field::PointNames() const { return JoinNames(points); }

Vec2 FieldCircle::PointAt(double deg) const {
  double s = 0.0, c = 0.0;
  pmath::SinCos(deg * std::numbers::pi / 180.0, &s, &c);
  return centre_mm + radius_mm * Vec2(c, s);
}

bool FieldCircle::Covers(double deg, double tolerance_deg) const {
  if (IsFullCircle()) return true;
  // The direction's angle after from_deg, in [0, 360).
  double after = std::fmod(deg - from_deg, 360.0);
  if (after < 0.0) after += 360.0;
  const double span = to_deg - from_deg;
  return after <= span + tolerance_deg || after >= 360.0 - tolerance_deg;
}

namespace {

std::string Mm(double v) { return FormatNumber(v); }
std::string Pair(const Vec2& p) { return Mm(p.x()) + " " + Mm(p.y()); }

std::string PadRight(std::string s, size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

}  // namespace

std::string FieldSummaryLine(const Field& f) {
  std::string size = f.length_mm > 0.0 && f.width_mm > 0.0
                         ? Mm(f.length_mm) + " x " + Mm(f.width_mm) + " mm"
                         : "size not given";
  if (f.boundary_mm) size += ", boundary " + Mm(*f.boundary_mm) + " mm";
  return PadRight(f.name, 16) + " " + PadRight(size, 34) + " " +
         (f.year > 0 ? std::to_string(f.year) : std::string("-")) + "  " + f.source;
}

std::string FieldDescriptionText(const Field& f) {
  std::string out = "field " + f.name + (f.family.empty() ? "" : " (family " + f.family + ")") +
                    "\nsource: " + f.source + "\n";
  if (f.year > 0) out += "year: " + std::to_string(f.year) + "\n";
  if (f.length_mm > 0.0) out += "length_mm: " + Mm(f.length_mm) + "\n";
  if (f.width_mm > 0.0) out += "width_mm: " + Mm(f.width_mm) + "\n";
  if (f.boundary_mm) out += "boundary_mm: " + Mm(*f.boundary_mm) + "\n";
  if (f.goal_width_mm > 0.0) out += "goal_width_mm: " + Mm(f.goal_width_mm) + "\n";
  if (f.goal_depth_mm > 0.0) out += "goal_depth_mm: " + Mm(f.goal_depth_mm) + "\n";
  out += "\nlandmarks (name x_mm y_mm):\n";
  for (const FieldPoint& p : f.points) {
    out += "  " + PadRight(p.name, 28) + " " + Pair(p.at_mm) + "\n";
  }
  out += "\nlines (name from_x from_y to_x to_y, mm):\n";
  for (const FieldLine& l : f.lines) {
    out += "  " + PadRight(l.name, 28) + " " + Pair(l.from_mm) + "  " + Pair(l.to_mm) + "\n";
  }
  out += "\narcs (name centre_x centre_y radius, mm; from_deg to_deg):\n";
  for (const FieldCircle& c : f.circles) {
    out += "  " + PadRight(c.name, 28) + " " + Pair(c.centre_mm) + " " + Mm(c.radius_mm) + "  " +
           Mm(c.from_deg) + " " + Mm(c.to_deg) + (c.IsFullCircle() ? " (full circle)" : "") + "\n";
  }
  return out;
}

}  // namespace patlab::calib
