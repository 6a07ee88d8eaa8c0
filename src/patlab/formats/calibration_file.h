// Camera calibration files: the camera model of camera/camera.h (pinhole with radial distortion,
// or one homography per plane height), the plane height of each colour class and the recorded
// residuals, as patlab calibrate writes them.
#pragma once

#include <string>
#include <string_view>

#include "patlab/camera/camera.h"

namespace patlab::formats {

// Reads a calibration TOML file:
//   model = "pinhole"                 # or "homography"
//   image_size_px = [780, 580]        # optional
//   [pinhole]
//   fx_px = 520.0
//   fy_px = 520.0
//   cx_px = 390.0
//   cy_px = 290.0
//   k1 = -0.2                         # optional, default 0
//   k2 = 0.0                          # optional, default 0
//   # extrinsics, either OpenCV's (world -> camera):
//   rotation_rodrigues = [3.14159, 0, 0]
//   translation_mm = [0, 0, 4000]
//   # or a camera looking straight down from camera_position_mm, image right = world x
//   # rotated by yaw_deg counter-clockwise:
//   camera_position_mm = [0, 0, 4000]
//   yaw_deg = 0
//   [[homography]]                    # model = "homography": one table per plane height
//   height_mm = 140
//   matrix = [[1, 0, -400], [0, -1, 400], [0, 0, 1]]   # (u, v, 1) -> (x, y, w) mm
//   [heights]
//   default_mm = 140                  # plane height of every class not listed (default 0)
//   orange = 21                       # class name = plane height in mm
//   [[residual]]                      # optional, written by patlab calibrate; one per height
//   height_mm = 140
//   rms_mm = 9.3                      # the calibration's RMS position error on that plane
//   worst_mm = 41.0
//   measured = false                  # optional (default true): converted from px residuals
camera::Calibration LoadCalibration(const std::string& path);
camera::Calibration ParseCalibration(std::string_view text, const std::string& name);

}  // namespace patlab::formats
