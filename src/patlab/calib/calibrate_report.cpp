// Residuals of a camera fit and the files and text it produces (calibrate.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "patlab/calib/calibrate.h"
#include "patlab/calib/calibrate_internal.h"
#include "patlab/core/format.h"

namespace patlab::calib {

namespace internal {

namespace {

// Adds one pixel's residual: reprojection of the fitted target, and the observed pixel
// back-projected onto the target's plane measured by `distance_mm` (NaN when it misses it).
template <typename Distance>
void AddResidual(const camera::CameraModel& cam, ObservationResidual r, const Vec2& pixel,
                 const Vec2& target, Distance distance_mm, CalibrationFit& fit) {
  const auto projected = cam.WorldToPixel(target, r.height_mm);
  r.pixel = pixel;
  r.px = projected ? (*projected - pixel).norm() : std::numeric_limits<double>::infinity();
  const auto back = cam.PixelToWorld(pixel, r.height_mm);
  r.mm = back ? distance_mm(*back) : std::numeric_limits<double>::quiet_NaN();
  fit.residuals.push_back(r);
}

void Summarise(CalibrationFit& fit) {
  std::map<double, PlaneResiduals> planes;
  double sum_px2 = 0.0;
  for (const ObservationResidual& r : fit.residuals) {
    PlaneResiduals& p = planes[r.height_mm];
    p.height_mm = r.height_mm;
    ++p.count;
    p.rms_px += r.px * r.px;
    p.worst_px = std::max(p.worst_px, r.px);
    p.rms_mm += r.mm * r.mm;  // NaN (a pixel whose ray misses the plane) stays visible
    p.worst_mm = std::max(p.worst_mm, r.mm);
    sum_px2 += r.px * r.px;
    fit.worst_px = std::max(fit.worst_px, r.px);
  }
  for (auto& [h, p] : planes) {
    p.rms_px = std::sqrt(p.rms_px / p.count);
    p.rms_mm = std::sqrt(p.rms_mm / p.count);
    fit.planes.push_back(p);
  }
  fit.rms_px = std::sqrt(sum_px2 / static_cast<double>(std::max<size_t>(1, fit.residuals.size())));
}

// The [[residual]] rows of the calibration file (CalibrationFit::file_residuals).
void FileResiduals(const CalibrationInput& in, const camera::CameraModel& cam,
                   CalibrationFit& fit) {
  std::vector<double> heights = {in.default_height_mm};
  for (const auto& [name, h] : in.class_height_mm) heights.push_back(h);
  for (const PlaneResiduals& p : fit.planes) heights.push_back(p.height_mm);
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end(),
                            [](double a, double b) { return std::abs(a - b) <= 0.5; }),
                heights.end());
  for (const double h : heights) {
    camera::PlaneResidual row;
    row.height_mm = h;
    const auto plane = std::find_if(fit.planes.begin(), fit.planes.end(), [&](const auto& p) {
      return std::abs(p.height_mm - h) <= 0.5;
    });
    if (plane != fit.planes.end() && std::isfinite(plane->rms_mm)) {
      row.rms_mm = plane->rms_mm;
      row.worst_mm = plane->worst_mm;
    } else {
      // No observation on this plane: a pixel's error at its place, in mm of this plane.
      row.measured = false;
      double sum2 = 0.0;
      for (const ObservationResidual& r : fit.residuals) {
        const double mm = r.px * std::sqrt(cam.AreaScale(r.pixel, h));
        sum2 += mm * mm;
        row.worst_mm = std::max(row.worst_mm, mm);
      }
      row.rms_mm = std::sqrt(sum2 / static_cast<double>(std::max<size_t>(1, fit.residuals.size())));
    }
    fit.file_residuals.push_back(row);
  }
}

}  // namespace

