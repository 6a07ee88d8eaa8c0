// The field-line finder and the automatic field calibration on rendered frames: random known
// cameras (height, tilt, yaw, focal length, k1, principal point) over the SSL 2009 field, lines
// drawn by render/field_render.h with sensor noise; the fitted camera is compared with the true
// one on a pixel grid over the visible field.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/calib/auto_calibrate.h"
#include "patlab/calib/calibrate.h"
#include "patlab/calib/field_marks.h"
#include "patlab/core/rng.h"
#include "patlab/formats/field_file.h"
#include "patlab/render/camera_render.h"
#include "patlab/render/field_render.h"
#include "patlab/vision/field_lines.h"
#include "rendered_field.h"

namespace patlab::vision {
namespace {

calib::Field Ssl() {
  return formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2009.toml");
}

struct TrueCamera {
  double height_mm, tilt_rad, tilt_axis_rad, yaw_rad, focal_px, k1;
  Vec2 over_mm, principal_offset_px;
};

using patlab::testing::kFrameHeight, patlab::testing::kFrameWidth;

camera::Image Render(const camera::PinholeCamera& camera, uint64_t seed) {
  return rendered::RenderLines(Ssl(), camera, kFrameWidth, kFrameHeight, seed);
}

// Over the pixels that show the field's area (within its lines, 200 mm margin).
double MappingRmsMm(const camera::PinholeCamera& truth, const camera::PinholeCamera& fitted) {
  return rendered::MappingRmsMm(truth, fitted, kFrameWidth, kFrameHeight, 3225, 2225);
}

camera::PinholeCamera MakeCamera(const TrueCamera& t) {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = t.focal_px;
  c.cx_px = 0.5 * (kFrameWidth - 1) + t.principal_offset_px.x();
  c.cy_px = 0.5 * (kFrameHeight - 1) + t.principal_offset_px.y();
  c.k1 = t.k1;
  const Eigen::Vector3d axis(std::cos(t.tilt_axis_rad), std::sin(t.tilt_axis_rad), 0.0);
  return rendered::LookingDown(c, t.over_mm, t.height_mm, t.yaw_rad,
                               Eigen::AngleAxisd(t.tilt_rad, axis).matrix());
}

TEST(FieldLines, PixelsLieOnTheTrueLineCentres) {
  TrueCamera t{4000, 0.05, 0.3, 0.1, 600, -0.15, Vec2(1500, 300), Vec2(6, -4)};
  const camera::PinholeCamera camera = MakeCamera(t);
  const camera::Image frame = Render(camera, 7);
  const std::vector<calib::LinePixel> found = FindLinePixels(frame);
  ASSERT_GT(found.size(), 1000u);
  // Each found point's distance (px) to the nearest painted mark, through the true camera.
  const camera::CameraModel model = camera::CameraModel::Pinhole(camera);
  const calib::FieldMarks marks = calib::PaintedMarks(Ssl());
  double sum = 0.0;
  int far = 0;
  for (const calib::LinePixel& p : found) {
    const auto q = model.PixelToWorld(p.pixel, 0.0);
    ASSERT_TRUE(q);
    double d = 1e9;
    for (const auto& s : marks.segments) d = std::min(d, calib::DistanceToMark(s, *q));
    for (const auto& a : marks.arcs) d = std::min(d, calib::DistanceToMark(a, *q));
    const double px = d / std::sqrt(model.AreaScale(p.pixel, 0.0));
    if (px > 1.0)
      ++far;
    else
      sum += px * px;
  }
  const double rms = std::sqrt(sum / (found.size() - far));
  EXPECT_LT(far, static_cast<int>(found.size() / 100)) << "points off every line";
  EXPECT_LT(rms, 0.25) << "sub-pixel centre error";
}

TEST(FieldLines, BadOptionsAreInputErrors) {
  LineFinderOptions o;
  o.line_width_px = 0.5;
  EXPECT_INPUT_ERROR(FindLinePixels(camera::Image::Rgb(10, 10), o),
                     "--line-width: 0.5 px is out of range; expected 1 to 30");
}

TEST(FieldLines, AnEmptyCarpetDoesNotDecideTheCamera) {
  camera::Image frame = camera::Image::Rgb(200, 150);
  for (size_t i = 0; i < frame.data.size(); i += 3) frame.data[i + 1] = 120;
  EXPECT_INPUT_ERROR(AutoCalibrateFrame(frame, "carpet.png", Ssl()),
                     "carpet.png: found 0 line pixels; expected at least 100 (white field lines on "
                     "the carpet; check --line-width and the frame)");
}

// Random cameras with fixed seeds; index 0 sees a quarter of the field.
TrueCamera RandomCamera(int index) {
  RandomStream r(2024, 0x4c494e, static_cast<uint64_t>(index));
  auto u = [&](double lo, double hi) { return lo + (hi - lo) * r.Uniform(); };
  TrueCamera t;
  t.height_mm = u(3500, 4500);
  t.tilt_rad = u(0.0, 0.25);
  t.tilt_axis_rad = u(0.0, 2 * std::numbers::pi);
  t.yaw_rad = u(-0.3, 0.3) + (index % 2) * 0.5 * std::numbers::pi;
  t.focal_px = u(480, 650);
  t.k1 = u(-0.3, 0.0);
  t.principal_offset_px = Vec2(u(-15, 15), u(-15, 15));
  t.over_mm = Vec2(u(-1800, 1800), u(-500, 500));
  if (index == 0 || index == 6) {  // a quarter of the field; 6: nearly straight down
    t.over_mm = Vec2(1500, 1000);
    t.height_mm = 2300;
    if (index == 6) t.tilt_rad = 0.04;
  }
  // A lens that shows every pixel once: the radial model's fold (calib::DistortionFoldRadius)
  // at least 10 % beyond the image's farthest corner, as calibrate refuses a fit that folds
  // inside the image (a drawn k1 of -0.3 at 480 px folds at 0.70, inside the corner's 1.01).
  double corner = 0.0;
  for (const double x : {0.0, kFrameWidth - 1.0})
    for (const double y : {0.0, kFrameHeight - 1.0}) {
      const Vec2 c(0.5 * (kFrameWidth - 1) + t.principal_offset_px.x(),
                   0.5 * (kFrameHeight - 1) + t.principal_offset_px.y());
      corner = std::max(corner, (Vec2(x, y) - c).norm() / t.focal_px);
    }
  for (auto fold = calib::DistortionFoldRadius(t.k1, 0.0); fold && *fold < 1.1 * corner;
       fold = calib::DistortionFoldRadius(t.k1, 0.0)) {
    t.k1 *= 0.9;
  }
  return t;
}

class AutoCalibrateRendered : public ::testing::TestWithParam<int> {};

TEST_P(AutoCalibrateRendered, MapsTheFloorWithin5MmAndKnowsItsError) {
  const TrueCamera t = RandomCamera(GetParam());
  const camera::PinholeCamera truth = MakeCamera(t);
  const camera::Image frame = Render(truth, 100 + GetParam());
  const FrameCalibration fc = AutoCalibrateFrame(frame, "rendered.png", Ssl());
  const calib::AutoCalibration& a = fc.calibration;
  // The kept one of the two equivalent cameras looks at x >= 0 at the image centre.
  const auto look = camera::CameraModel::Pinhole(truth).PixelToWorld(
      Vec2(0.5 * (kFrameWidth - 1), 0.5 * (kFrameHeight - 1)), 0.0);
  ASSERT_TRUE(look);
  const bool turn = look->x() < 0;
  const camera::PinholeCamera expected = turn ? camera::PinholeCamera{[&] {
    camera::PinholeCamera c = truth;
    c.rotation = truth.rotation * Eigen::Vector3d(-1, -1, 1).asDiagonal();
    return c;
  }()}
                                              : truth;
  const double rms = MappingRmsMm(expected, a.fit.camera);
  std::printf(
      "camera %d: %d line pixels, true mapping RMS %.2f mm, held-out estimate %.2f mm "
      "(held-out pixels %.2f mm, noise %.2f mm)\n",
      GetParam(), a.line_pixels, rms, a.held_out_mapping_mm, a.held_out_rms_mm,
      a.held_out_noise_mm);
  EXPECT_LT(rms, 5.0);
  // The held-out estimate against the truth: within a factor 1.5 either way, with 0.5 mm for the
  // line finder's noise, which the estimate cannot resolve below that.
  EXPECT_LT(a.held_out_mapping_mm, 1.5 * rms + 0.5);
  EXPECT_GT(a.held_out_mapping_mm, rms / 1.5 - 0.5);
}

INSTANTIATE_TEST_SUITE_P(Seeds, AutoCalibrateRendered, ::testing::Values(1, 2, 3, 4, 5, 6));

// A quarter of the field seen with a 12 deg tilt: the search does not find this camera today; what
// matters is that it is refused with a message, never a wrong calibration.
TEST(AutoCalibrateRenderedQuarter, TiltedQuarterIsRightOrRefused) {
  const camera::PinholeCamera truth = MakeCamera(RandomCamera(0));
  const camera::Image frame = Render(truth, 100);
  try {
    const FrameCalibration fc = AutoCalibrateFrame(frame, "rendered.png", Ssl());
    EXPECT_LT(MappingRmsMm(truth, fc.calibration.fit.camera), 5.0);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rendered.png: "), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace patlab::vision
