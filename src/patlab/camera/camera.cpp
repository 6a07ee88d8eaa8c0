#include "patlab/camera/camera.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "patlab/core/error.h"
#include "patlab/core/format.h"

namespace patlab::camera {

Eigen::Matrix3d RotationFromRodrigues(const Eigen::Vector3d& rodrigues) {
  const double angle = rodrigues.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rodrigues / angle).toRotationMatrix();
}

CameraModel CameraModel::Pinhole(const PinholeCamera& pinhole) {
  CameraModel m;
  m.is_pinhole_ = true;
  m.pinhole_ = pinhole;
  return m;
}

CameraModel CameraModel::Homographies(std::vector<PlaneHomography> homographies) {
  CameraModel m;
  m.is_pinhole_ = false;
  m.homographies_ = std::move(homographies);
  for (const PlaneHomography& h : m.homographies_)
    m.inverses_.push_back(h.pixel_to_world.inverse());
  return m;
}

const PlaneHomography* CameraModel::FindHomography(double height_mm) const {
  for (const PlaneHomography& h : homographies_) {
    if (std::abs(h.height_mm - height_mm) <= kHeightToleranceMm) return &h;
  }
  return nullptr;
}

bool CameraModel::SupportsHeight(double height_mm) const {
  return is_pinhole_ || FindHomography(height_mm) != nullptr;
}

std::optional<Vec2> CameraModel::PixelToWorld(const Vec2& pixel, double height_mm) const {
  if (!is_pinhole_) {
    const PlaneHomography* h = FindHomography(height_mm);
    if (h == nullptr) return std::nullopt;
    const Eigen::Vector3d w = h->pixel_to_world * Eigen::Vector3d(pixel.x(), pixel.y(), 1.0);
    if (std::abs(w.z()) < 1e-12) return std::nullopt;
    return Vec2(w.x() / w.z(), w.y() / w.z());
  }
  const PinholeCamera& c = pinhole_;
  // Undistort: solve r_d = r (1 + k1 r^2 + k2 r^4) for r by Newton's method from r = r_d.
  const double xd = (pixel.x() - c.cx_px) / c.fx_px;
  const double yd = (pixel.y() - c.cy_px) / c.fy_px;
  const double rd = std::hypot(xd, yd);
  double scale = 1.0;  // r / r_d
  if (rd > 0.0 && (c.k1 != 0.0 || c.k2 != 0.0)) {
    double r = rd;
    for (int iteration = 0; iteration < 20; ++iteration) {
      const double r2 = r * r;
      const double g = r * (1.0 + c.k1 * r2 + c.k2 * r2 * r2) - rd;
      const double dg = 1.0 + 3.0 * c.k1 * r2 + 5.0 * c.k2 * r2 * r2;
      if (dg <= 0.0) return std::nullopt;  // beyond the fold of the distortion polynomial
      const double step = g / dg;
      r -= step;
      if (std::abs(step) < 1e-14) break;
    }
    if (!(r >= 0.0)) return std::nullopt;
    const double r2 = r * r;
    if (1.0 + 3.0 * c.k1 * r2 + 5.0 * c.k2 * r2 * r2 <= 0.0) return std::nullopt;
    scale = r / rd;
  }
  // Ray through the undistorted point, in world coordinates, from the camera centre C.
  const Eigen::Vector3d ray_camera(xd * scale, yd * scale, 1.0);
  const Eigen::Matrix3d rt = c.rotation.transpose();
  const Eigen::Vector3d centre = -rt * c.translation_mm;
  const Eigen::Vector3d ray = rt * ray_camera;
  if (std::abs(ray.z()) < 1e-12) return std::nullopt;
  const double s = (height_mm - centre.z()) / ray.z();
  if (s <= 0.0) return std::nullopt;  // the plane is behind the camera
  return Vec2(centre.x() + s * ray.x(), centre.y() + s * ray.y());
}

