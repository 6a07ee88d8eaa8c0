// The camera fit's checks of its input and its start cameras (calibrate_fit.cpp solves from
// them): the known points' homography decomposed with candidate focal lengths.
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

#include "patlab/calib/calibrate.h"
#include "patlab/calib/calibrate_internal.h"
#include "patlab/core/format.h"
#include "patlab/estimate/estimators.h"

namespace patlab::calib::internal {
namespace {

// ---- validation -------------------------------------------------------------------------------

void CheckPixel(const CalibrationInput& in, const Vec2& px, const FileLoc& loc,
                const std::string& what) {
  if (px.x() < -0.5 || px.y() < -0.5 || px.x() > in.image_width_px - 0.5 ||
      px.y() > in.image_height_px - 0.5) {
    throw InputError(loc, what + " (" + FormatNumber(px.x()) + ", " + FormatNumber(px.y()) +
                              ") is outside the " + std::to_string(in.image_width_px) + "x" +
                              std::to_string(in.image_height_px) +
                              " image; expected pixel coordinates within it");
  }
}

}  // namespace

void CheckPixels(const CalibrationInput& in) {
  for (const PointObservation& p : in.points) CheckPixel(in, p.pixel, p.loc, "pixel");
  for (const LineObservation& l : in.lines)
    for (const Vec2& px : l.pixels) CheckPixel(in, px, l.loc, "a pixel of line " + l.name);
  for (const CircleObservation& c : in.circles)
    for (const Vec2& px : c.pixels) CheckPixel(in, px, c.loc, "a pixel of circle " + c.name);
  for (const PatternObservation& p : in.patterns)
    for (const auto& px : p.pixels)
      if (px) CheckPixel(in, *px, p.loc, "a pixel of pattern " + p.name);
}

namespace {

// The plane height with the most known points: the start is fitted to its points.
double StartPlane(const CalibrationInput& in) {
  std::map<double, int> count;
  for (const PointObservation& p : in.points) ++count[p.height_mm];
  double best = 0.0;
  int most = -1;
  for (const auto& [h, n] : count) {
    if (n > most) best = h, most = n;
  }
  return best;
}

std::vector<const PointObservation*> PointsOnPlane(const CalibrationInput& in, double height) {
  std::vector<const PointObservation*> out;
  for (const PointObservation& p : in.points)
    if (p.height_mm == height) out.push_back(&p);
  return out;
}

// Whether some four of the points have no three on a line (a triangle of area below 1e-3 of the
// points' squared extent counts as a line): what a plane homography needs. Points on one field
// line (the halfway line's ends, the centre, the centre circle's crossings) do not suffice,
// however many.
bool HasFourInGeneralPosition(const std::vector<const PointObservation*>& pts) {
  const size_t n = std::min<size_t>(pts.size(), 40);
  double extent2 = 0.0;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      extent2 = std::max(extent2, (pts[i]->world_mm - pts[j]->world_mm).squaredNorm());
  auto line = [&](size_t a, size_t b, size_t c) {
    const Vec2 u = pts[b]->world_mm - pts[a]->world_mm, v = pts[c]->world_mm - pts[a]->world_mm;
    return std::abs(u.x() * v.y() - u.y() * v.x()) < 2e-3 * extent2;
  };
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n; ++b)
      for (size_t c = b + 1; c < n; ++c) {
        if (line(a, b, c)) continue;
        for (size_t d = c + 1; d < n; ++d)
          if (!line(a, b, d) && !line(a, c, d) && !line(b, c, d)) return true;
      }
  return false;
}

}  // namespace

// At least four known points on one plane, no three of them on a line, so that the plane
// homography of the start is determined.
void CheckStartPoints(const CalibrationInput& in) {
  if (in.options.start_camera) return;  // the caller's own start
  const auto pts = PointsOnPlane(in, StartPlane(in));
  if (pts.size() < 4) {
    throw InputError(in.loc, "the input has " + std::to_string(pts.size()) +
                                 " known points on its best-covered plane; expected at least 4 "
                                 "[[point]] tables on one plane height (the fit starts from their "
                                 "homography)");
  }
  if (!HasFourInGeneralPosition(pts)) {
    throw InputError(pts.front()->loc,
                     "no four of the known points on the plane at " +
                         FormatNumber(pts.front()->height_mm) +
                         " mm are free of three on a line; expected at least 4 points no three of "
                         "which lie on one line (e.g. field corners and the centre)");
  }
}

