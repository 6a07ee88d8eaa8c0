// Stage 5 of the vision pipeline: from pixels to millimetres on a horizontal plane at a known
// height (the top of a pattern, or the centre of a ball). World frame: x, y on the floor in mm,
// z up; a plane at height h is z = h.
//
// Two models:
//  - pinhole: intrinsics fx, fy, cx, cy (px), radial distortion k1, k2 (Brown-Conrady, as in
//    OpenCV: x_d = x (1 + k1 r^2 + k2 r^4) on normalised coordinates), and extrinsics R, t with
//    X_camera = R X_world + t (OpenCV's rvec/tvec convention). Works for any plane height.
//  - homography: a 3x3 matrix H per plane height taking (u, v, 1) to (x, y, w) mm; for flat
//    scenes or when only the pattern tops matter. Heights with no matrix are refused.
#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/core/options.h"

namespace patlab::camera {

struct PinholeCamera {
  double fx_px = 1.0;  // focal length in pixels, > 0
  double fy_px = 1.0;
  double cx_px = 0.0;  // principal point
  double cy_px = 0.0;
  double k1 = 0.0;  // radial distortion, unitless
  double k2 = 0.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // world -> camera
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();
};

// The ranges a camera over a robot field can have, in one place (docs/architecture.md rule 4):
// radial distortion |k1|, |k2| <= 10 (real lenses: |k1| < 1), and the camera centre above the
// floor, at a height in (0, 100000] mm. Field names as the calibration file spells them
// ("pinhole.k1"; the height under "pinhole.camera_position_mm" or "pinhole.translation_mm").
inline constexpr double kMaxDistortion = 10.0;
inline constexpr double kMaxCameraHeightMm = 1e5;
std::vector<OptionsProblem> Check(const PinholeCamera& camera);

struct PlaneHomography {
  double height_mm = 0.0;
  Eigen::Matrix3d pixel_to_world = Eigen::Matrix3d::Identity();
};
// A homography serves the plane heights within this of its own (and a calibration file may hold
// one homography, and one residual, per height so far apart).
inline constexpr double kHeightToleranceMm = 0.5;

class CameraModel {
 public:
  static CameraModel Pinhole(const PinholeCamera& pinhole);
  static CameraModel Homographies(std::vector<PlaneHomography> homographies);

  bool is_pinhole() const { return is_pinhole_; }
  const PinholeCamera& pinhole() const { return pinhole_; }
  // Whether points on the plane at this height can be mapped (always for a pinhole camera).
  bool SupportsHeight(double height_mm) const;

  // The world point (mm) on the plane z = height_mm seen at `pixel`; nullopt when the ray misses
  // the plane (behind the camera, parallel) or lies outside the distortion model's valid range.
  std::optional<Vec2> PixelToWorld(const Vec2& pixel, double height_mm) const;
  // The pixel where world point (x, y, height_mm) appears; nullopt behind the camera or beyond
  // the fold of the distortion model (where PixelToWorld could not map it back).
  std::optional<Vec2> WorldToPixel(const Vec2& world_mm, double height_mm) const;
  // mm^2 of plane per px^2 of image around `pixel`: |det| of the Jacobian of PixelToWorld
  // (central differences, 0.5 px step). 0 when it cannot be evaluated.
  double AreaScale(const Vec2& pixel, double height_mm) const;

  // The same camera for its frames resized by `scale` (> 0) with corners kept: the resized
  // frame's pixel p sees what this one's (p + 0.5) / scale - 0.5 sees (image.h's pixel centres).
  // A pinhole's focal lengths and principal point scale, its distortion (on normalised
  // coordinates) stays; a homography gains the pixel change. Resized(1 / k) is the camera of
  // frames binned k x k (image.h's BinImage), Resized(k) takes such a camera back.
  CameraModel Resized(double scale) const;

 private:
  const PlaneHomography* FindHomography(double height_mm) const;
  bool is_pinhole_ = true;
  PinholeCamera pinhole_;
  std::vector<PlaneHomography> homographies_;
  std::vector<Eigen::Matrix3d> inverses_;
};

// Where a frame's pixel (centre) lies in the frame resized by `scale` with corners kept:
// scale (p + 0.5) - 0.5 (image.h's pixel centres; CameraModel::Resized, BinImage).
Vec2 ResizedPixel(const Vec2& pixel, double scale);

// The calibration's own position error on one plane, as `patlab calibrate` measured it (the
// calibration file's [[residual]] tables): the RMS and worst distance (mm) between where the
// fitted camera puts an observed pixel on the plane and where it truly is. `measured` is false
// for a height no observation lay on, where calibrate converted the pixel residuals to mm with
// the plane's scale instead.
struct PlaneResidual {
  double height_mm = 0.0;
  double rms_mm = 0.0;    // >= 0
  double worst_mm = 0.0;  // >= rms_mm
  bool measured = true;
};

// A calibration file: the camera model plus the plane height of each colour class.
struct Calibration {
  CameraModel camera = CameraModel::Pinhole(PinholeCamera{});
  double default_height_mm = 0.0;                 // plane height for classes not listed
  std::map<std::string, double> class_height_mm;  // class name -> plane height (mm)
  int image_width_px = 0;                         // 0 = any size; else frames must match
  int image_height_px = 0;
  std::string source;
  std::vector<PlaneResidual> residuals;  // by increasing height; empty = none recorded

  // The recorded RMS residual (mm) on the plane at `height_mm`: the row of that height (within
  // 0.5 mm), else the row of the nearest height; 0 when the file records none (old files).
  double ResidualRmsMm(double height_mm) const;

  // The calibration of the frames resized by `scale` (CameraModel::Resized), whose size is
  // width_px x height_px (0 x 0 when this one names none); heights and residuals (mm) stay.
  Calibration Resized(double scale, int width_px, int height_px) const;

  double HeightOf(const std::string& class_name) const {
    auto it = class_height_mm.find(class_name);
    return it == class_height_mm.end() ? default_height_mm : it->second;
  }
};

// Rodrigues vector (axis * angle, rad) -> rotation matrix.
Eigen::Matrix3d RotationFromRodrigues(const Eigen::Vector3d& rodrigues);

}  // namespace patlab::camera
