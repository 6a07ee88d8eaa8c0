// The cross-validated mapping error (CalibrationFit::heldout_rms_mm) against the truth: random
// SSL cameras see the 2009 field's points, lines and arcs with Gaussian pixel noise; the
// held-out estimate must agree with the true error of a point the fit never saw -- the fitted
// camera at measured (noisy) pixels against the true camera, over a grid of the image pixels that
// show the field -- where the in-sample rms_mm understates it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <numbers>

#include "../test_util.h"
#include "patlab/calib/calibrate.h"
#include "patlab/core/format.h"
#include "patlab/core/rng.h"
#include "patlab/formats/field_file.h"

namespace patlab::calib {
namespace {

using testing::kFrameHeight, testing::kFrameWidth;

Field ShippedSsl2009() {
  return formats::LoadField(std::string(PATLAB_SOURCE_DIR) + "/experiments/fields/ssl-2009.toml");
}

// A camera over one half of the field, 3-4.5 m up, looking down within 12 deg, barrel distortion.
camera::PinholeCamera HalfFieldCamera(RandomStream& rng) {
  camera::PinholeCamera c;
  const double height = rng.Uniform(3000.0, 4500.0);
  c.fx_px = c.fy_px = height * rng.Uniform(0.16, 0.2);
  c.cx_px = 389.5 + rng.Uniform(-15.0, 15.0);
  c.cy_px = 289.5 + rng.Uniform(-15.0, 15.0);
  c.k1 = rng.Uniform(-0.3, -0.05);
  const double side = rng.Uniform() < 0.5 ? -1.0 : 1.0;
  const double yaw = side * std::numbers::pi / 2 + rng.Uniform(-0.2, 0.2);
  const double tilt = rng.Uniform(0.0, 12.0) * std::numbers::pi / 180.0;
  const double axis = rng.Uniform(0.0, 2 * std::numbers::pi);
  Eigen::Matrix3d down;
  down.col(0) = Eigen::Vector3d(std::cos(yaw), std::sin(yaw), 0);
  down.col(1) = Eigen::Vector3d(std::sin(yaw), -std::cos(yaw), 0);
  down.col(2) = Eigen::Vector3d(0, 0, -1);
  const Eigen::Matrix3d camera_to_world =
      Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0))
          .toRotationMatrix() *
      down;
  const Eigen::Vector3d centre(side * rng.Uniform(1300, 1750), rng.Uniform(-200, 200), height);
  c.rotation = camera_to_world.transpose();
  c.translation_mm = -c.rotation * centre;
  return c;
}

std::optional<Vec2> ObserveOnTheFloor(const camera::CameraModel& cam, const Vec2& world,
                                      double noise_px, RandomStream& rng) {
  const auto px = cam.WorldToPixel(world, 0.0);
  if (!px || px->x() < 2 || px->y() < 2 || px->x() > kFrameWidth - 3 || px->y() > kFrameHeight - 3)
    return std::nullopt;
  const Vec2 noisy = *px + noise_px * Vec2(rng.Normal(), rng.Normal());
  if (!cam.PixelToWorld(noisy, 0.0)) return std::nullopt;
  return noisy;
}

CalibrationInput Observations(const Field& field, const camera::CameraModel& cam, double noise_px,
                              RandomStream& rng) {
  CalibrationInput in;
  in.image_width_px = kFrameWidth;
  in.image_height_px = kFrameHeight;
  in.loc = FileLoc{"synthetic", 0};
  for (const FieldPoint& p : field.points)
    if (const auto px = ObserveOnTheFloor(cam, p.at_mm, noise_px, rng))
      in.points.push_back({p.name, *px, p.at_mm, 0.0, {}});
  for (const FieldLine& l : field.lines) {
    LineObservation o{l.name, l.from_mm, l.to_mm, 0.0, {}, {}};
    for (int k = 0; k <= 40; ++k)
      if (const auto px =
              ObserveOnTheFloor(cam, l.from_mm + (k / 40.0) * (l.to_mm - l.from_mm), noise_px, rng))
        o.pixels.push_back(*px);
    if (o.pixels.size() >= 2) in.lines.push_back(o);
  }
  for (const FieldCircle& c : field.circles) {
    CircleObservation o{c.name, c.centre_mm, c.radius_mm, 0.0, {}, {}};
    for (int k = 0; k <= 24; ++k) {  // along the arc's own extent
      const double deg = c.from_deg + (c.to_deg - c.from_deg) * k / 24.0;
      if (const auto px = ObserveOnTheFloor(cam, c.PointAt(deg), noise_px, rng))
        o.pixels.push_back(*px);
    }
    if (o.pixels.size() >= 2) in.circles.push_back(o);
  }
  return in;
}

