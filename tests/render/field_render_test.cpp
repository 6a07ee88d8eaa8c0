// Field lines through a camera: line pixels where the field's lines project, carpet elsewhere.
#include "patlab/render/field_render.h"

#include <gtest/gtest.h>

#include "../expect_error.h"
#include "patlab/formats/field_file.h"

namespace patlab::render {
namespace {

camera::PinholeCamera Nadir() {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = 500;
  c.cx_px = 159.5;
  c.cy_px = 119.5;
  c.rotation = Eigen::Vector3d(1, -1, -1).asDiagonal();
  c.translation_mm = -c.rotation * Eigen::Vector3d(0, 0, 5000);  // 10 mm per px
  return c;
}

TEST(FieldRender, LinesWhereTheFieldHasThem) {
  const calib::Field f = formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2009.toml");
  FieldLineStyle style;
  style.line_width_mm = 30;  // 3 px
  const camera::Image img =
      RenderFieldLines(f, camera::CameraModel::Pinhole(Nadir()), 320, 240, style);
  auto at = [&](int x, int y) {
    const uint8_t* p = img.Row(y) + 3 * x;
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  // The halfway line x = 0 is the column at cx; the centre circle (r 500 mm) 50 px from it.
  const std::array<int, 3> line{235, 235, 235}, carpet{40, 110, 40};
  EXPECT_EQ(at(159, 30), line);  // the pixel straddles x = 0 (cx = 159.5): mostly line
  EXPECT_EQ(at(100, 30), carpet);
  EXPECT_EQ(at(209, 119), line);  // on the circle, right of the centre (x = 500 mm)
  EXPECT_EQ(at(250, 200), carpet);
}

TEST(FieldRender, HomographyCameraIsRefused) {
  const calib::Field f = formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/vss.toml");
  EXPECT_INPUT_ERROR(
      RenderFieldLines(f, camera::CameraModel::Homographies({camera::PlaneHomography{}}), 10, 10),
      "camera: a homography camera cannot render field lines; expected a pinhole "
      "camera");
}

}  // namespace
}  // namespace patlab::render
