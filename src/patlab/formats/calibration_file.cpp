#include "patlab/formats/calibration_file.h"

#include <Eigen/LU>
#include <cmath>
#include <optional>

#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/toml_util.h"

namespace patlab::formats {

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

void ReadImageSize(const io::TomlReader& top, camera::Calibration& cal) {
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

void ReadIntrinsics(const io::TomlReader& r, camera::PinholeCamera& c) {
  c.fx_px = Positive(r, "fx_px");
  c.fy_px = Positive(r, "fy_px");
  c.cx_px = r.Number("cx_px");
  c.cy_px = r.Number("cy_px");
  c.k1 = r.OptionalNumber("k1").value_or(0.0);
  c.k2 = r.OptionalNumber("k2").value_or(0.0);
}

// The OpenCV form: world-to-camera rotation (Rodrigues vector) and translation.
void ReadOpenCvExtrinsics(const io::TomlReader& r, camera::PinholeCamera& c) {
  const auto rv = NumberArray(r, "rotation_rodrigues", 3, "[rx, ry, rz] in radians");
  const auto tv = NumberArray(r, "translation_mm", 3, "[tx, ty, tz] in mm");
  c.rotation = camera::RotationFromRodrigues(Eigen::Vector3d(rv[0], rv[1], rv[2]));
  c.translation_mm = Eigen::Vector3d(tv[0], tv[1], tv[2]);
}

// The overhead form: a camera looking straight down from a position, turned by a yaw.
void ReadOverheadExtrinsics(const io::TomlReader& r, camera::PinholeCamera& c) {
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

void ReadExtrinsics(const io::TomlReader& r, camera::PinholeCamera& c) {
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
camera::PinholeCamera ReadPinhole(const toml::table& root, const io::TomlReader& top,
                                  const std::string& name) {
  const toml::table* t = root["pinhole"].as_table();
  if (t == nullptr)
    top.Fail("pinhole",
             "model = \"pinhole\" needs a [pinhole] table; expected fx_px, fy_px, cx_px, cy_px "
             "and extrinsics");
  const io::TomlReader r(*t, name, "[pinhole]");
  r.CheckKeys({"fx_px", "fy_px", "cx_px", "cy_px", "k1", "k2", "rotation_rodrigues",
               "translation_mm", "camera_position_mm", "yaw_deg"});
  camera::PinholeCamera c;
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
camera::PlaneHomography ReadHomography(const toml::node& node, size_t i, const std::string& name,
                                       const std::vector<camera::PlaneHomography>& earlier) {
  const toml::table* t = node.as_table();
  const std::string context = "[[homography]] " + std::to_string(i + 1);
  if (t == nullptr)
    throw InputError(io::LocOf(name, node),
                     context + " is not a table; expected [[homography]] tables");
  const io::TomlReader r(*t, name, context);
  r.CheckKeys({"height_mm", "matrix"});
  camera::PlaneHomography h;
  h.height_mm = r.Number("height_mm");
  const auto matrix = Matrix3(t->get("matrix"));
  if (!matrix)
    r.Fail("matrix", "matrix in " + context + " is malformed; expected 3 rows of 3 numbers");
  h.pixel_to_world = *matrix;
  const double norm = h.pixel_to_world.norm();
  if (std::abs(h.pixel_to_world.determinant()) <= 1e-12 * norm * norm * norm) {
    r.Fail("matrix", "matrix in " + context + " is singular; expected an invertible homography");
  }
  for (const camera::PlaneHomography& other : earlier) {
    if (std::abs(other.height_mm - h.height_mm) <= camera::kHeightToleranceMm) {
      r.Fail("height_mm", "height_mm " + FormatNumber(h.height_mm) + " in " + context +
                              " repeats an earlier homography; expected one matrix per height");
    }
  }
  return h;
}

// The [[homography]] tables of a model = "homography" file.
std::vector<camera::PlaneHomography> ReadHomographies(const toml::table& root,
                                                      const io::TomlReader& top,
                                                      const std::string& name) {
  const toml::node* node = root.get("homography");
  const toml::array* list = node ? node->as_array() : nullptr;
  if (list == nullptr || list->empty()) {
    top.Fail("homography",
             "model = \"homography\" needs [[homography]] tables; expected height_mm and matrix");
  }
  std::vector<camera::PlaneHomography> hs;
  for (size_t i = 0; i < list->size(); ++i) hs.push_back(ReadHomography((*list)[i], i, name, hs));
  return hs;
}

void ReadHeights(const toml::table& heights, const std::string& name, camera::Calibration& cal) {
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
camera::PlaneResidual ReadResidual(const toml::node& node, size_t i, const std::string& name,
                                   const std::vector<camera::PlaneResidual>& earlier) {
  const toml::table* t = node.as_table();
  const std::string context = "[[residual]] " + std::to_string(i + 1);
  if (t == nullptr)
    throw InputError(io::LocOf(name, node),
                     context + " is not a table; expected [[residual]] tables");
  const io::TomlReader r(*t, name, context);
  r.CheckKeys({"height_mm", "rms_mm", "worst_mm", "measured"});
  camera::PlaneResidual p;
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
  for (const camera::PlaneResidual& other : earlier) {
    if (std::abs(other.height_mm - p.height_mm) <= camera::kHeightToleranceMm) {
      r.Fail("height_mm", "height_mm " + FormatNumber(p.height_mm) + " in " + context +
                              " repeats an earlier residual; expected one per height");
    }
  }
  return p;
}

std::vector<camera::PlaneResidual> ReadResiduals(const toml::table& root, const io::TomlReader& top,
                                                 const std::string& name) {
  std::vector<camera::PlaneResidual> out;
  const toml::node* node = root.get("residual");
  if (node == nullptr) return out;
  const toml::array* list = node->as_array();
  if (list == nullptr) {
    top.Fail("residual", "residual is not an array of tables; expected [[residual]] tables");
  }
  for (size_t i = 0; i < list->size(); ++i) out.push_back(ReadResidual((*list)[i], i, name, out));
  std::sort(out.begin(), out.end(),
            [](const camera::PlaneResidual& a, const camera::PlaneResidual& b) {
              return a.height_mm < b.height_mm;
            });
  return out;
}

}  // namespace

camera::Calibration ParseCalibration(std::string_view text, const std::string& name) {
  const toml::table root = io::ParseTomlText(text, name);
  const io::TomlReader top(root, name);
  top.CheckKeys({"model", "image_size_px", "pinhole", "homography", "heights", "residual"});
  camera::Calibration cal;
  cal.source = name;
  if (top.Has("image_size_px")) ReadImageSize(top, cal);
  const std::string model = top.String("model");
  if (model == "pinhole") {
    cal.camera = camera::CameraModel::Pinhole(ReadPinhole(root, top, name));
  } else if (model == "homography") {
    cal.camera = camera::CameraModel::Homographies(ReadHomographies(root, top, name));
  } else {
    top.Fail("model", "model is \"" + model + "\"; expected \"pinhole\" or \"homography\"");
  }
  if (const toml::table* t = root["heights"].as_table()) ReadHeights(*t, name, cal);
  cal.residuals = ReadResiduals(root, top, name);
  return cal;
}

camera::Calibration LoadCalibration(const std::string& path) {
  return ParseCalibration(io::ReadTextFile(path, "calibration TOML file"), path);
}

}  // namespace patlab::formats
