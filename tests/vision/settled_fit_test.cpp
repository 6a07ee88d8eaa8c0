// The automatic calibration's fits stop once the camera's image of the floor has settled
// (calib::AutoOptions::settle_px, FitOptions::settle_px): lines on the floor leave a valley of
// focal length against height along which the solver crawls to its last iteration, the cost
// falling by a few parts in 10^7 per step. Stopped once settled, it maps the floor as the
// crawling fit does, within a tenth of a pixel, on the rendered lines of seed 58's camera.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <vector>

#include "../test_util.h"
#include "patlab/calib/auto_calibrate.h"
#include "patlab/formats/field_file.h"
#include "patlab/vision/field_lines.h"
#include "rendered_field.h"

namespace patlab::vision {
namespace {

using patlab::testing::kFrameHeight, patlab::testing::kFrameWidth;

// Seed 58's camera (scripts/setup_rendered.py, tests/bench/setup_bench.cpp): 3.3 m over ssl-2015.
camera::PinholeCamera Seed58Camera() {
  return rendered::CameraOfFile(620.773377, Vec2(388.2586, 287.504088), -0.053985,
                                Eigen::Vector3d(-1.781230243, 2.570248600, -0.008345282),
                                Eigen::Vector3d(768.181397, -2561.128992, 3283.150133));
}

// The true model's last fit on seed 58's lines crawls along the valley to its 200th iteration,
// its focal length from about 735 px to about 398 px, while its image of the floor moves by a
// hundredth of a pixel or so; settled, it stops within a few dozen iterations at the same map.
TEST(SettledFit, StopsTheCrawlAlongTheValleyAtTheSameFloorMap) {
  const camera::PinholeCamera truth = Seed58Camera();
  const calib::Field field =
      formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2015.toml");
  const std::vector<calib::LinePixel> pixels =
      FindLinePixels(rendered::RenderLines(field, truth, kFrameWidth, kFrameHeight, 5));
  calib::AutoOptions crawling;
  crawling.settle_px = 0.0;
  const calib::AutoCalibration settled =
      calib::AutoCalibrate(pixels, kFrameWidth, kFrameHeight, "rendered.png", field);
  const calib::AutoCalibration full =
      calib::AutoCalibrate(pixels, kFrameWidth, kFrameHeight, "rendered.png", field, crawling);
  const double between_mm =
      rendered::MappingRmsMm(full.fit.camera, settled.fit.camera, kFrameWidth, kFrameHeight);
  const double mm_per_px = -(truth.rotation.transpose() * truth.translation_mm).z() / truth.fx_px;
  std::printf(
      "settled: %d iterations, f %.1f px, %.2f px of line; crawling: %d iterations, f %.1f px, "
      "%.2f px of line; floor maps %.3f mm apart (%.3f mm per px)\n",
      settled.fit.iterations, settled.fit.camera.fx_px, settled.score_px, full.fit.iterations,
      full.fit.camera.fx_px, full.score_px, between_mm, mm_per_px);
  ASSERT_GE(full.fit.iterations, 150) << "this view no longer crawls: the test shows nothing";
  EXPECT_LT(settled.fit.iterations, 60);
  // Far apart along the valley (the focal length), the same map of the floor: within a tenth of
  // a pixel, and the same line length explained to 0.1 %.
  EXPECT_GT(std::abs(settled.fit.camera.fx_px - full.fit.camera.fx_px), 50.0);
  EXPECT_LT(between_mm, 0.1 * mm_per_px);
  EXPECT_NEAR(settled.score_px, full.score_px, 1e-3 * full.score_px);
  // The report names the stop: the settle's rule, not Ceres' "user callback".
  EXPECT_EQ(settled.fit.termination,
            "SETTLED: no floor point's image moved more than 0.01 px over the last 10 successful "
            "iterations");
  EXPECT_EQ(full.fit.termination.rfind("NO_CONVERGENCE", 0), 0u) << full.fit.termination;
}

}  // namespace
}  // namespace patlab::vision
