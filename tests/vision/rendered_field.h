// Frames of a field's painted lines seen by known cameras, and how far a fitted camera's floor
// map lies from the true one: what the automatic calibration's tests (field_lines_test.cpp,
// field_family_test.cpp, held_out_error_test.cpp, narrow_view_test.cpp, settled_fit_test.cpp)
// share.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "patlab/calib/field.h"
#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/render/camera_render.h"
#include "patlab/render/field_render.h"

namespace patlab::vision::rendered {

// A camera as a calibration file gives it (camera.toml's [pinhole], as scripts/setup_rendered.py
// writes its random cameras): square pixels of focal length f_px, the principal point, k1, the
// rotation as a Rodrigues vector and the translation.
inline camera::PinholeCamera CameraOfFile(double f_px, const Vec2& principal_px, double k1,
                                          const Eigen::Vector3d& rodrigues,
                                          const Eigen::Vector3d& translation_mm) {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = f_px;
  c.cx_px = principal_px.x();
  c.cy_px = principal_px.y();
  c.k1 = k1;
  c.rotation = Eigen::AngleAxisd(rodrigues.norm(), rodrigues.normalized()).matrix();
  c.translation_mm = translation_mm;
  return c;
}

// `intrinsics` looking straight down from `height_mm` over `over_mm` (the image's x along the
// floor's x and its y against the floor's y, before the turn by `yaw_rad` about the vertical),
// then tilted by `tilt`.
inline camera::PinholeCamera LookingDown(camera::PinholeCamera intrinsics, const Vec2& over_mm,
                                         double height_mm, double yaw_rad,
                                         const Eigen::Matrix3d& tilt) {
  const Eigen::Matrix3d nadir = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).matrix();
  intrinsics.rotation = tilt * nadir * yaw;
  intrinsics.translation_mm =
      -intrinsics.rotation * Eigen::Vector3d(over_mm.x(), over_mm.y(), height_mm);
  return intrinsics;
}

// The field's painted lines through `camera` and the colour camera's sensor (read noise 3
// levels, noise seed `seed`), as RGB.
inline camera::Image RenderLines(const calib::Field& field, const camera::PinholeCamera& camera,
                                 int width, int height, uint64_t seed) {
  const camera::Image clean =
      render::RenderFieldLines(field, camera::CameraModel::Pinhole(camera), width, height);
  render::CameraSensorOptions sensor;
  sensor.seed = seed;
  sensor.read_noise_levels = 3.0;
  return camera::ToRgb(render::SimulateSensor(clean, sensor, 0));
}

// RMS (mm) between two cameras' floor maps over a 10 px grid of a width x height frame, over the
// pixels whose true floor point lies within |x| <= half_x_mm and |y| <= half_y_mm (every pixel
// by default); a pixel the fitted camera cannot map counts 10^6 mm.
inline double MappingRmsMm(const camera::PinholeCamera& truth, const camera::PinholeCamera& fitted,
                           int width, int height,
                           double half_x_mm = std::numeric_limits<double>::infinity(),
                           double half_y_mm = std::numeric_limits<double>::infinity()) {
  const camera::CameraModel a = camera::CameraModel::Pinhole(truth),
                            b = camera::CameraModel::Pinhole(fitted);
  double sum = 0.0;
  int n = 0;
  for (int y = 5; y < height; y += 10) {
    for (int x = 5; x < width; x += 10) {
      const auto qa = a.PixelToWorld(Vec2(x, y), 0.0);
      if (!qa || std::abs(qa->x()) > half_x_mm || std::abs(qa->y()) > half_y_mm) continue;
      const auto qb = b.PixelToWorld(Vec2(x, y), 0.0);
      sum += qb ? (*qa - *qb).squaredNorm() : 1e12;
      ++n;
    }
  }
  return std::sqrt(sum / std::max(1, n));
}

}  // namespace patlab::vision::rendered
