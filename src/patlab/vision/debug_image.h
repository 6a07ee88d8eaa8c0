// Debug images of the vision stages (docs/architecture.md rule 8), composed per stage by
// FrameDetector (frame_detector.h, DebugImageNames): the class image; the frame dimmed with the
// boundary of every classified pixel area in its class's display colour and each kept region's
// bounding box and centroid; the blobs as discs; detections with ID and heading.
#pragma once

#include <array>
#include <string>

#include "patlab/vision/color_lut.h"
#include "patlab/vision/image.h"
#include "patlab/vision/segment.h"

namespace patlab::vision {

// The annotated RGB image of the segmenter's last frame (`frame` must be that frame).
Image DrawRegions(const Image& frame, const Segmenter& segmenter, const Thresholds& thresholds);

// The segmenter's class image in RGB: each classified pixel in its class's display colour, the
// rest black.
Image DrawClasses(const Segmenter& segmenter, const Thresholds& thresholds);

// A filled disc of radius_px at centre_px (clipped to the image).
void DrawDisc(Image* image, const Vec2& centre_px, double radius_px,
              const std::array<uint8_t, 3>& rgb);

// A detection: a circle of radius_px at centre_px, a heading line to heading_tip_px, and the
// text (digits, '-', letters A-Z) beside it.
void DrawDetection(Image* image, const Vec2& centre_px, double radius_px,
                   const Vec2& heading_tip_px, const std::string& text,
                   const std::array<uint8_t, 3>& rgb);

void DrawLine(Image* image, const Vec2& a, const Vec2& b, const std::array<uint8_t, 3>& rgb);
void DrawText(Image* image, int x, int y, const std::string& text,
              const std::array<uint8_t, 3>& rgb, int scale = 2);

}  // namespace patlab::vision
