// calibrate.h's refusal of folded or unphysical fits (UnphysicalFitReason, DistortionFoldRadius):
// one fit built to have each fault, the numbers of each message worked out here by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "../test_util.h"
#include "patlab/calib/calibrate.h"

namespace patlab::calib {
namespace {

using testing::kFrameHeight, testing::kFrameWidth;

// A camera that passes every check: f = 600 px, principal point at the image centre, mild barrel
// distortion, 4 m over the field looking down.
CalibrationFit PhysicalFit() {
  CalibrationFit fit;
  camera::PinholeCamera& c = fit.camera;
  c.fx_px = c.fy_px = 600.0;
  c.cx_px = 390.0;
  c.cy_px = 290.0;
  c.k1 = -0.2;
  c.rotation = Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal());
  c.translation_mm = Eigen::Vector3d(0, 0, 4000);
  fit.rms_px = 0.3;
  fit.worst_px = 0.9;
  PlaneResiduals plane;
  plane.count = 10;
  plane.rms_px = 0.3;
  plane.rms_mm = 2.0;
  fit.planes.push_back(plane);
  return fit;
}

std::string Reason(const CalibrationFit& fit) {
  return UnphysicalFitReason(fit, kFrameWidth, kFrameHeight);
}

TEST(CalibrateChecks, DistortionFoldRadiusIsWhereTheMapStopsIncreasing) {
  // k1 = -1/3: d/dr r (1 - r^2 / 3) = 1 - r^2 = 0 at r = 1, where the image radius is 2/3.
  EXPECT_NEAR(*DistortionFoldRadius(-1.0 / 3.0, 0.0), 2.0 / 3.0, 1e-12);
  // k1 = 0, k2 = -0.2: 1 - r^4 = 0 at r = 1, image radius 0.8.
  EXPECT_NEAR(*DistortionFoldRadius(0.0, -0.2), 0.8, 1e-12);
  // k1 = -0.6, k2 = 0.1: 1 - 1.8 u + 0.5 u^2 = 0 at u = 1.8 - sqrt(1.24) = 0.686454...
  const double u = 1.8 - std::sqrt(1.24);
  EXPECT_NEAR(*DistortionFoldRadius(-0.6, 0.1), std::sqrt(u) * (1 - 0.6 * u + 0.1 * u * u), 1e-12);
  // Pincushion, no distortion, and barrel that a large k2 turns back up never fold.
  EXPECT_FALSE(DistortionFoldRadius(0.1, 0.0).has_value());
  EXPECT_FALSE(DistortionFoldRadius(0.0, 0.0).has_value());
  EXPECT_FALSE(DistortionFoldRadius(-0.3, 0.1).has_value());  // 1 - 0.9 u + 0.5 u^2 > 0
}

TEST(CalibrateChecks, APhysicalFitPasses) { EXPECT_EQ(Reason(PhysicalFit()), ""); }

TEST(CalibrateChecks, DistortionThatFoldsInsideTheImageIsRefused) {
  CalibrationFit fit = PhysicalFit();
  fit.camera.k1 = -0.6;
  // Fold: 1 - 1.8 r^2 = 0 at r = 0.745, image radius 0.745 (1 - 0.6 / 1.8) = 0.497 (298 px at
  // f = 600); the image's corner is at hypot(390, 290) / 600 = 0.810.
  EXPECT_EQ(Reason(fit),
            "the fitted camera is not usable: its distortion folds at r = 0.497 (radius 298 px) "
            "inside the image's 0.81: k1 = -0.6, k2 = 0; expected a lens that shows every pixel "
            "once (observe lines and points near the image edge, or hold k1 and k2 with [fit] fix "
            "= [\"k1\", \"k2\", ...])");
  // The same lens with a longer focal length folds beyond the image: accepted.
  fit.camera.fx_px = fit.camera.fy_px = 1000.0;  // corner at 0.486 < 0.497
  EXPECT_EQ(Reason(fit), "");
}

TEST(CalibrateChecks, NumbersThatAreNotFiniteAreRefused) {
  CalibrationFit fit = PhysicalFit();
  fit.camera.k2 = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Reason(fit),
            "the fitted camera is not usable: k2 = nan is not a finite number; expected "
            "observations a pinhole camera explains (check for mis-clicked pixels, or hold k1 and "
            "k2 with [fit] fix)");
  fit = PhysicalFit();
  fit.rms_px = std::numeric_limits<double>::infinity();
  EXPECT_EQ(Reason(fit),
            "the fitted camera is not usable: rms_px = inf is not a finite number (an observed "
            "pixel the camera cannot project or map back); expected observations a pinhole camera "
            "explains (check for mis-clicked pixels)");
  fit = PhysicalFit();
  fit.planes[0].rms_mm = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Reason(fit).substr(0, 89),
            "the fitted camera is not usable: rms_mm = nan on the plane at 0 mm is not a finite "
            "number");
}

TEST(CalibrateChecks, APrincipalPointOutsideTheImageIsRefused) {
  CalibrationFit fit = PhysicalFit();
  fit.camera.k1 = 0.0;  // no fold: the principal point alone is wrong
  fit.camera.cy_px = 612.4;
  EXPECT_EQ(
      Reason(fit),
      "the fitted camera is not usable: its principal point (390.0, 612.4) px lies outside the "
      "780 x 580 px image; expected it inside the image (a lens's axis meets its sensor; "
      "hold it with [fit] fix = [\"principal_point\", ...])");
  fit.camera.cy_px = 580.0;  // on the edge: inside
  EXPECT_EQ(Reason(fit), "");
}

TEST(CalibrateChecks, AFocalLengthOutsidePhysicalBoundsIsRefused) {
  CalibrationFit fit = PhysicalFit();
  fit.camera.fx_px = fit.camera.fy_px = 20000.0;  // 25.6 image widths: a 2.2 deg field of view
  EXPECT_EQ(Reason(fit),
            "the fitted camera is not usable: its focal length 20000 px is 25.6 image widths; "
            "expected 0.2 to 20 (a field of view between 136 and 2.9 degrees: a camera over a "
            "field sees more than a robot and less than a half sphere); give [fit] focal_px or "
            "camera_height_mm");
  fit.camera.k1 = 0.0;
  fit.camera.fx_px = fit.camera.fy_px = 150.0;  // 0.192 image widths
  EXPECT_EQ(Reason(fit).substr(0, 78),
            "the fitted camera is not usable: its focal length 150 px is 0.192 image widths");
}

TEST(CalibrateChecks, APixelAspectFarFromSquareIsRefused) {
  CalibrationFit fit = PhysicalFit();
  fit.camera.fy_px = 1500.0;
  EXPECT_EQ(Reason(fit),
            "the fitted camera is not usable: its pixel aspect fy / fx = 2.5 (fx 600 px, fy 1500 "
            "px); expected 0.5 to 2 (sensor pixels are nearly square; hold it with [fit] fix = "
            "[\"aspect\", ...])");
}

}  // namespace
}  // namespace patlab::calib
