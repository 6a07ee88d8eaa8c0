// The automatic field calibration's cameras (auto_calibrate_internal.h): a nadir view as a
// pinhole camera, the camera turned by 180 deg, how far two cameras map a frame apart and
// whether the lines decide between them, whether a field is the same turned, and whether a
// camera sees above the horizon.
#include <Eigen/Geometry>
#include <algorithm>
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

double FloorDifferenceMm(const camera::PinholeCamera& first, const camera::PinholeCamera& second,
                         bool point_symmetric, int width_px, int height_px) {
  const camera::CameraModel a = camera::CameraModel::Pinhole(first);
  double differ = INFINITY;
  for (int turn = 0; turn < (point_symmetric ? 2 : 1); ++turn) {
    const camera::CameraModel b = camera::CameraModel::Pinhole(turn == 0 ? second : Turned(second));
    double d = 0.0;
    for (double fx : {0.25, 0.5, 0.75})
      for (double fy : {0.25, 0.5, 0.75}) {
        const Vec2 px(fx * width_px, fy * height_px);
        const auto qa = a.PixelToWorld(px, 0.0), qb = b.PixelToWorld(px, 0.0);
        if (qa && qb) d = std::max(d, (*qa - *qb).norm());
      }
    differ = std::min(differ, d);
  }
  return differ;
}

bool SameMap(const camera::PinholeCamera& first, const camera::PinholeCamera& second,
             bool point_symmetric, int width_px, int height_px, double* differ_mm) {
  *differ_mm = FloorDifferenceMm(first, second, point_symmetric, width_px, height_px);
  const camera::CameraModel a = camera::CameraModel::Pinhole(first);
  const double mm_per_px = std::sqrt(a.AreaScale(Vec2(0.5 * width_px, 0.5 * height_px), 0.0));
  return !(*differ_mm > 20.0 * mm_per_px);
}

bool Undecided(const camera::PinholeCamera& best, double best_score,
               const camera::PinholeCamera& second, double second_score, bool point_symmetric,
               int width_px, int height_px, double* differ_mm) {
  if (!std::isfinite(second_score) || !(second_score > kUndecidedRatio * best_score)) return false;
  return !SameMap(best, second, point_symmetric, width_px, height_px, differ_mm);
}

namespace {

// The distance (px) from every pixel of the frame to a camera's marks, projected about 1 px
// apart.
LineDistance MarksDistance(const camera::PinholeCamera& camera, const FieldMarks& marks,
                           int width_px, int height_px) {
  const camera::CameraModel model = camera::CameraModel::Pinhole(camera);
  const Vec2 c(0.5 * (width_px - 1), 0.5 * (height_px - 1));
  const double mm_per_px = std::sqrt(std::max(1e-9, model.AreaScale(c, 0.0)));
  std::vector<LinePixel> projected;
  for (const Vec2& p : SampleMarks(marks, mm_per_px, nullptr)) {
    if (const auto q = model.WorldToPixel(p, 0.0)) projected.push_back({*q, Vec2(1, 0), 0.0});
  }
  return LineDistance(projected, width_px, height_px);
}

}  // namespace

ExclusiveLines ExclusiveLinePixels(const camera::PinholeCamera& first,
                                   const FieldMarks& first_marks,
                                   const camera::PinholeCamera& second,
                                   const FieldMarks& second_marks,
                                   const std::vector<LinePixel>& pixels, int width_px,
                                   int height_px) {
  const LineDistance a = MarksDistance(first, first_marks, width_px, height_px);
  const LineDistance b = MarksDistance(second, second_marks, width_px, height_px);
  ExclusiveLines e;
  for (const LinePixel& p : pixels) {
    const double da = a.At(p.pixel), db = b.At(p.pixel);
    e.first += da <= kOwnPx && db > kOtherPx ? 1 : 0;
    e.second += db <= kOwnPx && da > kOtherPx ? 1 : 0;
  }
  return e;
}

bool OwnLinesDecide(const ExclusiveLines& e) {
  return e.first >= kDecidingPixels && 4 * e.second <= e.first;
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

double BendPx(const std::vector<Vec2>& px) {
  Vec2 mean = Vec2::Zero();
  for (const Vec2& p : px) mean += p;
  mean /= static_cast<double>(px.size());
  double sxx = 0, syy = 0, sxy = 0;
  for (const Vec2& p : px) {
    const Vec2 d = p - mean;
    sxx += d.x() * d.x(), syy += d.y() * d.y(), sxy += d.x() * d.y();
  }
  const double n = static_cast<double>(px.size());
  sxx /= n, syy /= n, sxy /= n;
  // The smaller eigenvalue of the scatter: the mean squared distance from the best line.
  const double half = std::sqrt(0.25 * (sxx - syy) * (sxx - syy) + sxy * sxy);
  return std::sqrt(std::max(0.0, 0.5 * (sxx + syy) - half));
}

CalibrationInput BaseInput(const std::string& source, int width_px, int height_px,
                           const AutoOptions& options) {
  CalibrationInput base;
  base.source = source;
  base.image_width_px = width_px;
  base.image_height_px = height_px;
  base.loc = FileLoc{source, 0};
  base.options.fixed = options.fixed;
  base.options.huber_px = options.huber_px;
  base.options.camera_height_mm = options.camera_height_mm;
  base.options.holdout_folds = 0;
  base.options.settle_px = options.settle_px;
  return base;
}

std::optional<Vec2> AboveHorizon(const camera::PinholeCamera& camera, int width_px, int height_px) {
  const camera::CameraModel model = camera::CameraModel::Pinhole(camera);
  const double right = width_px - 1.0, bottom = height_px - 1.0;
  const Vec2 corners[] = {Vec2(0, 0), Vec2(right, 0), Vec2(right, bottom), Vec2(0, bottom)};
  for (int side = 0; side < 4; ++side) {
    const Vec2 from = corners[side], to = corners[(side + 1) % 4];
    const int steps = std::max(1, static_cast<int>(std::ceil((to - from).norm() / kHorizonStepPx)));
    for (int i = 0; i < steps; ++i) {
      const Vec2 pixel = from + (to - from) * (static_cast<double>(i) / steps);
      if (!model.PixelToWorld(pixel, 0.0)) return pixel;
    }
  }
  return std::nullopt;
}

}  // namespace patlab::calib::internal