void FillResiduals(const CalibrationInput& in, const FitState& s, CalibrationFit& fit) {
  const camera::CameraModel cam = camera::CameraModel::Pinhole(CameraOf(s));
  for (const PointObservation& p : in.points) {
    AddResidual(
        cam, {"point", p.name, 0, p.loc, p.height_mm}, p.pixel, p.world_mm,
        [&](const Vec2& q) { return (q - p.world_mm).norm(); }, fit);
  }
  for (size_t i = 0; i < in.lines.size(); ++i) {
    const LineObservation& l = in.lines[i];
    const Vec2 u = (l.to_mm - l.from_mm).normalized();
    auto distance = [&](const Vec2& q) {
      const Vec2 d = q - l.from_mm;
      return std::abs(d.x() * u.y() - d.y() * u.x());
    };
    for (size_t j = 0; j < l.pixels.size(); ++j) {
      AddResidual(cam, {"line", l.name, static_cast<int>(j), l.loc, l.height_mm}, l.pixels[j],
                  LineTarget(l, s.line_t[i][j]), distance, fit);
    }
  }
  for (size_t i = 0; i < in.circles.size(); ++i) {
    const CircleObservation& c = in.circles[i];
    auto distance = [&](const Vec2& q) { return std::abs((q - c.centre_mm).norm() - c.radius_mm); };
    for (size_t j = 0; j < c.pixels.size(); ++j) {
      AddResidual(cam, {"circle", c.name, static_cast<int>(j), c.loc, c.height_mm}, c.pixels[j],
                  CircleTarget(c, s.circle_phi[i][j]), distance, fit);
    }
  }
  for (size_t i = 0; i < in.patterns.size(); ++i) {
    const PatternObservation& p = in.patterns[i];
    for (size_t j = 0; j < p.pixels.size(); ++j) {
      if (!p.pixels[j]) continue;
      const Vec2 target = PatternTarget(p, s.pattern_pose[i], static_cast<int>(j));
      AddResidual(
          cam, {"pattern", p.name, static_cast<int>(j), p.loc, p.height_mm}, *p.pixels[j], target,
          [&](const Vec2& q) { return (q - target).norm(); }, fit);
    }
  }
  Summarise(fit);
  FileResiduals(in, cam, fit);
}