// The true error of a point the fit never saw, as a measured point has it: over a 10 px grid of
// the pixels that show the field and its 250 mm boundary, the RMS distance (mm) on the floor
// between where the fitted camera puts the pixel measured with `noise_px` of Gaussian noise and
// where the true camera puts the pixel itself. `noise_px` = 0: the cameras' mappings compared.
double TrueError(const camera::CameraModel& fitted, const camera::CameraModel& truth,
                 const Field& field, double noise_px, RandomStream& rng) {
  double sum2 = 0.0;
  int n = 0;
  for (int v = 5; v < kFrameHeight; v += 10) {
    for (int u = 5; u < kFrameWidth; u += 10) {
      const auto t = truth.PixelToWorld(Vec2(u, v), 0.0);
      if (!t || std::abs(t->x()) > field.length_mm / 2 + 250 ||
          std::abs(t->y()) > field.width_mm / 2 + 250)
        continue;
      const Vec2 measured = Vec2(u, v) + noise_px * Vec2(rng.Normal(), rng.Normal());
      const auto f = fitted.PixelToWorld(measured, 0.0);
      if (!f) return std::numeric_limits<double>::infinity();
      sum2 += (*f - *t).squaredNorm();
      ++n;
    }
  }
  return std::sqrt(sum2 / n);
}

TEST(CalibrateHoldout, HeldOutErrorAgreesWithTheTrueMappingError) {
  const Field field = ShippedSsl2009();
  int compared = 0;
  double worst_ratio = 1.0, in_sample_ratio = 0.0;
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    RandomStream rng(seed, 7, 0);
    const camera::CameraModel truth = camera::CameraModel::Pinhole(HalfFieldCamera(rng));
    const double noise_px = 0.5;
    CalibrationInput in = Observations(field, truth, noise_px, rng);
    const camera::PinholeCamera& t = truth.pinhole();
    const auto fold = DistortionFoldRadius(t.k1, t.k2);
    if (in.points.size() < 6 || (fold && *fold < std::hypot(400 / t.fx_px, 300 / t.fy_px)))
      continue;  // too few points, or a true lens that folds inside the image
    CalibrationFit fit;
    try {
      fit = FitCamera(in);
    } catch (const InputError& e) {
      // A draw whose visible points give no start (fewer than four in general position at the
      // start's tolerance, a knife edge that another compiler's last bits can tip) says nothing
      // about the held-out error: the next seed is drawn, as for too few points above.
      if (std::string(e.what()).find("three on a line") == std::string::npos) throw;
      continue;
    }
    ASSERT_EQ(fit.heldout_folds, 5);
    ASSERT_EQ(fit.planes.size(), 1u);
    EXPECT_EQ(fit.planes[0].heldout_count, fit.planes[0].count);
    const camera::CameraModel fitted = camera::CameraModel::Pinhole(fit.camera);
    const double truth_mm = TrueError(fitted, truth, field, noise_px, rng);
    const double mapping_mm = TrueError(fitted, truth, field, 0.0, rng);
    const double ratio = fit.heldout_rms_mm / truth_mm;
    std::cout << "seed " << seed << ": true " << FormatFixed(truth_mm, 3)
              << " mm (the mapping alone " << FormatFixed(mapping_mm, 3) << " mm), held-out "
              << FormatFixed(fit.heldout_rms_mm, 3) << " mm, in-sample "
              << FormatFixed(fit.planes[0].rms_mm, 3) << " mm\n";
    EXPECT_GT(ratio, 1 / 1.5);
    EXPECT_LT(ratio, 1.5);
    // The in-sample residual, which the fit minimised, understates it (by a third here).
    EXPECT_GT(fit.heldout_rms_mm, 1.2 * fit.planes[0].rms_mm);
    worst_ratio = std::max({worst_ratio, ratio, 1 / ratio});
    in_sample_ratio += fit.planes[0].rms_mm / truth_mm;
    ++compared;
  }
  EXPECT_GE(compared, 5);
  std::cout << "worst ratio " << FormatFixed(worst_ratio, 3) << ", mean in-sample / true "
            << FormatFixed(in_sample_ratio / compared, 3) << "\n";
}

}  // namespace
}  // namespace patlab::calib
