#include "patlab/vision/pipeline.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../frame_test_util.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/render/render.h"

namespace patlab::vision {
namespace {

Thresholds BlueOrange() {
  return formats::ParseThresholdsToml(
      "space = \"yuv\"\n"
      "[[class]]\nname = \"blue\"\nu = [160, 255]\nv = [0, 120]\n"
      "[[class]]\nname = \"orange\"\nu = [0, 110]\nv = [160, 255]\n",
      "t.toml");
}

camera::Calibration Overhead(double k1) {
  return formats::ParseCalibration(
      "model = \"pinhole\"\nimage_size_px = [320, 240]\n[pinhole]\nfx_px = 800\nfy_px = 800\n"
      "cx_px = 160\ncy_px = 120\nk1 = " +
          std::to_string(k1) +
          "\ncamera_position_mm = [0, 0, 3000]\nyaw_deg = 30\n[heights]\ndefault_mm = 140\norange "
          "= 21\n",
      "c.toml");
}

// Patches rendered in world mm through the camera come back as blobs at their world positions.
// The plane is fronto-parallel, so without distortion a disc images to a disc and its centroid
// is exact up to digitisation (< 0.15 px for a 7 px radius, see the Segmenter test: 0.54 mm at
// 3.6 mm per px here); mild barrel distortion adds a bias of well under a millimetre.
TEST(VisionPipeline, RenderedWorldDiscsComeBackInMillimetres) {
  for (double k1 : {0.0, -0.1}) {
    const camera::Calibration cal = Overhead(k1);
    const std::vector<render::Disc> blue = {{Vec2(-300, 200), 25, {20, 40, 230}},
                                            {Vec2(150.5, -100.25), 25, {20, 40, 230}},
                                            {Vec2(0, 0), 40, {20, 40, 230}}};
    camera::Image image = render::RenderWorldDiscs(320, 240, cal.camera, 140, {60, 60, 60}, blue);
    // The ball at its own plane height, painted over the same background.
    const std::vector<render::Disc> orange = {{Vec2(400, 50), 21, {250, 120, 10}}};
    const camera::Image ball =
        render::RenderWorldDiscs(320, 240, cal.camera, 21, {60, 60, 60}, orange);
    for (size_t i = 0; i < image.data.size(); ++i) {
      if (ball.data[i] != 60) image.data[i] = ball.data[i];
    }
    VisionPipeline pipeline(BlueOrange(), cal, SegmenterOptions{});
    pipeline.CheckFrameSize(image, "frame");
    std::vector<detect::Blob> blobs;
    VisionStats stats;
    pipeline.Process(image, &blobs, &stats);
    ASSERT_EQ(blobs.size(), 4u) << "k1 = " << k1;
    EXPECT_EQ(stats.blobs, 4);
    EXPECT_EQ(stats.regions, 4);
    // Blue regions by area: the big one first; the two equal discs in either order.
    if (blobs[1].position_mm.x() > blobs[2].position_mm.x()) std::swap(blobs[1], blobs[2]);
    const Vec2 expected[] = {blue[2].centre, blue[0].centre, blue[1].centre, orange[0].centre};
    const double radius[] = {40, 25, 25, 21};
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(blobs[i].colour, i < 3 ? 0 : 1);
      EXPECT_NEAR(blobs[i].position_mm.x(), expected[i].x(), 1.0) << i << " k1 = " << k1;
      EXPECT_NEAR(blobs[i].position_mm.y(), expected[i].y(), 1.0) << i << " k1 = " << k1;
      // Area: pi r^2 up to half a pixel ring of 3.6 mm pixels.
      const double area = M_PI * radius[i] * radius[i];
      EXPECT_NEAR(blobs[i].area_mm2, area, 2 * M_PI * radius[i] * 0.5 * 3.6) << i;
    }
  }
}

TEST(VisionPipeline, FrameSizeMustMatchTheCalibration) {
  VisionPipeline pipeline(BlueOrange(), Overhead(0), SegmenterOptions{});
  EXPECT_INPUT_ERROR(pipeline.CheckFrameSize(camera::Image::Rgb(640, 480), "f.png"),
                     "f.png: image is 640x480; expected 320x240 as in c.toml");
}

TEST(VisionPipeline, HomographyMustCoverEveryClassHeight) {
  const camera::Calibration cal = formats::ParseCalibration(
      "model = \"homography\"\n[[homography]]\nheight_mm = 140\n"
      "matrix = [[1, 0, 0], [0, -1, 800], [0, 0, 1]]\n[heights]\ndefault_mm = 140\norange = 21\n",
      "h.toml");
  EXPECT_INPUT_ERROR(VisionPipeline(BlueOrange(), cal, SegmenterOptions{}),
                     "h.toml: no homography for height 21 mm (class 'orange'); expected a "
                     "[[homography]] with that height_mm");
}

TEST(VisionPipeline, HeightsMustNameKnownClasses) {
  const camera::Calibration cal = formats::ParseCalibration(
      "model = \"homography\"\n[[homography]]\nheight_mm = 0\n"
      "matrix = [[1, 0, 0], [0, -1, 800], [0, 0, 1]]\n[heights]\npink = 0\n",
      "h.toml");
  EXPECT_INPUT_ERROR(VisionPipeline(BlueOrange(), cal, SegmenterOptions{}),
                     "h.toml: [heights] names class 'pink', which t.toml does not define; "
                     "expected one of: blue, orange");
}

}  // namespace
}  // namespace patlab::vision
