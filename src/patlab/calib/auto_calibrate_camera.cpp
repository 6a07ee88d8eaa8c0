// The automatic field calibration's cameras (auto_calibrate_internal.h): a nadir view as a
// pinhole camera, the camera turned by 180 deg, and whether a field is the same turned.
#include <Eigen/Geometry>
#include <cmath>

#include "patlab/calib/auto_calibrate_internal.h"

namespace patlab::calib::internal {

camera::PinholeCamera PinholeOf(const NadirView& v, int width, int height) {
  camera::PinholeCamera cam;
  cam.fx_px = cam.fy_px = width;
  cam.cx_px = 0.5 * (width - 1);
  cam.cy_px = 0.5 * (height - 1);
  cam.k1 = v.kd;
  Eigen::Matrix2d a;
  switch (v.k & 3) {
    case 0:
      a << 1, 0, 0, -1;
      break;
    case 1:
      a << 0, 1, 1, 0;
      break;
    case 2:
      a << -1, 0, 0, 1;
      break;
    default:
      a << 0, -1, -1, 0;
      break;
  }
  Eigen::Matrix2d rot;
  rot << std::cos(v.psi), -std::sin(v.psi), std::sin(v.psi), std::cos(v.psi);
  const Eigen::Matrix2d r2 = rot * a;
  cam.rotation.setZero();
  cam.rotation.topLeftCorner<2, 2>() = r2;
  cam.rotation(2, 2) = -1.0;
  const Eigen::Vector3d centre(v.centre_mm.x(), v.centre_mm.y(), width / v.scale);
  cam.translation_mm = -cam.rotation * centre;
  return cam;
}

camera::PinholeCamera Turned(const camera::PinholeCamera& camera) {
  camera::PinholeCamera out = camera;
  out.rotation = camera.rotation * Eigen::Vector3d(-1, -1, 1).asDiagonal();
  return out;
}

bool PointSymmetric(const Field& field) {
  auto near = [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1.0; };
  for (const FieldLine& l : field.lines) {
    bool found = false;
    for (const FieldLine& m : field.lines)
      found = found || (near(-l.from_mm, m.from_mm) && near(-l.to_mm, m.to_mm)) ||
              (near(-l.from_mm, m.to_mm) && near(-l.to_mm, m.from_mm));
    if (!found) return false;
  }
  for (const FieldCircle& c : field.circles) {
    bool found = false;
    for (const FieldCircle& d : field.circles)
      found = found || (near(-c.centre_mm, d.centre_mm) && std::abs(c.radius_mm - d.radius_mm) < 1);
    if (!found) return false;
  }
  return true;
}

}  // namespace patlab::calib::internal
