// A short lossless video (FFV1 in Matroska) written with FFmpeg's libraries, for the tests of
// the video frame source: what is read back must be the frames written, pixel for pixel.
#pragma once

#include <string>
#include <vector>

#include "patlab/camera/image.h"

namespace patlab::live::testing {

// Writes `frames` (RGB, one size) at `fps` frames per second; false when FFmpeg refuses.
bool WriteLosslessVideo(const std::string& path, const std::vector<camera::Image>& frames, int fps);

}  // namespace patlab::live::testing