std::optional<Vec2> CameraModel::WorldToPixel(const Vec2& world_mm, double height_mm) const {
  if (!is_pinhole_) {
    const PlaneHomography* h = FindHomography(height_mm);
    if (h == nullptr) return std::nullopt;
    const Eigen::Matrix3d& inverse = inverses_[static_cast<size_t>(h - homographies_.data())];
    const Eigen::Vector3d p = inverse * Eigen::Vector3d(world_mm.x(), world_mm.y(), 1.0);
    if (std::abs(p.z()) < 1e-12) return std::nullopt;
    return Vec2(p.x() / p.z(), p.y() / p.z());
  }
  const PinholeCamera& c = pinhole_;
  const Eigen::Vector3d pc =
      c.rotation * Eigen::Vector3d(world_mm.x(), world_mm.y(), height_mm) + c.translation_mm;
  if (pc.z() <= 0.0) return std::nullopt;
  const double x = pc.x() / pc.z(), y = pc.y() / pc.z();
  const double r2 = x * x + y * y;
  // Beyond the fold of the distortion polynomial (where r (1 + k1 r^2 + k2 r^4) stops growing)
  // the lens model maps far-off points back into the image; no real lens sees them there.
  if (1.0 + 3.0 * c.k1 * r2 + 5.0 * c.k2 * r2 * r2 <= 0.0) return std::nullopt;
  const double f = 1.0 + c.k1 * r2 + c.k2 * r2 * r2;
  return Vec2(c.fx_px * x * f + c.cx_px, c.fy_px * y * f + c.cy_px);
}

double CameraModel::AreaScale(const Vec2& pixel, double height_mm) const {
  constexpr double h = 0.5;
  const auto xp = PixelToWorld(pixel + Vec2(h, 0), height_mm);
  const auto xm = PixelToWorld(pixel - Vec2(h, 0), height_mm);
  const auto yp = PixelToWorld(pixel + Vec2(0, h), height_mm);
  const auto ym = PixelToWorld(pixel - Vec2(0, h), height_mm);
  if (!xp || !xm || !yp || !ym) return 0.0;
  const Vec2 du = (*xp - *xm) / (2 * h), dv = (*yp - *ym) / (2 * h);
  return std::abs(du.x() * dv.y() - du.y() * dv.x());
}

Vec2 ResizedPixel(const Vec2& pixel, double scale) {
  return scale * (pixel + Vec2(0.5, 0.5)) - Vec2(0.5, 0.5);
}

CameraModel CameraModel::Resized(double scale) const {
  PATLAB_CHECK(scale > 0.0);
  if (is_pinhole_) {
    PinholeCamera c = pinhole_;
    c.fx_px *= scale;
    c.fy_px *= scale;
    const Vec2 centre = ResizedPixel(Vec2(c.cx_px, c.cy_px), scale);
    c.cx_px = centre.x();
    c.cy_px = centre.y();
    return Pinhole(c);
  }
  // The old pixel of a new one: p = (p' + 0.5) / scale - 0.5.
  Eigen::Matrix3d to_old = Eigen::Matrix3d::Identity();
  to_old(0, 0) = to_old(1, 1) = 1.0 / scale;
  to_old(0, 2) = to_old(1, 2) = 0.5 / scale - 0.5;
  std::vector<PlaneHomography> resized = homographies_;
  for (PlaneHomography& h : resized) h.pixel_to_world = h.pixel_to_world * to_old;
  return Homographies(std::move(resized));
}

Calibration Calibration::Resized(double scale, int width_px, int height_px) const {
  Calibration c = *this;
  c.camera = camera.Resized(scale);
  c.image_width_px = image_width_px == 0 ? 0 : width_px;
  c.image_height_px = image_height_px == 0 ? 0 : height_px;
  return c;
}

double Calibration::ResidualRmsMm(double height_mm) const {
  const PlaneResidual* best = nullptr;
  for (const PlaneResidual& r : residuals) {
    if (best == nullptr ||
        std::abs(r.height_mm - height_mm) < std::abs(best->height_mm - height_mm)) {
      best = &r;
    }
  }
  return best == nullptr ? 0.0 : best->rms_mm;
}

std::vector<OptionsProblem> Check(const PinholeCamera& c) {
  OptionsChecker check("pinhole");
  check.InRange("k1", c.k1, -kMaxDistortion, kMaxDistortion)
      .InRange("k2", c.k2, -kMaxDistortion, kMaxDistortion);
  // The camera centre in world coordinates: -R^T t.
  const double height_mm = -(c.rotation.transpose() * c.translation_mm).z();
  if (!(height_mm > 0.0 && height_mm <= kMaxCameraHeightMm)) {
    check.Fail("camera_position_mm",
               "the camera centre is at height " + FormatNumber(height_mm) +
                   " mm; expected a camera above the floor, at a height in (0, " +
                   FormatNumber(kMaxCameraHeightMm) + "] mm");
  }
  return check.Take();
}

}  // namespace patlab::camera
