// The automatic calibration's horizon check (calib::internal::AboveHorizon): a camera over the
// field sees the floor in every pixel, so a fitted camera whose horizon crosses the image is not
// the frame's camera. Checked against every pixel of the image, ray by ray.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>

#include "../test_util.h"
#include "patlab/calib/auto_calibrate_internal.h"

namespace patlab::calib {
namespace {

using testing::kFrameHeight, testing::kFrameWidth;

// A camera `height_mm` over the floor point (0, 0), tilted `tilt_deg` from straight down towards
// the heading `heading_deg`, with radial distortion k1.
camera::PinholeCamera TiltedCamera(double height_mm, double tilt_deg, double heading_deg,
                                   double focal_px, double k1) {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = focal_px;
  c.cx_px = 0.5 * (kFrameWidth - 1);
  c.cy_px = 0.5 * (kFrameHeight - 1);
  c.k1 = k1;
  const double deg = std::numbers::pi / 180.0;
  // World to camera: straight down (camera z along world -z), then tilted about a floor axis.
  const Eigen::Matrix3d down = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const Eigen::Vector3d tilt_axis(std::cos(heading_deg * deg), std::sin(heading_deg * deg), 0.0);
  const Eigen::Matrix3d to_camera =
      down * Eigen::AngleAxisd(tilt_deg * deg, tilt_axis).toRotationMatrix().transpose();
  c.rotation = to_camera;
  c.translation_mm = -c.rotation * Eigen::Vector3d(0.0, 0.0, height_mm);
  return c;
}

// Whether the ray through `pixel` points below the horizon, by the camera's own geometry: its
// undistorted direction (the distortion solved by bisection, independently of
// CameraModel::PixelToWorld's Newton steps) turned into the world descends.
bool Descends(const camera::PinholeCamera& c, double u, double v) {
  const double xd = (u - c.cx_px) / c.fx_px, yd = (v - c.cy_px) / c.fy_px;
  const double rd = std::hypot(xd, yd);
  // r (1 + k1 r^2) = rd: with barrel distortion r >= rd, and r below the fold, where the
  // left side stops increasing (r^2 = -1 / (3 k1)).
  double lo = 0.0, hi = rd;
  if (c.k1 < 0.0) hi = std::sqrt(-1.0 / (3.0 * c.k1));
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (mid * (1.0 + c.k1 * mid * mid) < rd ? lo : hi) = mid;
  }
  const double scale = rd > 0.0 ? lo / rd : 1.0;
  const Eigen::Vector3d ray = c.rotation.transpose() * Eigen::Vector3d(xd * scale, yd * scale, 1);
  return ray.z() < 0.0;
}

// The image's pixels, every pixel of its border and 3 px apart inside: whether one of them sees
// above the horizon.
bool AnyPixelAboveHorizon(const camera::PinholeCamera& c) {
  for (int u = 0; u < kFrameWidth; ++u) {
    if (!Descends(c, u, 0) || !Descends(c, u, kFrameHeight - 1)) return true;
  }
  for (int v = 0; v < kFrameHeight; ++v) {
    if (!Descends(c, 0, v) || !Descends(c, kFrameWidth - 1, v)) return true;
  }
  for (int v = 1; v < kFrameHeight - 1; v += 3) {
    for (int u = 1; u < kFrameWidth - 1; u += 3) {
      if (!Descends(c, u, v)) return true;
    }
  }
  return false;
}

TEST(AutoCalibrateHorizon, ACameraLookingDownSeesTheFloorInEveryPixel) {
  const camera::PinholeCamera c = TiltedCamera(4000.0, 3.0, 30.0, 550.0, -0.05);
  EXPECT_EQ(internal::AboveHorizon(c, kFrameWidth, kFrameHeight), std::nullopt);
  EXPECT_FALSE(AnyPixelAboveHorizon(c));
}

// Fresh rendered seed 196's wrong camera: 42 mm up, tilted 86.4 deg, f 4076 px, k1 -5.05. Its
// marks piled near the horizon explained more line than the true camera.
TEST(AutoCalibrateHorizon, ACameraLyingNearTheFloorSeesAboveTheHorizon) {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = 4075.9389663221295;
  c.cx_px = 372.24205763453256;
  c.cy_px = 284.85205349034055;
  c.k1 = -5.049320808304527;
  c.rotation =
      Eigen::AngleAxisd(
          Eigen::Vector3d(1.4242167540720934, 0.9271619366895292, 0.8205378802232097).norm(),
          Eigen::Vector3d(1.4242167540720934, 0.9271619366895292, 0.8205378802232097).normalized())
          .toRotationMatrix();
  c.translation_mm = Eigen::Vector3d(-1385.7111050680876, -2704.0574851003175, -304.1507406464363);
  ASSERT_NEAR((-c.rotation.transpose() * c.translation_mm).z(), 41.84, 0.01);
  const std::optional<Vec2> sky = internal::AboveHorizon(c, kFrameWidth, kFrameHeight);
  ASSERT_TRUE(sky.has_value());
  EXPECT_FALSE(Descends(c, sky->x(), sky->y())) << sky->transpose();
  EXPECT_TRUE(AnyPixelAboveHorizon(c));
}

// Pincushion distortion bulges the image's edges beyond their corners (before distortion): a
// horizon can cut off the middle of an edge with every corner below it.
TEST(AutoCalibrateHorizon, AHorizonAcrossTheMiddleOfAnEdgeOnly) {
  const double mid_u = 0.5 * (kFrameWidth - 1);
  const Vec2 corners[] = {Vec2(0, 0), Vec2(kFrameWidth - 1, 0), Vec2(0, kFrameHeight - 1),
                          Vec2(kFrameWidth - 1, kFrameHeight - 1)};
  int found = 0;
  for (const double heading : {0.0, 180.0}) {
    for (double tilt = 30.0; tilt < 100.0; tilt += 0.01) {
      const camera::PinholeCamera c = TiltedCamera(3000.0, tilt, heading, 400.0, 0.3);
      bool corners_below = true;
      for (const Vec2& p : corners) corners_below = corners_below && Descends(c, p.x(), p.y());
      if (!corners_below || (Descends(c, mid_u, 0) && Descends(c, mid_u, kFrameHeight - 1)))
        continue;
      ++found;
      const std::optional<Vec2> sky = internal::AboveHorizon(c, kFrameWidth, kFrameHeight);
      ASSERT_TRUE(sky.has_value()) << "heading " << heading << ", tilt " << tilt;
      EXPECT_FALSE(Descends(c, sky->x(), sky->y()));
      break;
    }
  }
  EXPECT_EQ(found, 2);  // one camera for each heading: the top edge and the bottom edge
}

// Random cameras from straight down to past the horizon, every heading, with pincushion
// distortion (whose image edges bulge beyond their corners, so the corners alone do not decide)
// or barrel distortion short of folding inside the image (calibrate.h refuses a fit that folds):
// the border check agrees with the image's pixels' rays, and the pixel it names sees above the
// horizon.
TEST(AutoCalibrateHorizon, TheBorderDecidesAsEveryPixelDoes) {
  std::mt19937 rng(196);
  std::uniform_real_distribution<double> tilt(0.0, 100.0), heading(0.0, 360.0),
      focal(300.0, 1500.0), k1(-0.3, 0.3), height(500.0, 6000.0);
  int above = 0, below = 0;
  for (int trial = 0; trial < 40; ++trial) {
    camera::PinholeCamera c;
    do {
      c = TiltedCamera(height(rng), tilt(rng), heading(rng), focal(rng), k1(rng));
    } while (DistortionFoldRadius(c.k1, c.k2).value_or(INFINITY) <
             std::hypot(0.5 * kFrameWidth, 0.5 * kFrameHeight) / c.fx_px);
    const std::optional<Vec2> sky = internal::AboveHorizon(c, kFrameWidth, kFrameHeight);
    const bool brute = AnyPixelAboveHorizon(c);
    EXPECT_EQ(sky.has_value(), brute) << "trial " << trial;
    if (sky) {
      EXPECT_FALSE(Descends(c, sky->x(), sky->y())) << "trial " << trial;
    }
    ++(brute ? above : below);
  }
  // Both kinds were drawn.
  EXPECT_GT(above, 10);
  EXPECT_GT(below, 10);
}

}  // namespace
}  // namespace patlab::calib
