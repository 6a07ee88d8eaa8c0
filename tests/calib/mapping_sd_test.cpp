// The fitted camera's uncertainty over the floor it shows (MappingSdOver) against the analytic
// spread of a camera looking straight down: where the covariance moves only the camera's
// position, every floor point moves with it; where it moves only the focal length, a floor point
// at distance d from the axis moves by d se(f) / f.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "patlab/calib/calibrate.h"

namespace patlab::calib {
namespace {

constexpr int kSdWidth = 780, kSdHeight = 580;
constexpr double kSdCameraHeight = 4000.0, kSdFocal = 600.0;

// A camera 4 m over the field's centre looking straight down (image x along world x, image y
// along world -y), no distortion, with a covariance of zeros to fill in.
CalibrationFit StraightDown() {
  CalibrationFit fit;
  camera::PinholeCamera& c = fit.camera;
  c.fx_px = c.fy_px = kSdFocal;
  c.cx_px = 389.5;
  c.cy_px = 289.5;
  c.rotation = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
  fit.rotation_rodrigues = Eigen::Vector3d(std::numbers::pi, 0.0, 0.0);
  c.translation_mm = Eigen::Vector3d(0.0, 0.0, kSdCameraHeight);
  fit.covariance.fill(0.0);
  return fit;
}

double& Variance(CalibrationFit& fit, int parameter) {
  return fit.covariance[static_cast<size_t>(parameter * kCameraParameters + parameter)];
}

bool Everywhere(const Vec2&) { return true; }

TEST(MappingSdOver, ACameraPositionsSpreadMovesEveryFloorPointByIt) {
  CalibrationFit fit = StraightDown();
  Variance(fit, 9) = 3.0 * 3.0;  // translation x, mm^2
  Variance(fit, 10) = 4.0 * 4.0;
  EXPECT_NEAR(MappingSdOver(fit, kSdWidth, kSdHeight, 0.0, Everywhere, 10), 5.0, 1e-4);
  // On the robots' plane, 140 mm up, too: a shift of the camera shifts every plane alike.
  EXPECT_NEAR(MappingSdOver(fit, kSdWidth, kSdHeight, 140.0, Everywhere, 10), 5.0, 1e-4);
}

TEST(MappingSdOver, AFocalLengthsSpreadGrowsWithTheDistanceFromTheAxis) {
  CalibrationFit fit = StraightDown();
  const double se = 6.0;  // px
  Variance(fit, 0) = se * se;
  // Only the floor within 1 m of the axis: the pixels whose floor point is there, by hand.
  const auto near = [](const Vec2& p) { return p.norm() <= 1000.0; };
  const int step = 20;
  double sum2 = 0.0;
  int n = 0;
  for (int v = step / 2; v < kSdHeight; v += step) {
    for (int u = step / 2; u < kSdWidth; u += step) {
      const Vec2 floor(kSdCameraHeight * (u - 389.5) / kSdFocal,
                       -kSdCameraHeight * (v - 289.5) / kSdFocal);
      if (floor.norm() > 1000.0) continue;
      sum2 += floor.squaredNorm() * se * se / (kSdFocal * kSdFocal);
      ++n;
    }
  }
  ASSERT_GT(n, 50);
  EXPECT_NEAR(MappingSdOver(fit, kSdWidth, kSdHeight, 0.0, near, step), std::sqrt(sum2 / n), 1e-3);
}

TEST(MappingSdOver, IsUndeterminedWithoutACovarianceOrAPixelInside) {
  CalibrationFit fit = StraightDown();
  Variance(fit, 9) = 1.0;
  EXPECT_TRUE(std::isnan(MappingSdOver(
      fit, kSdWidth, kSdHeight, 0.0, [](const Vec2&) { return false; }, 10)));
  fit.covariance.fill(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(std::isnan(MappingSdOver(fit, kSdWidth, kSdHeight, 0.0, Everywhere, 10)));
}

}  // namespace
}  // namespace patlab::calib
