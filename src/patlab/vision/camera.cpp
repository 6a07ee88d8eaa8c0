#include "patlab/vision/camera.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/toml_util.h"

namespace patlab::vision {

namespace {
constexpr double kHeightToleranceMm = 0.5;  // a homography serves heights within this
}

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

namespace {

// An integer or a finite float as a double; anything else is not a number here.
std::optional<double> FiniteNumber(const toml::node& node) {
  if (const auto* i = node.as_integer()) return static_cast<double>(i->get());
  if (const auto* f = node.as_floating_point(); f && std::isfinite(f->get())) return f->get();
  return std::nullopt;
}

std::vector<double> NumberArray(const io::TomlReader& r, std::string_view key, size_t n,
                                const std::string& expected) {
  const toml::node* node = r.table().get(key);
  if (node == nullptr) r.Fail(key, "missing " + r.Describe(key) + "; expected " + expected);
  const toml::array* a = node->as_array();
  std::vector<double> out;
  if (a != nullptr && a->size() == n) {
    for (const toml::node& e : *a) {
      if (const auto v = FiniteNumber(e)) out.push_back(*v);
    }
  }
  if (out.size() != n) r.Fail(key, r.Describe(key) + " is malformed; expected " + expected);
  return out;
}

double Positive(const io::TomlReader& r, std::string_view key) {
  const double v = r.Number(key);
  if (!(v > 0.0)) r.Fail(key, r.Describe(key) + " is " + FormatNumber(v) + "; expected > 0");
  return v;
}

void ReadImageSize(const io::TomlReader& top, Calibration& cal) {
  const auto size = NumberArray(top, "image_size_px", 2, "[width, height] in pixels");
  // At most 100000 px a side, so the sizes fit an int (a huge value was found by
  // calibration_fuzz).
  if (size[0] < 1 || size[1] < 1 || size[0] > 1e5 || size[1] > 1e5 ||
      size[0] != std::floor(size[0]) || size[1] != std::floor(size[1])) {
    top.Fail("image_size_px",
             "image_size_px is not two integers in [1, 100000]; expected [width, height] in "
             "pixels");
  }
  cal.image_width_px = static_cast<int>(size[0]);
  cal.image_height_px = static_cast<int>(size[1]);
}

void ReadIntrinsics(const io::TomlReader& r, PinholeCamera& c) {
  c.fx_px = Positive(r, "fx_px");
  c.fy_px = Positive(r, "fy_px");
  c.cx_px = r.Number("cx_px");
  c.cy_px = r.Number("cy_px");
  c.k1 = r.OptionalNumber("k1").value_or(0.0);
  c.k2 = r.OptionalNumber("k2").value_or(0.0);
}

// The OpenCV form: world-to-camera rotation (Rodrigues vector) and translation.
void ReadOpenCvExtrinsics(const io::TomlReader& r, PinholeCamera& c) {
  const auto rv = NumberArray(r, "rotation_rodrigues", 3, "[rx, ry, rz] in radians");
  const auto tv = NumberArray(r, "translation_mm", 3, "[tx, ty, tz] in mm");
  c.rotation = RotationFromRodrigues(Eigen::Vector3d(rv[0], rv[1], rv[2]));
  c.translation_mm = Eigen::Vector3d(tv[0], tv[1], tv[2]);
}

// The overhead form: a camera looking straight down from a position, turned by a yaw.
void ReadOverheadExtrinsics(const io::TomlReader& r, PinholeCamera& c) {
  const auto p = NumberArray(r, "camera_position_mm", 3, "[x, y, z] in mm");
  const double yaw = r.OptionalNumber("yaw_deg").value_or(0.0) * std::numbers::pi / 180.0;
  // Camera axes in world coordinates: image right, image down, optical axis (straight down).
  Eigen::Matrix3d camera_to_world;
  camera_to_world.col(0) = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0.0);
  camera_to_world.col(1) = Eigen::Vector3d(std::sin(yaw), -std::cos(yaw), 0.0);
  camera_to_world.col(2) = Eigen::Vector3d(0.0, 0.0, -1.0);
  c.rotation = camera_to_world.transpose();
  c.translation_mm = -c.rotation * Eigen::Vector3d(p[0], p[1], p[2]);
}

void ReadExtrinsics(const io::TomlReader& r, PinholeCamera& c) {
  const bool opencv = r.Has("rotation_rodrigues") || r.Has("translation_mm");
  const bool overhead = r.Has("camera_position_mm") || r.Has("yaw_deg");
  if (opencv == overhead) {
    r.Fail(opencv ? "camera_position_mm" : "fx_px",
           "[pinhole] needs exactly one form of extrinsics; expected rotation_rodrigues and "
           "translation_mm, or camera_position_mm and yaw_deg");
  }
  if (opencv) {
    ReadOpenCvExtrinsics(r, c);
  } else {
    ReadOverheadExtrinsics(r, c);
  }
}

// The [pinhole] table of a model = "pinhole" file.
PinholeCamera ReadPinhole(const toml::table& root, const io::TomlReader& top,
                          const std::string& name) {
  const toml::table* t = root["pinhole"].as_table();
  if (t == nullptr)
    top.Fail("pinhole",
             "model = \"pinhole\" needs a [pinhole] table; expected fx_px, fy_px, cx_px, cy_px "
             "and extrinsics");
  const io::TomlReader r(*t, name, "[pinhole]");
  r.CheckKeys({"fx_px", "fy_px", "cx_px", "cy_px", "k1", "k2", "rotation_rodrigues",
               "translation_mm", "camera_position_mm", "yaw_deg"});
  PinholeCamera c;
  ReadIntrinsics(r, c);
  ReadExtrinsics(r, c);
  io::ThrowFirstProblemAt(root, name, Check(c));
  return c;
}

// A 3x3 array of numbers, or nullopt when `node` is absent or any other shape.
std::optional<Eigen::Matrix3d> Matrix3(const toml::node* node) {
  const toml::array* rows = node ? node->as_array() : nullptr;
  if (rows == nullptr || rows->size() != 3) return std::nullopt;
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (size_t row = 0; row < 3; ++row) {
    const toml::array* cols = (*rows)[row].as_array();
    if (cols == nullptr || cols->size() != 3) return std::nullopt;
    for (size_t col = 0; col < 3; ++col) {
      const auto v = FiniteNumber((*cols)[col]);
      if (!v) return std::nullopt;
      m(row, col) = *v;
    }
  }
  return m;
}

// One [[homography]] table (number i + 1 in messages), checked against the earlier ones.
PlaneHomography ReadHomography(const toml::node& node, size_t i, const std::string& name,
                               const std::vector<PlaneHomography>& earlier) {
  const toml::table* t = node.as_table();
  const std::string context = "[[homography]] " + std::to_string(i + 1);
  if (t == nullptr)
    throw InputError(io::LocOf(name, node),
                     context + " is not a table; expected [[homography]] tables");
  const io::TomlReader r(*t, name, context);
  r.CheckKeys({"height_mm", "matrix"});
  PlaneHomography h;
  h.height_mm = r.Number("height_mm");
  const auto matrix = Matrix3(t->get("matrix"));
  if (!matrix)
    r.Fail("matrix", "matrix in " + context + " is malformed; expected 3 rows of 3 numbers");
  h.pixel_to_world = *matrix;
  const double norm = h.pixel_to_world.norm();
  if (std::abs(h.pixel_to_world.determinant()) <= 1e-12 * norm * norm * norm) {
    r.Fail("matrix", "matrix in " + context + " is singular; expected an invertible homography");
  }
  for (const PlaneHomography& other : earlier) {
    if (std::abs(other.height_mm - h.height_mm) <= kHeightToleranceMm) {
      r.Fail("height_mm", "height_mm " + FormatNumber(h.height_mm) + " in " + context +
                              " repeats an earlier homography; expected one matrix per height");
    }
  }
  return h;
}

// The [[homography]] tables of a model = "homography" file.
std::vector<PlaneHomography> ReadHomographies(const toml::table& root, const io::TomlReader& top,
                                              const std::string& name) {
  const toml::node* node = root.get("homography");
  const toml::array* list = node ? node->as_array() : nullptr;
  if (list == nullptr || list->empty()) {
    top.Fail("homography",
             "model = \"homography\" needs [[homography]] tables; expected height_mm and matrix");
  }
  std::vector<PlaneHomography> hs;
  for (size_t i = 0; i < list->size(); ++i) hs.push_back(ReadHomography((*list)[i], i, name, hs));
  return hs;
}

void ReadHeights(const toml::table& heights, const std::string& name, Calibration& cal) {
  const io::TomlReader r(heights, name, "[heights]");
  for (const auto& [key, node] : heights) {
    const double v = r.Number(key.str());
    if (key.str() == "default_mm") {
      cal.default_height_mm = v;
    } else {
      cal.class_height_mm[std::string(key.str())] = v;
    }
  }
}

// One [[residual]] table (number i + 1 in messages).
PlaneResidual ReadResidual(const toml::node& node, size_t i, const std::string& name,
                           const std::vector<PlaneResidual>& earlier) {
  const toml::table* t = node.as_table();
  const std::string context = "[[residual]] " + std::to_string(i + 1);
  if (t == nullptr)
    throw InputError(io::LocOf(name, node),
                     context + " is not a table; expected [[residual]] tables");
  const io::TomlReader r(*t, name, context);
  r.CheckKeys({"height_mm", "rms_mm", "worst_mm", "measured"});
  PlaneResidual p;
  p.height_mm = r.Number("height_mm");
  p.rms_mm = r.Number("rms_mm");
  p.worst_mm = r.OptionalNumber("worst_mm").value_or(p.rms_mm);
  p.measured = r.OptionalBool("measured").value_or(true);
  if (p.rms_mm < 0.0) {
    r.Fail("rms_mm", "rms_mm is " + FormatNumber(p.rms_mm) + " in " + context +
                         "; expected a residual >= 0 (mm)");
  }
  if (p.worst_mm < p.rms_mm) {
    r.Fail("worst_mm", "worst_mm is " + FormatNumber(p.worst_mm) + " in " + context +
                           "; expected at least rms_mm (" + FormatNumber(p.rms_mm) + ")");
  }
  for (const PlaneResidual& other : earlier) {
    if (std::abs(other.height_mm - p.height_mm) <= kHeightToleranceMm) {
      r.Fail("height_mm", "height_mm " + FormatNumber(p.height_mm) + " in " + context +
                              " repeats an earlier residual; expected one per height");
    }
  }
  return p;
}

std::vector<PlaneResidual> ReadResiduals(const toml::table& root, const io::TomlReader& top,
                                         const std::string& name) {
  std::vector<PlaneResidual> out;
  const toml::node* node = root.get("residual");
  if (node == nullptr) return out;
  const toml::array* list = node->as_array();
  if (list == nullptr) {
    top.Fail("residual", "residual is not an array of tables; expected [[residual]] tables");
  }
  for (size_t i = 0; i < list->size(); ++i) out.push_back(ReadResidual((*list)[i], i, name, out));
  std::sort(out.begin(), out.end(), [](const PlaneResidual& a, const PlaneResidual& b) {
    return a.height_mm < b.height_mm;
  });
  return out;
}

}  // namespace

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

Calibration ParseCalibration(std::string_view text, const std::string& name) {
  const toml::table root = io::ParseTomlText(text, name);
  const io::TomlReader top(root, name);
  top.CheckKeys({"model", "image_size_px", "pinhole", "homography", "heights", "residual"});
  Calibration cal;
  cal.source = name;
  if (top.Has("image_size_px")) ReadImageSize(top, cal);
  const std::string model = top.String("model");
  if (model == "pinhole") {
    cal.camera = CameraModel::Pinhole(ReadPinhole(root, top, name));
  } else if (model == "homography") {
    cal.camera = CameraModel::Homographies(ReadHomographies(root, top, name));
  } else {
    top.Fail("model", "model is \"" + model + "\"; expected \"pinhole\" or \"homography\"");
  }
  if (const toml::table* t = root["heights"].as_table()) ReadHeights(*t, name, cal);
  cal.residuals = ReadResiduals(root, top, name);
  return cal;
}

Calibration LoadCalibration(const std::string& path) {
  return ParseCalibration(io::ReadTextFile(path, "calibration TOML file"), path);
}

}  // namespace patlab::vision
