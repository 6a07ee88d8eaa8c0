// Field geometry as calibration targets: the named straight lines, circles (arcs) and points of a
// playing field, in field millimetres on the floor (z = 0). The shipped field models are
// experiments/fields/*.toml (docs/fields.md lists them, `patlab fields` prints them); a user's own
// field is a file of the same form:
//
//   name = "ssl-2009"
//   source = "Laws of the RoboCup Small Size League 2009-2011, law 1"
//   family = "ssl"              # optional: the model family (`patlab fields ssl`)
//   year = 2009                 # optional: the first year of these rules
//   length_mm = 6050            # optional: between the goal lines' centres
//   width_mm = 4050             # optional: between the touch lines' centres
//   boundary_mm = 250           # optional: floor beyond the lines that cameras see
//   goal_width_mm = 700         # optional: between the goal posts' inner faces
//   goal_depth_mm = 180         # optional
//   [[line]]                    # a straight line through two points (a segment's ends)
//   name = "halfway"
//   from_mm = [0, -1700]
//   to_mm = [0, 1700]
//   [[circle]]                  # a circle, or an arc with its extent
//   name = "defense_arc_left_pos"
//   centre_mm = [3025, 175]
//   radius_mm = 500
//   from_deg = 90               # optional, with to_deg: the arc runs anticlockwise from
//   to_deg = 180                # from_deg to to_deg (0 = +x); without them, the full circle
//   [[point]]                   # a marked point, e.g. a line crossing
//   name = "centre"
//   at_mm = [0, 0]
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/geometry.h"

namespace patlab::calib {

struct FieldLine {
  std::string name;
  Vec2 from_mm = Vec2::Zero();
  Vec2 to_mm = Vec2::Zero();  // != from_mm
};

struct FieldCircle {
  std::string name;
  Vec2 centre_mm = Vec2::Zero();
  double radius_mm = 0.0;  // > 0
  // The arc's angular extent, anticlockwise from from_deg to to_deg (degrees, 0 along +x,
  // from_deg < to_deg <= from_deg + 360). The defaults, 0 and 360, mean the full circle, so code
  // written for full circles reads an arc as the circle it lies on.
  double from_deg = 0.0;
  double to_deg = 360.0;

  bool IsFullCircle() const { return to_deg - from_deg >= 360.0; }
  // The point at `deg` on the circle; ArcFrom/ArcTo: the arc's two ends.
  Vec2 PointAt(double deg) const;
  Vec2 ArcFrom() const { return PointAt(from_deg); }
  Vec2 ArcTo() const { return PointAt(to_deg); }
  // Whether the direction `deg` lies on the arc (within `tolerance_deg`).
  bool Covers(double deg, double tolerance_deg = 1e-9) const;
};

struct FieldPoint {
  std::string name;
  Vec2 at_mm = Vec2::Zero();
};

struct Field {
  std::string name;
  std::string source;
  // Optional facts of a model (0, "" or nullopt when the file does not give them): its family
  // ("ssl", "vss"), the first year of its rules, the field's size between the lines' centres, the
  // floor beyond the lines, and the goal's inner width and depth, all mm.
  std::string family;
  int year = 0;
  double length_mm = 0.0, width_mm = 0.0;
  std::optional<double> boundary_mm;
  double goal_width_mm = 0.0, goal_depth_mm = 0.0;
  std::vector<FieldLine> lines;
  std::vector<FieldCircle> circles;
  std::vector<FieldPoint> points;

  const FieldLine* FindLine(std::string_view name) const;
  const FieldCircle* FindCircle(std::string_view name) const;
  const FieldPoint* FindPoint(std::string_view name) const;
  // "a, b, c" of the names of one kind, for messages.
  std::string LineNames() const;
  std::string CircleNames() const;
  std::string PointNames() const;
};

// One line of `patlab fields`: name, size, boundary, year and source.
std::string FieldSummaryLine(const Field& field);
// The model in full for `patlab fields NAME`: its facts, then its landmarks (name, x, y), lines
// (name, from, to) and arcs (name, centre, radius, extent), one a line, in mm and degrees.
std::string FieldDescriptionText(const Field& field);

}  // namespace patlab::calib
