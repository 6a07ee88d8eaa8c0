#include "patlab/render/draw.h"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace patlab::render {

namespace {

// 3x5 glyphs, one row per 3 bits (MSB = left column).
const uint8_t* Glyph(char c) {
  static const uint8_t kDigits[10][5] = {
      {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
      {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7}};
  static const uint8_t kLetters[26][5] = {
      {2, 5, 7, 5, 5}, {6, 5, 6, 5, 6}, {7, 4, 4, 4, 7}, {6, 5, 5, 5, 6}, {7, 4, 6, 4, 7},
      {7, 4, 6, 4, 4}, {7, 4, 5, 5, 7}, {5, 5, 7, 5, 5}, {7, 2, 2, 2, 7}, {1, 1, 1, 5, 7},
      {5, 5, 6, 5, 5}, {4, 4, 4, 4, 7}, {5, 7, 7, 5, 5}, {6, 5, 5, 5, 5}, {7, 5, 5, 5, 7},
      {7, 5, 7, 4, 4}, {7, 5, 5, 7, 1}, {6, 5, 6, 5, 5}, {7, 4, 7, 1, 7}, {7, 2, 2, 2, 2},
      {5, 5, 5, 5, 7}, {5, 5, 5, 5, 2}, {5, 5, 7, 7, 5}, {5, 5, 2, 5, 5}, {5, 5, 2, 2, 2},
      {7, 1, 2, 4, 7}};
  static const uint8_t kDash[5] = {0, 0, 7, 0, 0};
  static const uint8_t kQuestion[5] = {7, 1, 2, 0, 2};
  if (c >= '0' && c <= '9') return kDigits[c - '0'];
  if (std::isalpha(static_cast<unsigned char>(c)))
    return kLetters[std::toupper(static_cast<unsigned char>(c)) - 'A'];
  if (c == '-') return kDash;
  return kQuestion;
}

}  // namespace

void PutPixel(camera::Image* image, int x, int y, const std::array<uint8_t, 3>& rgb) {
  if (x < 0 || y < 0 || x >= image->width_px || y >= image->height_px) return;
  uint8_t* p = image->Row(y) + 3 * x;
  p[0] = rgb[0];
  p[1] = rgb[1];
  p[2] = rgb[2];
}

void DrawLine(camera::Image* image, const Vec2& a, const Vec2& b,
              const std::array<uint8_t, 3>& rgb) {
  const int steps = static_cast<int>(std::ceil((b - a).lpNorm<Eigen::Infinity>())) + 1;
  for (int i = 0; i <= steps; ++i) {
    const Vec2 p = a + (b - a) * (static_cast<double>(i) / steps);
    PutPixel(image, static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())),
             rgb);
  }
}

void DrawText(camera::Image* image, int x, int y, const std::string& text,
              const std::array<uint8_t, 3>& rgb, int scale) {
  for (size_t k = 0; k < text.size(); ++k) {
    if (text[k] == ' ') continue;
    const uint8_t* g = Glyph(text[k]);
    for (int row = 0; row < 5; ++row) {
      for (int col = 0; col < 3; ++col) {
        if (!(g[row] & (4 >> col))) continue;
        for (int dy = 0; dy < scale; ++dy) {
          for (int dx = 0; dx < scale; ++dx) {
            PutPixel(image, x + static_cast<int>(k) * 4 * scale + col * scale + dx,
                     y + row * scale + dy, rgb);
          }
        }
      }
    }
  }
}

void DrawDetection(camera::Image* image, const Vec2& centre_px, double radius_px,
                   const Vec2& heading_tip_px, const std::string& text,
                   const std::array<uint8_t, 3>& rgb) {
  const int n = std::max(16, static_cast<int>(radius_px * 8));
  for (int i = 0; i < n; ++i) {
    const double a0 = 2 * M_PI * i / n, a1 = 2 * M_PI * (i + 1) / n;
    DrawLine(image, centre_px + radius_px * Vec2(std::cos(a0), std::sin(a0)),
             centre_px + radius_px * Vec2(std::cos(a1), std::sin(a1)), rgb);
  }
  DrawLine(image, centre_px, heading_tip_px, rgb);
  DrawText(image, static_cast<int>(centre_px.x() + radius_px + 2),
           static_cast<int>(centre_px.y() - radius_px), text, rgb);
}

void DrawDisc(camera::Image* image, const Vec2& centre_px, double radius_px,
              const std::array<uint8_t, 3>& rgb) {
  const int x0 = static_cast<int>(std::floor(centre_px.x() - radius_px));
  const int x1 = static_cast<int>(std::ceil(centre_px.x() + radius_px));
  const int y0 = static_cast<int>(std::floor(centre_px.y() - radius_px));
  const int y1 = static_cast<int>(std::ceil(centre_px.y() + radius_px));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if ((Vec2(x, y) - centre_px).squaredNorm() <= radius_px * radius_px)
        PutPixel(image, x, y, rgb);
    }
  }
}

}  // namespace patlab::render