namespace {

// ---- the start --------------------------------------------------------------------------------

// The homography world (x, y, 1) -> pixel (u, v, 1) of the points, by the normalised DLT
// (Hartley & Zisserman, algorithm 4.2).
Eigen::Matrix3d Homography(const std::vector<const PointObservation*>& pts) {
  auto normaliser = [](const std::vector<Vec2>& v) {
    Vec2 mean = Vec2::Zero();
    for (const Vec2& p : v) mean += p;
    mean /= static_cast<double>(v.size());
    double spread = 0.0;
    for (const Vec2& p : v) spread += (p - mean).norm();
    const double s = std::sqrt(2.0) * static_cast<double>(v.size()) / spread;
    Eigen::Matrix3d n;
    n << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
    return n;
  };
  std::vector<Vec2> world, pixel;
  for (const auto* p : pts) world.push_back(p->world_mm), pixel.push_back(p->pixel);
  const Eigen::Matrix3d nw = normaliser(world), np = normaliser(pixel);
  Eigen::MatrixXd a(2 * pts.size(), 9);
  for (size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d w = nw * world[i].homogeneous();
    const Eigen::Vector3d p = np * pixel[i].homogeneous();
    a.row(2 * i) << 0, 0, 0, -w.transpose(), p.y() * w.transpose();
    a.row(2 * i + 1) << w.transpose(), 0, 0, 0, -p.x() * w.transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d hn;
  hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  return np.inverse() * hn * nw;
}

// Zhang's constraints r1 . r2 = 0 and |r1| = |r2| on H = lambda K [r1 r2 t] with the principal
// point removed (K = diag(f, f, 1)) read a_i / f^2 + b_i = 0, i = 1, 2; their least-squares
// solution for f^2 is -(a1 b1 + a2 b2) / (b1^2 + b2^2). nullopt when that is not a plausible focal
// length for the image (between 0.2 and 20 image widths): the plane is then seen so nearly
// head-on that the homography does not determine f (f and the camera's height trade off).
std::optional<double> FocalFromHomography(const Eigen::Matrix3d& h, double image_width) {
  const double a1 = h(0, 0) * h(0, 1) + h(1, 0) * h(1, 1), b1 = h(2, 0) * h(2, 1);
  const double a2 = h(0, 0) * h(0, 0) + h(1, 0) * h(1, 0) - h(0, 1) * h(0, 1) - h(1, 1) * h(1, 1);
  const double b2 = h(2, 0) * h(2, 0) - h(2, 1) * h(2, 1);
  const double denominator = b1 * b1 + b2 * b2;
  if (!(denominator > 0.0)) return std::nullopt;
  const double f2 = -(a1 * b1 + a2 * b2) / denominator;
  if (!(f2 > 0.0)) return std::nullopt;
  const double f = std::sqrt(f2);
  if (f < 0.2 * image_width || f > 20.0 * image_width) return std::nullopt;
  return f;
}

// R, t from H = K [r1 r2 t'] for the plane z = height (t = t' - r3 height), camera in front.
void PoseFromHomography(const Eigen::Matrix3d& h, double f, const Vec2& c, double height,
                        const std::vector<const PointObservation*>& pts, FitState& s) {
  Eigen::Matrix3d k_inv;
  k_inv << 1 / f, 0, -c.x() / f, 0, 1 / f, -c.y() / f, 0, 0, 1;
  Eigen::Matrix3d m = k_inv * h;
  m /= 0.5 * (m.col(0).norm() + m.col(1).norm());
  double depth = 0.0;  // the sign that puts the points in front of the camera
  for (const auto* p : pts) depth += (m * p->world_mm.homogeneous()).z();
  if (depth < 0) m = -m;
  Eigen::Matrix3d r;
  r.col(0) = m.col(0);
  r.col(1) = m.col(1);
  r.col(2) = m.col(0).cross(m.col(1));
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  r = svd.matrixU() * svd.matrixV().transpose();
  const Eigen::Vector3d t = m.col(2) - r.col(2) * height;
  const Eigen::AngleAxisd aa(r);
  const Eigen::Vector3d rv = aa.angle() * aa.axis();
  s.pose = {rv.x(), rv.y(), rv.z(), t.x(), t.y(), t.z()};
}

// Start values of the per-pixel and per-pattern unknowns from the start camera.
void StartNuisance(const CalibrationInput& in, FitState& s, std::vector<std::string>& notes) {
  const camera::CameraModel cam = camera::CameraModel::Pinhole(internal::CameraOf(s));
  auto on_plane = [&](const Vec2& px, double h) { return cam.PixelToWorld(px, h); };
  for (const LineObservation& l : in.lines) {
    std::vector<double>& ts = s.line_t.emplace_back();
    const Vec2 d = l.to_mm - l.from_mm;
    for (const Vec2& px : l.pixels) {
      const auto q = on_plane(px, l.height_mm);
      const double t = q ? (*q - l.from_mm).dot(d) / d.squaredNorm() : 0.5;
      ts.push_back(std::isfinite(t) ? t : 0.5);
    }
  }
  for (const CircleObservation& c : in.circles) {
    std::vector<double>& phis = s.circle_phi.emplace_back();
    for (const Vec2& px : c.pixels) {
      const auto q = on_plane(px, c.height_mm);
      const double phi = q ? std::atan2(q->y() - c.centre_mm.y(), q->x() - c.centre_mm.x()) : 0.0;
      phis.push_back(std::isfinite(phi) ? phi : 0.0);
    }
  }
  for (const PatternObservation& p : in.patterns) {
    Pattern seen;
    std::vector<Vec2> world;
    for (size_t i = 0; i < p.pixels.size(); ++i) {
      const auto q = p.pixels[i] ? on_plane(*p.pixels[i], p.height_mm) : std::nullopt;
      if (!q) continue;
      seen.patches.push_back(p.pattern.patches[i]);
      world.push_back(*q);
    }
    Pose2 pose;
    if (seen.patches.size() >= 2 && std::isfinite(world[0].x())) {
      pose = estimate::LeastSquares(estimate::Model::FromPattern(seen), world.data());
    } else {
      notes.push_back("pattern " + p.name + ": start pose unknown (patches off the start plane)");
    }
    s.pattern_pose.push_back({pose.x_mm, pose.y_mm, pose.theta_rad});
  }
}

// RMS reprojection error (px) of the known points on the start plane through the camera of `s`
// (distortion ignored); infinite when a point is behind it.
double PointsRms(const FitState& s, const std::vector<const PointObservation*>& pts) {
  const camera::CameraModel cam = camera::CameraModel::Pinhole(internal::CameraOf(s));
  double sum = 0.0;
  for (const auto* p : pts) {
    const auto px = cam.WorldToPixel(p->world_mm, p->height_mm);
    if (!px) return std::numeric_limits<double>::infinity();
    sum += (*px - p->pixel).squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(pts.size()));
}

}  // namespace

// Start cameras: the plane homography of the known points on the best-covered plane, decomposed
// with each candidate focal length: the user's, or Zhang's closed form and a log-spaced sweep of
// 0.5 to 4 image widths (lens distortion, which the homography ignores, can spoil the closed form,
// and a plane seen nearly head-on does not give it at all). The fit's first stage starts from
// each and keeps the best.
std::vector<FitState> StartCandidates(const CalibrationInput& in) {
  const FitOptions& o = in.options;
  if (o.start_camera) {
    const camera::PinholeCamera& cam = *o.start_camera;
    FitState s;
    s.intrinsics = {cam.fx_px, cam.fy_px / cam.fx_px, cam.cx_px, cam.cy_px, cam.k1, cam.k2};
    const Eigen::AngleAxisd aa(cam.rotation);
    const Eigen::Vector3d rv = aa.angle() * aa.axis();
    s.pose = {rv.x(),
              rv.y(),
              rv.z(),
              cam.translation_mm.x(),
              cam.translation_mm.y(),
              cam.translation_mm.z()};
    std::vector<std::string> notes;
    StartNuisance(in, s, notes);
    return {s};
  }
  const Vec2 c = o.principal_point_px.value_or(
      Vec2(0.5 * (in.image_width_px - 1), 0.5 * (in.image_height_px - 1)));
  const double plane = StartPlane(in);
  const auto pts = PointsOnPlane(in, plane);
  const Eigen::Matrix3d h = Homography(pts);
  Eigen::Matrix3d shift;
  shift << 1, 0, -c.x(), 0, 1, -c.y(), 0, 0, 1;
  std::vector<double> focal;
  if (o.focal_px) {
    focal.push_back(*o.focal_px);
  } else {
    if (const auto zhang = FocalFromHomography(shift * h, in.image_width_px))
      focal.push_back(*zhang);
    for (int i = 0; i <= 6; ++i) focal.push_back(in.image_width_px * 0.5 * std::pow(8.0, i / 6.0));
  }
  std::vector<FitState> out;
  for (double f : focal) {
    FitState s;
    s.intrinsics = {f, 1.0, c.x(), c.y(), o.k1, o.k2};
    PoseFromHomography(h, f, c, plane, pts, s);
    if (!std::isfinite(PointsRms(s, pts))) continue;  // a point behind the camera
    std::vector<std::string> notes;
    StartNuisance(in, s, notes);
    out.push_back(s);
  }
  return out;
}

}  // namespace patlab::calib::internal
