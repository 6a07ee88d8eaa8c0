// Field lines through a camera (field_render.h).
#include "patlab/render/field_render.h"

#include <algorithm>
#include <cmath>

#include "patlab/calib/field_marks.h"
#include "patlab/core/error.h"

namespace patlab::render {

camera::Image RenderFieldLines(const calib::Field& field, const camera::CameraModel& camera,
                               int width_px, int height_px, const FieldLineStyle& style) {
  if (!camera.is_pinhole()) {
    throw InputError(
        "camera: a homography camera cannot render field lines; expected a pinhole "
        "camera");
  }
  if (!(style.line_width_mm > 0.0) || style.supersample < 1 || style.supersample > 8 ||
      width_px <= 0 || height_px <= 0) {
    throw InputError(
        "field line style: line_width_mm must be > 0, supersample in [1, 8] and the "
        "image size positive");
  }
  const calib::FieldMarks marks = calib::PaintedMarks(field);
  const double half = 0.5 * style.line_width_mm;
  auto on_line = [&](const Vec2& q) {
    for (const auto& s : marks.segments)
      if (calib::DistanceToMark(s, q) <= half) return true;
    for (const auto& a : marks.arcs)
      if (calib::DistanceToMark(a, q) <= half) return true;
    return false;
  };
  camera::Image image = camera::Image::Rgb(width_px, height_px);
  const int n = style.supersample;
  for (int y = 0; y < height_px; ++y) {
    uint8_t* row = image.Row(y);
    for (int x = 0; x < width_px; ++x) {
      int line = 0, carpet = 0, outside = 0;
      for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
          const Vec2 p(x - 0.5 + (i + 0.5) / n, y - 0.5 + (j + 0.5) / n);
          const auto q = camera.PixelToWorld(p, 0.0);
          if (!q) {
            ++outside;
          } else if (on_line(*q)) {
            ++line;
          } else {
            ++carpet;
          }
        }
      }
      for (int c = 0; c < 3; ++c) {
        const double v =
            (line * style.line[c] + carpet * style.carpet[c] + outside * style.outside[c]) /
            static_cast<double>(n * n);
        row[3 * x + c] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 255.0)));
      }
    }
  }
  return image;
}

}  // namespace patlab::render
