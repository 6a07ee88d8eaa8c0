// The white field lines of a frame, and the automatic field calibration of a frame.
//
// FindLinePixels: the centre points of thin bright ridges that are white on the carpet: a
// pixel is a candidate when its (Gaussian-smoothed) luminance exceeds the local carpet's (the
// mean over a window about it) by min_contrast and its chroma is low; the ridge itself is found
// with the Hessian of the smoothed luminance (Steger 1998, "An unbiased detector of curvilinear
// structures"): the eigenvector of its most negative eigenvalue is the normal across the line,
// and the second-order Taylor expansion along it puts the centre with sub-pixel accuracy; a
// pixel is kept when that centre lies within it. Each point carries the line's direction.
//
// AutoCalibrateFrame: FindLinePixels, then calib::AutoCalibrate (calib/auto_calibrate.h).
#pragma once

#include <string>
#include <vector>

#include "patlab/calib/auto_calibrate.h"
#include "patlab/calib/field.h"
#include "patlab/camera/image.h"

namespace patlab::vision {

struct LineFinderOptions {
  double line_width_px = 4.0;     // the lines' expected width in the image, in [1, 30]
  double min_contrast = 20.0;     // luminance above the local carpet (8-bit levels), in (0, 255]
  double max_chroma = 60.0;       // |U - 128| + |V - 128| of a line pixel, in (0, 255]
  int background_window_px = 31;  // odd, in [5, 255]: the local carpet's window
};

// The line-centre points of `frame` (RGB or UYVY), in row order. Bad options -> InputError.
std::vector<calib::LinePixel> FindLinePixels(const camera::Image& frame,
                                             const LineFinderOptions& options = {});

// `frame` dimmed, each line pixel a red dot; with `fit` (may be null), the field's marks drawn
// through the fitted camera in cyan.
camera::Image DrawLinePixels(const camera::Image& frame,
                             const std::vector<calib::LinePixel>& pixels,
                             const calib::Field* field = nullptr,
                             const calib::AutoCalibration* fit = nullptr);

// FindLinePixels and calib::AutoCalibrate; InputError when the lines do not decide the camera.
struct FrameCalibration {
  std::vector<calib::LinePixel> pixels;
  calib::AutoCalibration calibration;
  double find_seconds = 0.0;
};
FrameCalibration AutoCalibrateFrame(const camera::Image& frame, const std::string& source,
                                    const calib::Field& field, const LineFinderOptions& finder = {},
                                    const calib::AutoOptions& options = {});

}  // namespace patlab::vision
