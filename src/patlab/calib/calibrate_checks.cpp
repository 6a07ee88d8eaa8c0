// The checks of calibrate.h's UnphysicalFitReason: a fitted camera that folds its image, puts its
// principal point off the image, has a focal length no field camera has, or numbers that are not
// finite, is refused rather than written.
#include <algorithm>
#include <cmath>
#include <string>

#include "patlab/calib/calibrate.h"
#include "patlab/core/format.h"

namespace patlab::calib {

namespace {

std::string Num(double v) { return FormatSignificant(v, 3); }
std::string Px(double v) { return FormatFixed(v, 0); }

// The first camera number that is not finite, as "name = value", or "".
std::string FirstNotFinite(const CalibrationFit& fit) {
  const camera::PinholeCamera& c = fit.camera;
  const std::pair<const char*, double> numbers[] = {{"fx", c.fx_px},
                                                    {"fy", c.fy_px},
                                                    {"cx", c.cx_px},
                                                    {"cy", c.cy_px},
                                                    {"k1", c.k1},
                                                    {"k2", c.k2},
                                                    {"tx", c.translation_mm.x()},
                                                    {"ty", c.translation_mm.y()},
                                                    {"tz", c.translation_mm.z()}};
  for (const auto& [name, v] : numbers) {
    if (!std::isfinite(v)) return std::string(name) + " = " + FormatNumber(v);
  }
  if (!c.rotation.allFinite()) return "the rotation";
  return "";
}

// The first residual summary that is not finite, or "".
std::string FirstResidualNotFinite(const CalibrationFit& fit) {
  if (!std::isfinite(fit.rms_px)) return "rms_px = " + FormatNumber(fit.rms_px);
  if (!std::isfinite(fit.worst_px)) return "worst_px = " + FormatNumber(fit.worst_px);
  for (const PlaneResiduals& p : fit.planes) {
    const std::string at = " on the plane at " + FormatNumber(p.height_mm) + " mm";
    if (!std::isfinite(p.rms_px)) return "rms_px = " + FormatNumber(p.rms_px) + at;
    if (!std::isfinite(p.rms_mm)) return "rms_mm = " + FormatNumber(p.rms_mm) + at;
  }
  return "";
}

// r (1 + k1 r^2 + k2 r^4) at r.
double Distorted(double r, double k1, double k2) {
  const double r2 = r * r;
  return r * (1.0 + k1 * r2 + k2 * r2 * r2);
}

}  // namespace

std::optional<double> DistortionFoldRadius(double k1, double k2) {
  // The derivative is 1 + 3 k1 u + 5 k2 u^2 with u = r^2 >= 0; its smallest positive root.
  double u = std::numeric_limits<double>::infinity();
  const double a = 5.0 * k2, b = 3.0 * k1;
  if (a == 0.0) {
    if (b < 0.0) u = -1.0 / b;
  } else {
    const double disc = b * b - 4.0 * a;
    if (disc >= 0.0) {
      const double sq = std::sqrt(disc);
      // Both roots, the cancellation-free way (Numerical Recipes 5.6).
      const double q = -0.5 * (b + (b >= 0.0 ? sq : -sq));
      for (const double root : {q / a, q != 0.0 ? 1.0 / q : 0.0}) {
        if (root > 0.0) u = std::min(u, root);
      }
    }
  }
  if (!std::isfinite(u)) return std::nullopt;
  return Distorted(std::sqrt(u), k1, k2);
}

std::string UnphysicalFitReason(const CalibrationFit& fit, int image_width_px,
                                int image_height_px) {
  const std::string not_finite = FirstNotFinite(fit);
  if (!not_finite.empty()) {
    return "the fitted camera is not usable: " + not_finite +
           " is not a finite number; expected observations a pinhole camera explains (check for "
           "mis-clicked pixels, or hold k1 and k2 with [fit] fix)";
  }
  const camera::PinholeCamera& c = fit.camera;
  const double w = image_width_px, h = image_height_px;
  // The largest normalised radius of the image: its farthest corner from the principal point.
  double image_r = 0.0;
  for (const double x : {0.0, w}) {
    for (const double y : {0.0, h}) {
      image_r = std::max(image_r, std::hypot((x - c.cx_px) / c.fx_px, (y - c.cy_px) / c.fy_px));
    }
  }
  if (const std::optional<double> fold = DistortionFoldRadius(c.k1, c.k2);
      fold && *fold < image_r) {
    return "the fitted camera is not usable: its distortion folds at r = " + Num(*fold) +
           " (radius " + Px(*fold * c.fx_px) + " px) inside the image's " + Num(image_r) +
           ": k1 = " + Num(c.k1) + ", k2 = " + Num(c.k2) +
           "; expected a lens that shows every pixel once (observe lines and points near the image "
           "edge, or hold k1 and k2 with [fit] fix = [\"k1\", \"k2\", ...])";
  }
  if (!(c.cx_px >= 0.0 && c.cx_px <= w && c.cy_px >= 0.0 && c.cy_px <= h)) {
    return "the fitted camera is not usable: its principal point (" + FormatFixed(c.cx_px, 1) +
           ", " + FormatFixed(c.cy_px, 1) + ") px lies outside the " + FormatNumber(w) + " x " +
           FormatNumber(h) +
           " px image; expected it inside the image (a lens's axis meets its sensor; hold it with "
           "[fit] fix = [\"principal_point\", ...])";
  }
  if (!(c.fx_px >= kMinFocalWidths * w && c.fx_px <= kMaxFocalWidths * w)) {
    return "the fitted camera is not usable: its focal length " + Px(c.fx_px) + " px is " +
           Num(c.fx_px / w) + " image widths; expected " + Num(kMinFocalWidths) + " to " +
           Num(kMaxFocalWidths) +
           " (a field of view between 136 and 2.9 degrees: a camera over a field sees more than a "
           "robot and less than a half sphere); give [fit] focal_px or camera_height_mm";
  }
  const double aspect = c.fy_px / c.fx_px;
  if (!(aspect >= 1.0 / kMaxAspect && aspect <= kMaxAspect)) {
    return "the fitted camera is not usable: its pixel aspect fy / fx = " + Num(aspect) + " (fx " +
           Px(c.fx_px) + " px, fy " + Px(c.fy_px) + " px); expected " + Num(1.0 / kMaxAspect) +
           " to " + Num(kMaxAspect) +
           " (sensor pixels are nearly square; hold it with [fit] fix = [\"aspect\", ...])";
  }
  const std::string residual = FirstResidualNotFinite(fit);
  if (!residual.empty()) {
    return "the fitted camera is not usable: " + residual +
           " is not a finite number (an observed pixel the camera cannot project or map back); "
           "expected observations a pinhole camera explains (check for mis-clicked pixels)";
  }
  return "";
}

}  // namespace patlab::calib
