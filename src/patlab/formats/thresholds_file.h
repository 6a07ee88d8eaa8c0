// Colour thresholds files: CMVision's colors.txt or our TOML form, read into the colour classes
// of vision/color_lut.h.
#pragma once

#include <string>
#include <string_view>

#include "patlab/vision/color_lut.h"

namespace patlab::formats {

// Loads a thresholds file: CMVision's colors.txt when its first non-comment line is [Colors] or
// [Thresholds] (in any case, as CMVision compares section names), otherwise
// our TOML form (see ParseThresholdsToml). Bad syntax or impossible values are InputErrors
// naming the file and line.
vision::Thresholds LoadThresholds(const std::string& path);

// CMVision's colors.txt, as it is:
//   [Colors]
//   (255,128,  0) 0.5000 2 Ball        <- (R,G,B) display colour, merge, expected_num, name
//   [Thresholds]
//   ( 10:200, 38:120,138:200)          <- (Ylo:Yhi, Ulo:Uhi, Vlo:Vhi), one line per colour
// Section names are matched without regard to case ([colors], [THRESHOLDS]). Blank lines and
// lines starting with '#' or ';' are ignored.
vision::Thresholds ParseCmvisionColors(std::string_view text, const std::string& name);

// Our TOML form:
//   space = "yuv"                 # or "rgb" (default "yuv")
//   [[class]]
//   name = "blue"
//   display = [0, 0, 255]         # optional debug colour
//   y = [0, 255]                  # "rgb" space: r, g, b; a missing channel means 0..255
//   u = [150, 255]
//   v = [0, 125]
//   min_area_px = 20              # optional
//   max_area_px = 200             # optional, 0 = no limit
vision::Thresholds ParseThresholdsToml(std::string_view text, const std::string& name);

}  // namespace patlab::formats
