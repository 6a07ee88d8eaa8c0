// A synthetic frame renderer for tests and benchmarks: anti-aliased discs at sub-pixel
// positions with known centroids. Each pixel's colour is the background blended with every
// disc by the fraction of the pixel the disc covers, estimated on an n x n grid of sub-samples
// (error of the coverage <= 1 / n per boundary pixel).
#pragma once

#include <array>
#include <span>

#include "patlab/core/geometry.h"
#include "patlab/vision/camera.h"
#include "patlab/vision/image.h"

namespace patlab::vision {

using Rgb = std::array<uint8_t, 3>;

struct Disc {
  Vec2 centre;          // pixel coordinates (RenderDiscs) or world mm (RenderWorldDiscs)
  double radius = 0.0;  // px or mm, like centre
  Rgb rgb = {255, 255, 255};
};

// Discs given in pixel coordinates (pixel (i, j) centred at (i, j)); later discs cover earlier.
Image RenderDiscs(int width_px, int height_px, const Rgb& background, std::span<const Disc> discs,
                  int supersampling = 8);

// Discs given in world mm on the plane at height_mm, seen through `camera`: each sub-sample is
// mapped pixel -> world and tested against the discs, so perspective and lens distortion are
// rendered exactly.
Image RenderWorldDiscs(int width_px, int height_px, const CameraModel& camera, double height_mm,
                       const Rgb& background, std::span<const Disc> discs, int supersampling = 4);

}  // namespace patlab::vision
