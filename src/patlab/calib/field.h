// Field geometry as calibration targets: the named straight lines, circles (arcs) and points of a
// playing field, in field millimetres on the floor (z = 0). The shipped fields are
// experiments/fields/*.toml (docs/calibrate.md lists them); a user's own field is a file of the
// same form:
//
//   name = "ssl-2008"
//   source = "RoboCup SSL rules 2008, law 1"
//   [[line]]                    # a straight line through two points (a segment's ends)
//   name = "halfway"
//   from_mm = [0, -1700]
//   to_mm = [0, 1700]
//   [[circle]]                  # a circle or the circle an arc lies on
//   name = "centre_circle"
//   centre_mm = [0, 0]
//   radius_mm = 500
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
};

struct FieldPoint {
  std::string name;
  Vec2 at_mm = Vec2::Zero();
};

struct Field {
  std::string name;
  std::string source;
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

}  // namespace patlab::calib
