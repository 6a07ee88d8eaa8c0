// The crossings the robots' path places (calib::PlaceCrossings) where the lines match too few
// marks: a line is a run of pixels, not pixels strewn along a band of the floor.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/calib/auto_calibrate.h"
#include "patlab/formats/field_file.h"

namespace patlab::calib {
namespace {

using testing::kFrameHeight, testing::kFrameWidth;

// A camera 3 m straight down, 600 px focal length: 5 mm per px on the floor.
camera::PinholeCamera FloorCamera() {
  camera::PinholeCamera c;
  c.fx_px = c.fy_px = 600.0;
  c.cx_px = 0.5 * (kFrameWidth - 1);
  c.cy_px = 0.5 * (kFrameHeight - 1);
  c.rotation = Eigen::Vector3d(1, -1, -1).asDiagonal();
  c.translation_mm = -c.rotation * Eigen::Vector3d(0.0, 0.0, 3000.0);
  return c;
}

// One straight line down the image at x = 300 px, a line pixel every 0.6 px.
std::vector<LinePixel> OneLine() {
  std::vector<LinePixel> pixels;
  for (double y = 2.0; y < kFrameHeight - 2; y += 0.6)
    pixels.push_back({Vec2(300.0, y), Vec2(0, 1), 40});
  return pixels;
}

std::vector<Placement> Place(const std::vector<LinePixel>& pixels) {
  const std::vector<Field> fields = {
      formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-div-b.toml")};
  return PlaceCrossings(pixels, kFrameWidth, kFrameHeight, "synthetic.png", fields, FloorCamera(),
                        6.0, {});
}

TEST(PlaceCrossings, PixelsStrewnAcrossALineAreNoSecondLine) {
  // Fresh rendered seed 115's trouble: one line, and 14 pixels running across it strewn 40 px
  // apart along a band 2 px wide (a robot's rim here, noise there).
  std::vector<LinePixel> pixels = OneLine();
  for (int i = 0; i < 14; ++i)
    pixels.push_back({Vec2(150.0 + 40.0 * i, 200.0 + (i % 3 == 0 ? 1.0 : 0.0)), Vec2(1, 0), 40});
  EXPECT_TRUE(Place(pixels).empty());
}

TEST(PlaceCrossings, AShortRunAcrossALineIsASecondLine) {
  // The same 14 pixels in one run 1 px apart: a piece of a crossing line.
  std::vector<LinePixel> pixels = OneLine();
  for (int i = 0; i < 14; ++i) pixels.push_back({Vec2(500.0 + i, 200.0), Vec2(1, 0), 40});
  const std::vector<Placement> placements = Place(pixels);
  ASSERT_FALSE(placements.empty());
  // Each placement puts where the two runs meet, (300, 200) px, on its crossing of the model.
  const Field field = formats::LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-div-b.toml");
  auto line = [&](const std::string& name) {
    for (const FieldLine& l : field.lines)
      if (l.name == name) return l;
    ADD_FAILURE() << "no line " << name;
    return FieldLine{};
  };
  for (const Placement& p : placements) {
    const size_t x = p.crossing.find(" x ");
    ASSERT_NE(x, std::string::npos) << p.crossing;
    const FieldLine along_x = line(p.crossing.substr(0, x)),
                    along_y = line(p.crossing.substr(x + 3));
    const Vec2 crossing(along_y.from_mm.x(), along_x.from_mm.y());
    const auto seen = camera::CameraModel::Pinhole(p.camera).PixelToWorld(Vec2(300.0, 200.0), 0.0);
    ASSERT_TRUE(seen.has_value());
    EXPECT_LT((*seen - crossing).norm(), 10.0) << p.crossing;
  }
}

TEST(PlaceCrossings, OneLineAloneIsNoCrossing) { EXPECT_TRUE(Place(OneLine()).empty()); }

}  // namespace
}  // namespace patlab::calib
