// Drawing into RGB frames: pixels, lines, filled discs, a detection's circle with heading and
// label, and text in a 3x5 bitmap font (digits, '-', letters A-Z; anything else draws '?'). The
// vision stages' debug images (vision/debug_image.h, FrameDetector) are drawn with these.
// Everything is clipped to the image.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "patlab/camera/image.h"
#include "patlab/core/geometry.h"

namespace patlab::render {

// Sets pixel (x, y) of an RGB image to `rgb`; outside the image: nothing.
void PutPixel(camera::Image* image, int x, int y, const std::array<uint8_t, 3>& rgb);

// A filled disc of radius_px at centre_px (clipped to the image).
void DrawDisc(camera::Image* image, const Vec2& centre_px, double radius_px,
              const std::array<uint8_t, 3>& rgb);

// A detection: a circle of radius_px at centre_px, a heading line to heading_tip_px, and the
// text (digits, '-', letters A-Z) beside it.
void DrawDetection(camera::Image* image, const Vec2& centre_px, double radius_px,
                   const Vec2& heading_tip_px, const std::string& text,
                   const std::array<uint8_t, 3>& rgb);

void DrawLine(camera::Image* image, const Vec2& a, const Vec2& b,
              const std::array<uint8_t, 3>& rgb);
// `text` from its top-left corner (x, y), each glyph 3 x 5 cells of scale x scale pixels, one
// blank column between glyphs.
void DrawText(camera::Image* image, int x, int y, const std::string& text,
              const std::array<uint8_t, 3>& rgb, int scale = 2);

}  // namespace patlab::render
