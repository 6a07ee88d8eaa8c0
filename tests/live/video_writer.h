// Short videos written with FFmpeg's libraries, for the tests of the video frame source: a
// lossless one (FFV1 in Matroska), whose frames read back pixel for pixel, and a Motion JPEG one.
#pragma once

#include <string>
#include <vector>

#include "patlab/camera/image.h"

namespace patlab::live::testing {

// Writes `frames` (RGB, one size) at `fps` frames per second; false when FFmpeg refuses.
bool WriteLosslessVideo(const std::string& path, const std::vector<camera::Image>& frames, int fps);

// The same as Motion JPEG in Matroska: each frame one JPEG (SOI ff d8 ... EOI ff d9) stored whole
// in the file, so that a test can find a frame's bytes and damage them.
bool WriteMjpegVideo(const std::string& path, const std::vector<camera::Image>& frames, int fps);

}  // namespace patlab::live::testing
