#include "patlab/vision/debug_image.h"

#include "patlab/render/draw.h"

namespace patlab::vision {

camera::Image DrawClasses(const Segmenter& segmenter, const Thresholds& thresholds) {
  camera::Image out = camera::Image::Rgb(segmenter.width_px(), segmenter.height_px());
  const std::vector<uint8_t>& cls = segmenter.class_image();
  for (int y = 0; y < out.height_px; ++y) {
    for (int x = 0; x < out.width_px; ++x) {
      const uint8_t c = cls[static_cast<size_t>(y) * out.width_px + x];
      if (c != 0) render::PutPixel(&out, x, y, thresholds.classes[c - 1].display_rgb);
    }
  }
  return out;
}

camera::Image DrawRegions(const camera::ImageView& frame, const Segmenter& segmenter,
                          const Thresholds& thresholds) {
  camera::Image out = camera::ToRgb(frame);
  for (uint8_t& v : out.data) v = static_cast<uint8_t>(v / 3);  // dim, so the marks stand out
  const int w = segmenter.width_px(), h = segmenter.height_px();
  const std::vector<uint8_t>& cls = segmenter.class_image();
  // Class boundaries: classified pixels with a 4-neighbour of another class.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint8_t c = cls[static_cast<size_t>(y) * w + x];
      if (c == 0) continue;
      const bool edge = x == 0 || y == 0 || x == w - 1 || y == h - 1 ||
                        cls[static_cast<size_t>(y) * w + x - 1] != c ||
                        cls[static_cast<size_t>(y) * w + x + 1] != c ||
                        cls[static_cast<size_t>(y - 1) * w + x] != c ||
                        cls[static_cast<size_t>(y + 1) * w + x] != c;
      if (edge) render::PutPixel(&out, x, y, thresholds.classes[c - 1].display_rgb);
    }
  }
  // Kept regions: bounding box and centroid cross in the class colour.
  for (const Region& r : segmenter.regions()) {
    const auto& rgb = thresholds.classes[static_cast<size_t>(r.colour)].display_rgb;
    const Vec2 a(r.x_min - 1, r.y_min - 1), b(r.x_max + 1, r.y_max + 1);
    render::DrawLine(&out, a, Vec2(b.x(), a.y()), rgb);
    render::DrawLine(&out, Vec2(b.x(), a.y()), b, rgb);
    render::DrawLine(&out, b, Vec2(a.x(), b.y()), rgb);
    render::DrawLine(&out, Vec2(a.x(), b.y()), a, rgb);
    const Vec2 c = r.centroid_px;
    render::DrawLine(&out, c - Vec2(2, 0), c + Vec2(2, 0), {255, 255, 255});
    render::DrawLine(&out, c - Vec2(0, 2), c + Vec2(0, 2), {255, 255, 255});
  }
  return out;
}

}  // namespace patlab::vision
