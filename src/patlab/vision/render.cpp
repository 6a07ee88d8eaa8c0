#include "patlab/vision/render.h"

#include <algorithm>
#include <cmath>

#include "patlab/core/error.h"

namespace patlab::vision {

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

}  // namespace

Image RenderDiscs(int width_px, int height_px, const Rgb& background, std::span<const Disc> discs,
                  int supersampling) {
  PATLAB_CHECK(supersampling >= 1);
  Image image = Image::Rgb(width_px, height_px);
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

Image RenderWorldDiscs(int width_px, int height_px, const CameraModel& camera, double height_mm,
                       const Rgb& background, std::span<const Disc> discs, int supersampling) {
  PATLAB_CHECK(supersampling >= 1);
  Image image = Image::Rgb(width_px, height_px);
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      uint8_t* out = image.Row(y) + 3 * x;
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
          if ((*w - discs[i].centre).squaredNorm() <= discs[i].radius * discs[i].radius) {
            found = static_cast<int>(i);
          }
        }
        return found;
      });
    }
  }
  return image;
}

}  // namespace patlab::vision
