#include "patlab/render/render.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "patlab/core/error.h"

namespace patlab::render {

namespace {

// Blends the coverage of each disc (in paint order) over the background for one pixel.
template <typename InsideFn>
void ShadePixel(uint8_t* out, const Rgb& background, std::span<const Disc> discs, int n,
                InsideFn&& covering_disc) {
  // Accumulate the colour of each sub-sample: the last disc containing it, else the background.
  double sum[3] = {0, 0, 0};
  for (int sy = 0; sy < n; ++sy) {
    for (int sx = 0; sx < n; ++sx) {
      const int d = covering_disc((sx + 0.5) / n - 0.5, (sy + 0.5) / n - 0.5);
      const Rgb& c = d < 0 ? background : discs[static_cast<size_t>(d)].rgb;
      for (int k = 0; k < 3; ++k) sum[k] += c[k];
    }
  }
  for (int k = 0; k < 3; ++k) out[k] = static_cast<uint8_t>(std::lround(sum[k] / (n * n)));
}

// The pixels that may lie near a disc: the bounding box of each disc's outline grown by four
// pixels' worth of world distance (the test below rejects at two), sampled at 32 points and
// padded by 2 px (the chord error of 32 points is below 0.01 of the radius). Every other pixel is
// background without a single camera inversion, which is most of a field frame: the output is
// the same as testing every pixel, at a fraction of the cost. A disc whose outline does not map
// into the image cleanly (beyond the distortion fold) marks the whole image.
std::vector<uint8_t> CandidatePixels(int width_px, int height_px, const camera::CameraModel& camera,
                                     double height_mm, std::span<const Disc> discs) {
  std::vector<uint8_t> mask(static_cast<size_t>(width_px) * height_px, 0);
  constexpr int kOutline = 32;
  for (const Disc& d : discs) {
    const auto centre = camera.WorldToPixel(d.centre, height_mm);
    const double scale = centre ? std::sqrt(camera.AreaScale(*centre, height_mm)) : 0.0;
    double lo_x = 1e300, lo_y = 1e300, hi_x = -1e300, hi_y = -1e300;
    bool clean = centre.has_value() && scale > 0.0;
    for (int k = 0; clean && k < kOutline; ++k) {
      const double a = 2.0 * std::numbers::pi * k / kOutline;
      const auto p = camera.WorldToPixel(
          d.centre + (d.radius + 4.0 * scale) * Vec2(std::cos(a), std::sin(a)), height_mm);
      clean = p.has_value();
      if (!clean) break;
      lo_x = std::min(lo_x, p->x());
      hi_x = std::max(hi_x, p->x());
      lo_y = std::min(lo_y, p->y());
      hi_y = std::max(hi_y, p->y());
    }
    if (!clean) {
      std::fill(mask.begin(), mask.end(), uint8_t{1});
      return mask;
    }
    const int x0 = std::max(0, static_cast<int>(std::floor(lo_x - 2.0)));
    const int x1 = std::min(width_px - 1, static_cast<int>(std::ceil(hi_x + 2.0)));
    const int y0 = std::max(0, static_cast<int>(std::floor(lo_y - 2.0)));
    const int y1 = std::min(height_px - 1, static_cast<int>(std::ceil(hi_y + 2.0)));
    for (int y = y0; y <= y1; ++y) {
      if (x1 < x0) break;
      std::fill_n(mask.begin() + static_cast<std::ptrdiff_t>(y) * width_px + x0, x1 - x0 + 1,
                  uint8_t{1});
    }
  }
  return mask;
}

}  // namespace

camera::Image RenderDiscs(int width_px, int height_px, const Rgb& background,
                          std::span<const Disc> discs, int supersampling) {
  PATLAB_CHECK(supersampling >= 1);
  camera::Image image = camera::Image::Rgb(width_px, height_px);
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      uint8_t* out = image.Row(y) + 3 * x;
      // Discs that can touch this pixel at all.
      bool near = false;
      for (const Disc& d : discs) {
        near = near || (std::abs(d.centre.x() - x) < d.radius + 1 &&
                        std::abs(d.centre.y() - y) < d.radius + 1);
      }
      if (!near) {
        std::copy(background.begin(), background.end(), out);
        continue;
      }
      ShadePixel(out, background, discs, supersampling, [&](double dx, double dy) {
        int found = -1;
        for (size_t i = 0; i < discs.size(); ++i) {
          const double ex = x + dx - discs[i].centre.x(), ey = y + dy - discs[i].centre.y();
          if (ex * ex + ey * ey <= discs[i].radius * discs[i].radius) found = static_cast<int>(i);
        }
        return found;
      });
    }
  }
  return image;
}

camera::Image RenderWorldDiscs(int width_px, int height_px, const camera::CameraModel& camera,
                               double height_mm, const Rgb& background, std::span<const Disc> discs,
                               int supersampling) {
  PATLAB_CHECK(supersampling >= 1);
  camera::Image image = camera::Image::Rgb(width_px, height_px);
  const std::vector<uint8_t> candidate =
      CandidatePixels(width_px, height_px, camera, height_mm, discs);
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      uint8_t* out = image.Row(y) + 3 * x;
      if (candidate[static_cast<size_t>(y) * width_px + x] == 0) {
        std::copy(background.begin(), background.end(), out);
        continue;
      }
      // Cheap rejection: the pixel centre's world point and the local scale.
      const auto centre = camera.PixelToWorld(Vec2(x, y), height_mm);
      const double scale = std::sqrt(camera.AreaScale(Vec2(x, y), height_mm));
      bool near = false;
      if (centre) {
        for (const Disc& d : discs)
          near = near || (*centre - d.centre).norm() < d.radius + 2 * scale;
      }
      if (!near) {
        std::copy(background.begin(), background.end(), out);
        continue;
      }
      ShadePixel(out, background, discs, supersampling, [&](double dx, double dy) {
        const auto w = camera.PixelToWorld(Vec2(x + dx, y + dy), height_mm);
        int found = -1;
        if (!w) return found;
        for (size_t i = 0; i < discs.size(); ++i) {
          if (discs[i].Contains(*w)) found = static_cast<int>(i);
        }
        return found;
      });
    }
  }
  return image;
}

}  // namespace patlab::render
