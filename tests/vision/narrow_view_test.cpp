// Narrow views: a camera over the pos half of the SSL 2009 field that sees no touch line, only
// lines running one way (the halfway and goal lines) with the centre circle and the defence
// area's arcs, which alone tell the field's axes apart. The automatic calibration must map the
// floor as the true camera does (not turned by 90 deg: the search used to propose the field's
// centre along the image axis without a line only from peaks matched to lines, and the arcs'
// tangents matched only to the touch lines, out of view).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "../test_util.h"
#include "patlab/calib/auto_calibrate.h"
#include "patlab/formats/field_file.h"
#include "patlab/render/camera_render.h"
#include "patlab/render/field_render.h"
#include "patlab/vision/field_lines.h"
#include "rendered_field.h"

namespace patlab::vision {
namespace {

using patlab::testing::kFrameHeight, patlab::testing::kFrameWidth;

struct View {
  Vec2 over_mm;
  double height_mm, yaw_rad, k1;
};

camera::PinholeCamera CameraOfView(const View& v) {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = 560.0;
  c.cx_px = 392.0;
  c.cy_px = 287.0;
  c.k1 = v.k1;
  return rendered::LookingDown(c, v.over_mm, v.height_mm, v.yaw_rad,
                               Eigen::AngleAxisd(0.035, Eigen::Vector3d(0.8, 0.6, 0.0)).matrix());
}

class NarrowView : public ::testing::TestWithParam<View> {};

TEST_P(NarrowView, IsCalibratedTheRightWayRound) {
  const calib::Field field =
      formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2009.toml");
  const View v = GetParam();
  const camera::PinholeCamera truth = CameraOfView(v);
  // No touch line (y = +-2025 mm) in view: every corner of the frame maps inside them.
  const camera::CameraModel model = camera::CameraModel::Pinhole(truth);
  for (const Vec2& corner : {Vec2(0, 0), Vec2(kFrameWidth - 1, 0), Vec2(0, kFrameHeight - 1),
                             Vec2(kFrameWidth - 1, kFrameHeight - 1)}) {
    const auto q = model.PixelToWorld(corner, 0.0);
    ASSERT_TRUE(q);
    ASSERT_LT(std::abs(q->y()), 2025.0 - 100.0) << "a touch line is in view";
  }
  const camera::Image frame = rendered::RenderLines(field, truth, kFrameWidth, kFrameHeight, 3);
  const FrameCalibration fc = AutoCalibrateFrame(frame, "narrow.png", field);
  const double rms =
      rendered::MappingRmsMm(truth, fc.calibration.fit.camera, kFrameWidth, kFrameHeight);
  std::printf("over (%.0f, %.0f) at %.0f mm, yaw %.2f: mapping RMS %.2f mm vs the truth\n",
              v.over_mm.x(), v.over_mm.y(), v.height_mm, v.yaw_rad, rms);
  EXPECT_LT(rms, 5.0);
}

// Named after the view ("Over1500x0At3000mm"), not after the bytes of the struct (whose padding
// differs between builds, and so would the tests' names).
INSTANTIATE_TEST_SUITE_P(PosHalf, NarrowView,
                         ::testing::Values(View{Vec2(1500, 0), 3000, 0.0, -0.08},
                                           View{Vec2(1700, 100), 2800, 0.04, -0.12}),
                         [](const ::testing::TestParamInfo<View>& info) {
                           const View& v = info.param;
                           return "Over" + std::to_string(std::lround(v.over_mm.x())) + "x" +
                                  std::to_string(std::lround(v.over_mm.y())) + "At" +
                                  std::to_string(std::lround(v.height_mm)) + "mm";
                         });

}  // namespace
}  // namespace patlab::vision