double TiltDeg(const camera::PinholeCamera& c) {
  const Eigen::Vector3d axis_world = c.rotation.transpose() * Eigen::Vector3d(0, 0, 1);
  return std::acos(std::clamp(-axis_world.z(), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

}  // namespace internal

namespace {

std::string Vector3(const Eigen::Vector3d& v) {
  // Appended piece by piece: GCC 12's -Wrestrict misfires on a chain of "[" + std::string.
  std::string out = "[";
  out.append(FormatRoundTrip(v.x())).append(", ").append(FormatRoundTrip(v.y()));
  out.append(", ").append(FormatRoundTrip(v.z())).append("]");
  return out;
}

std::string PlaneLines(const CalibrationFit& fit, const std::string& prefix) {
  std::string out;
  for (const PlaneResiduals& p : fit.planes) {
    out +=
        prefix + StringPrintf("%-9s %7d %8s %8s %8s %10s %8s\n", FormatNumber(p.height_mm).c_str(),
                              p.count, FormatFixed(p.rms_px, 3).c_str(),
                              FormatFixed(p.worst_px, 3).c_str(), FormatFixed(p.rms_mm, 2).c_str(),
                              FormatFixed(p.heldout_rms_mm, 2).c_str(),
                              FormatFixed(p.worst_mm, 2).c_str());
  }
  return out;
}

std::string Parameter(const char* name, double value, double se) {
  std::string line = StringPrintf("  %-6s %12s", name, FormatSignificant(value, 7).c_str());
  if (se == 0.0) return line + "  (held fixed)\n";
  if (std::isnan(se)) return line + "  +- undetermined by these data\n";
  return line + "  +- " + FormatSignificant(se, 2) + "\n";
}

}  // namespace

std::string CalibrationFileText(const CalibrationInput& input, const CalibrationFit& fit) {
  const camera::PinholeCamera& c = fit.camera;
  std::string out =
      "# Fitted by `patlab calibrate " + input.loc.file +
      "` (patlab " PATLAB_VERSION "): " + std::to_string(fit.observations) + " pixels, RMS " +
      FormatFixed(fit.rms_px, 3) + " px, worst " + FormatFixed(fit.worst_px, 3) + " px.\n# " +
      (fit.heldout_folds > 0
           ? "Held-out mapping error " + FormatFixed(fit.heldout_rms_mm, 2) + " mm RMS (" +
                 std::to_string(fit.heldout_folds) +
                 "-fold cross-validation: points not used in the fit, their noise included); "
                 "rms_mm is in-sample.\n"
           : std::string("No cross-validated mapping error (holdout_folds = 0); rms_mm is "
                         "in-sample.\n")) +
      "# plane_mm  pixels  rms_px  worst_px  rms_mm  heldout_mm  worst_mm\n";
  out += PlaneLines(fit, "# ");
  out += "# Camera centre " + Vector3(fit.camera_centre_mm) + " mm, tilt " +
         FormatFixed(internal::TiltDeg(c), 2) + " deg from straight down.\n";
  out += "model = \"pinhole\"\nimage_size_px = [" + std::to_string(input.image_width_px) + ", " +
         std::to_string(input.image_height_px) + "]\n\n[pinhole]\n";
  out += "fx_px = " + FormatRoundTrip(c.fx_px) + "\nfy_px = " + FormatRoundTrip(c.fy_px) +
         "\ncx_px = " + FormatRoundTrip(c.cx_px) + "\ncy_px = " + FormatRoundTrip(c.cy_px) +
         "\nk1 = " + FormatRoundTrip(c.k1) + "\nk2 = " + FormatRoundTrip(c.k2) + "\n";
  out += "rotation_rodrigues = " + Vector3(fit.rotation_rodrigues) + "\n";
  out += "translation_mm = " + Vector3(c.translation_mm) + "\n\n[heights]\n";
  out += "default_mm = " + FormatRoundTrip(input.default_height_mm) + "\n";
  for (const auto& [name, h] : input.class_height_mm)
    out += name + " = " + FormatRoundTrip(h) + "\n";
  out +=
      "\n# The fit's position error on each plane; patlab detect adds the robot-top plane's "
      "rms_mm\n"
      "# to its blob noise (docs/detect.md). measured = false: no observation on that plane, the\n"
      "# pixel residuals converted with the plane's mm per px.\n";
  for (const camera::PlaneResidual& r : fit.file_residuals) {
    out += "[[residual]]\nheight_mm = " + FormatRoundTrip(r.height_mm) +
           "\nrms_mm = " + FormatFixed(r.rms_mm, 3) + "\nworst_mm = " + FormatFixed(r.worst_mm, 3) +
           "\n";
    if (!r.measured) out += "measured = false\n";
  }
  return out;
}

std::string FitReportText(const CalibrationInput& input, const CalibrationFit& fit) {
  const camera::PinholeCamera& c = fit.camera;
  std::string out = "calibration of " + input.loc.file + ": " + std::to_string(fit.observations) +
                    " pixels, " + std::to_string(fit.parameters) + " free parameters, " +
                    std::to_string(fit.iterations) + " iterations, " +
                    FormatFixed(fit.seconds * 1e3, 1) + " ms\n  solver: " + fit.termination + "\n";
  const auto& se = fit.standard_error;
  out += Parameter("fx_px", c.fx_px, se[0]) + Parameter("fy_px", c.fy_px, se[1]) +
         Parameter("cx_px", c.cx_px, se[2]) + Parameter("cy_px", c.cy_px, se[3]) +
         Parameter("k1", c.k1, se[4]) + Parameter("k2", c.k2, se[5]);
  out += "  camera centre " + Vector3(fit.camera_centre_mm) + " mm, tilt " +
         FormatFixed(internal::TiltDeg(c), 2) + " deg\n";
  out += "residuals: RMS " + FormatFixed(fit.rms_px, 3) + " px, worst " +
         FormatFixed(fit.worst_px, 3) + " px; " +
         (fit.heldout_folds > 0
              ? "held-out mapping error " + FormatFixed(fit.heldout_rms_mm, 2) + " mm RMS (" +
                    std::to_string(fit.heldout_folds) +
                    "-fold cross-validation: points not used in the fit, mapped by the camera "
                    "fitted without them, their noise included; rms_mm is in-sample)\n"
              : std::string("no cross-validated mapping error (holdout_folds = 0)\n")) +
         "  plane_mm   pixels   rms_px worst_px   rms_mm heldout_mm worst_mm\n" +
         PlaneLines(fit, "  ");
  out +=
      "mapping uncertainty (1 sd along the worst axis, from the fit's covariance) over the "
      "observed pixels:\n  plane_mm   rms_mm worst_mm\n";
  for (const PlaneResiduals& p : fit.planes) {
    out += StringPrintf("  %-9s %8s %8s\n", FormatNumber(p.height_mm).c_str(),
                        FormatFixed(p.mapping_sd_rms_mm, 2).c_str(),
                        FormatFixed(p.mapping_sd_worst_mm, 2).c_str());
  }
  std::vector<const ObservationResidual*> worst;
  for (const ObservationResidual& r : fit.residuals) worst.push_back(&r);
  const size_t shown = std::min<size_t>(5, worst.size());
  std::partial_sort(worst.begin(), worst.begin() + static_cast<std::ptrdiff_t>(shown), worst.end(),
                    [](const auto* a, const auto* b) { return a->px > b->px; });
  out += "worst pixels:\n";
  for (size_t i = 0; i < shown; ++i) {
    const ObservationResidual& r = *worst[i];
    out += "  " + r.loc.ToString() + ": " + r.kind + (r.name.empty() ? "" : " " + r.name) +
           (r.kind == "point" ? "" : " pixel " + std::to_string(r.index + 1)) + ": " +
           FormatFixed(r.px, 3) + " px, " + FormatFixed(r.mm, 2) + " mm\n";
  }
  for (const std::string& note : fit.notes) out += "note: " + note + "\n";
  return out;
}

}  // namespace patlab::calib
