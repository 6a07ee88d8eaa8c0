// The fitted camera's uncertainty where a user meets it: where it puts a pixel on a plane
// (calibrate.h, MappingCovariance), and its summary over each plane's observed pixels.
#include <algorithm>
#include <cmath>

#include "patlab/calib/calibrate.h"
#include "patlab/calib/calibrate_internal.h"

namespace patlab::calib {

namespace {

using Parameters = std::array<double, kCameraParameters>;

Parameters ParametersOf(const CalibrationFit& fit) {
  const camera::PinholeCamera& c = fit.camera;
  const Eigen::Vector3d& r = fit.rotation_rodrigues;
  const Eigen::Vector3d& t = c.translation_mm;
  return {
      c.fx_px, c.fy_px / c.fx_px, c.cx_px, c.cy_px, c.k1, c.k2, r.x(), r.y(), r.z(), t.x(), t.y(),
      t.z()};
}

std::optional<Vec2> MapAt(const Parameters& p, const Vec2& pixel, double height_mm) {
  internal::FitState s;
  std::copy(p.begin(), p.begin() + 6, s.intrinsics.begin());
  std::copy(p.begin() + 6, p.end(), s.pose.begin());
  return camera::CameraModel::Pinhole(internal::CameraOf(s)).PixelToWorld(pixel, height_mm);
}

}  // namespace

std::optional<std::array<double, 4>> MappingCovariance(const CalibrationFit& fit, const Vec2& pixel,
                                                       double height_mm) {
  constexpr int n = kCameraParameters;
  const Parameters at = ParametersOf(fit);
  // d(world x, y) / d(parameter i); zero for a parameter held fixed (an Eigen vector's default
  // constructor leaves it uninitialised, and garbage times a zero covariance can be NaN).
  std::array<Vec2, n> jacobian;
  jacobian.fill(Vec2::Zero());
  for (int i = 0; i < n; ++i) {
    const double variance = fit.covariance[static_cast<size_t>(i * n + i)];
    if (std::isnan(variance)) return std::nullopt;
    if (!(variance > 0.0)) continue;  // held fixed: no contribution
    const double step = 1e-3 * std::sqrt(variance);
    Parameters up = at, down = at;
    up[static_cast<size_t>(i)] += step;
    down[static_cast<size_t>(i)] -= step;
    const auto a = MapAt(up, pixel, height_mm), b = MapAt(down, pixel, height_mm);
    if (!a || !b) return std::nullopt;
    jacobian[static_cast<size_t>(i)] = (*a - *b) / (2.0 * step);
  }
  double xx = 0.0, xy = 0.0, yy = 0.0;  // J C J'
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double c = fit.covariance[static_cast<size_t>(i * n + j)];
      const Vec2& ji = jacobian[static_cast<size_t>(i)];
      const Vec2& jj = jacobian[static_cast<size_t>(j)];
      xx += ji.x() * c * jj.x();
      xy += ji.x() * c * jj.y();
      yy += ji.y() * c * jj.y();
    }
  }
  return std::array<double, 4>{xx, xy, xy, yy};
}

double MappingSdOver(const CalibrationFit& fit, int width_px, int height_px, double height_mm,
                     const std::function<bool(const Vec2&)>& inside, int step_px) {
  const camera::CameraModel model = camera::CameraModel::Pinhole(fit.camera);
  double sum2 = 0.0;
  int n = 0;
  for (int v = step_px / 2; v < height_px; v += step_px) {
    for (int u = step_px / 2; u < width_px; u += step_px) {
      const Vec2 pixel(u, v);
      const std::optional<Vec2> at = model.PixelToWorld(pixel, height_mm);
      if (!at || !inside(*at)) continue;
      const auto c = MappingCovariance(fit, pixel, height_mm);
      if (!c) {
        if (std::isnan(fit.covariance[0])) return std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      sum2 += (*c)[0] + (*c)[3];
      ++n;
    }
  }
  return n > 0 ? std::sqrt(sum2 / n) : std::numeric_limits<double>::quiet_NaN();
}

namespace internal {

// The standard deviation along the worst axis: the square root of the larger eigenvalue.
double WorstAxisSd(const std::array<double, 4>& c) {
  const double mean = 0.5 * (c[0] + c[3]);
  const double half_gap = std::hypot(0.5 * (c[0] - c[3]), c[1]);
  return std::sqrt(std::max(0.0, mean + half_gap));
}

void FillMappingUncertainty(CalibrationFit& fit) {
  for (PlaneResiduals& plane : fit.planes) {
    double sum2 = 0.0, worst = 0.0;
    int n = 0;
    bool determined = true;
    for (const ObservationResidual& r : fit.residuals) {
      if (r.height_mm != plane.height_mm) continue;
      const auto c = MappingCovariance(fit, r.pixel, r.height_mm);
      if (!c) {
        // A pixel that does not map back (beyond the lens's fold) is reported by its NaN mm
        // residual; an undetermined covariance makes the whole summary undetermined.
        if (std::isnan(fit.covariance[0])) determined = false;
        continue;
      }
      const double sd = WorstAxisSd(*c);
      sum2 += sd * sd;
      worst = std::max(worst, sd);
      ++n;
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    plane.mapping_sd_rms_mm = determined && n > 0 ? std::sqrt(sum2 / n) : nan;
    plane.mapping_sd_worst_mm = determined && n > 0 ? worst : nan;
  }
}

}  // namespace internal

}  // namespace patlab::calib
