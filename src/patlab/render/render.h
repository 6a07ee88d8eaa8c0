// A synthetic frame renderer for tests and benchmarks: anti-aliased discs at sub-pixel
// positions with known centroids. Each pixel's colour is the background blended with every
// disc by the fraction of the pixel the disc covers, estimated on an n x n grid of sub-samples
// (error of the coverage <= 1 / n per boundary pixel).
#pragma once

#include <array>
#include <cmath>
#include <span>

#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/core/geometry.h"

namespace patlab::render {

using Rgb = std::array<uint8_t, 3>;

struct Disc {
  Vec2 centre;          // pixel coordinates (RenderDiscs) or world mm (RenderWorldDiscs)
  double radius = 0.0;  // px or mm, like centre; for a rectangle, half its diagonal (bounds)
  Rgb rgb = {255, 255, 255};
  // RenderWorldDiscs only: a rectangle instead of a disc when half_size > 0 (half the sides
  // along its own x and y, mm), its x axis at `angle_rad` counter-clockwise from the world's x.
  Vec2 half_size = Vec2::Zero();
  double angle_rad = 0.0;

  // Whether point p (same units as centre) is inside or on the shape.
  bool Contains(const Vec2& p) const {
    const Vec2 d = p - centre;
    if (half_size.x() <= 0.0) return d.squaredNorm() <= radius * radius;
    const double c = std::cos(angle_rad), s = std::sin(angle_rad);
    return std::abs(c * d.x() + s * d.y()) <= half_size.x() &&
           std::abs(-s * d.x() + c * d.y()) <= half_size.y();
  }
};

// Discs given in pixel coordinates (pixel (i, j) centred at (i, j)); later discs cover earlier.
camera::Image RenderDiscs(int width_px, int height_px, const Rgb& background,
                          std::span<const Disc> discs, int supersampling = 8);

// Discs given in world mm on the plane at height_mm, seen through `camera`: each sub-sample is
// mapped pixel -> world and tested against the discs, so perspective and lens distortion are
// rendered exactly.
camera::Image RenderWorldDiscs(int width_px, int height_px, const camera::CameraModel& camera,
                               double height_mm, const Rgb& background, std::span<const Disc> discs,
                               int supersampling = 4);

}  // namespace patlab::render
