// Debug images of the vision stages (docs/architecture.md rule 8), composed per stage by
// FrameDetector (frame_detector.h, DebugImageNames): the class image; the frame dimmed with the
// boundary of every classified pixel area in its class's display colour and each kept region's
// bounding box and centroid; the blobs as discs; detections with ID and heading (the last two
// drawn with render/draw.h).
#pragma once

#include "patlab/camera/image.h"
#include "patlab/vision/color_lut.h"
#include "patlab/vision/segment.h"

namespace patlab::vision {

// The annotated RGB image of the segmenter's last frame (`frame` must be that frame).
camera::Image DrawRegions(const camera::ImageView& frame, const Segmenter& segmenter,
                          const Thresholds& thresholds);

// The segmenter's class image in RGB: each classified pixel in its class's display colour, the
// rest black.
camera::Image DrawClasses(const Segmenter& segmenter, const Thresholds& thresholds);

}  // namespace patlab::vision
