// Lines that fit a camera only with its focal length at the fit's lower bound, through which no
// robot decodes at any height, fix no camera (internal::FocalAtItsBound): setup hands such a frame
// to the robots' path.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "patlab/formats/camera_setup_internal.h"
#include "patlab/formats/field_file.h"

namespace patlab::formats {
namespace {

calib::FamilyCalibration OnlyCamera(double focal_px) {
  calib::FamilyCalibration family;
  family.kept = 0;
  family.calibration.line_pixels = 942;
  family.calibration.fit.camera.fx_px = focal_px;
  return family;
}

// The heights ChooseHeight tried: none decodes a robot.
SetupHeight NothingDecodes() {
  SetupHeight h;
  h.decided_by = "undetermined";
  h.scan = {{1550.0, 310.0, 0, NAN}, {3120.0, 624.0, 0, NAN}, {8310.0, 1662.0, 0, NAN}};
  return h;
}

TEST(FocalAtItsBound, TheOnlyCameraAtTheLowerBoundThroughWhichNothingDecodesIsNamed) {
  const std::vector<calib::Field> fields = {
      LoadField(PATLAB_SOURCE_DIR "/experiments/fields/ssl-2015.toml")};
  // Few-lines view 5: 780 px wide, the bound 0.2 widths = 156 px.
  EXPECT_EQ(
      internal::FocalAtItsBound(OnlyCamera(156.0), fields, "frame.png", 780, NothingDecodes()),
      "frame.png: 942 line pixels fit ssl-2015 only with the focal length at the fit's lower "
      "bound (156 px, 0.2 image widths), and no robot decodes through that camera at any "
      "height from 1.55 to 8.31 m: the lines do not fix the camera");
  // Off the bound the lines measured the camera.
  EXPECT_EQ(
      internal::FocalAtItsBound(OnlyCamera(157.0), fields, "frame.png", 780, NothingDecodes()), "");
  // At the bound the lines still fix f / h, and robots decoded at one height choose it (rendered
  // seeds 16, 46, 63 and 104).
  SetupHeight scanned = NothingDecodes();
  scanned.scan[1].robots = 8;
  EXPECT_EQ(internal::FocalAtItsBound(OnlyCamera(156.0), fields, "frame.png", 780, scanned), "");
  SetupHeight given;
  given.decided_by = "given";
  given.robots = given.lines_robots = 3;
  EXPECT_EQ(internal::FocalAtItsBound(OnlyCamera(156.0), fields, "frame.png", 780, given), "");
  // With rivals the robots decide between the cameras (SetupFromLines), bound or not.
  calib::FamilyCalibration rivals = OnlyCamera(156.0);
  rivals.rivals.emplace_back();
  EXPECT_EQ(internal::FocalAtItsBound(rivals, fields, "frame.png", 780, NothingDecodes()), "");
}

}  // namespace
}  // namespace patlab::formats
