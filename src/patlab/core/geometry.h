// Plane geometry shared by every module: points in mm (Eigen fixed-size), 2-D poses, angles.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <numbers>

#include "patlab/core/portable_math.h"

namespace patlab {

using Vec2 = Eigen::Vector2d;

// A rigid pose in the plane: the model origin at (x_mm, y_mm), model x axis at theta_rad from
// the world x axis (counter-clockwise). Maps model point p to world R(theta) p + t.
struct Pose2 {
  double x_mm = 0.0;
  double y_mm = 0.0;
  double theta_rad = 0.0;

  Vec2 Apply(const Vec2& model_point) const {
    double s, c;
    pmath::SinCos(theta_rad, &s, &c);
    return {x_mm + c * model_point.x() - s * model_point.y(),
            y_mm + s * model_point.x() + c * model_point.y()};
  }
};

// Wraps an angle to (-pi, pi], exactly, for any finite angle (pmath::WrapAngle).
inline double WrapAngle(double angle_rad) { return pmath::WrapAngle(angle_rad); }

}  // namespace patlab
