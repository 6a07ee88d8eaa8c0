// Which robots decide between cameras the lines leave open (internal::CreditedRobots): only those
// decoded at a height something measures.
#include <gtest/gtest.h>

#include <cmath>

#include "patlab/formats/camera_setup.h"
#include "patlab/formats/camera_setup_internal.h"

namespace patlab::formats {
namespace {

// The lines measure 3.75 +- 0.13 m and decode 6 robots there; the scan and the fit with the
// robots chose `height_mm` +- `sd_mm`, where `robots` decode.
SetupHeight Chosen(double height_mm, double sd_mm, int robots, const char* fitted) {
  SetupHeight h;
  h.decided_by = "robots";
  h.lines_height_mm = 3750.0;
  h.lines_sd_mm = 130.0;
  h.lines_robots = 6;
  h.height_mm = h.fitted_height_mm = height_mm;
  h.sd_mm = h.fitted_sd_mm = sd_mm;
  h.robots = robots;
  h.fitted = fitted;
  return h;
}

TEST(CreditedRobots, AHeightTheRobotsMeasureAndTheLinesAgreeWithCountsItsRobots) {
  // 0.40 m apart, 0.18 m combined standard error: 2.2 of them.
  EXPECT_EQ(internal::CreditedRobots(Chosen(3350.0, 130.0, 9, "kept")), 9);
}

TEST(CreditedRobots, AHeightTheLinesContradictCountsNoRobot) {
  // Fresh seed 15's ssl-2018 camera: the lines 5.95 +- 0.44 m, the robots 1.01 +- 0.12 m.
  SetupHeight h = Chosen(1010.0, 120.0, 9, "kept");
  h.lines_height_mm = 5950.0;
  h.lines_sd_mm = 440.0;
  EXPECT_EQ(internal::CreditedRobots(h), 0);
  // Just inside kHeightAgreement combined standard errors it counts.
  h.height_mm = h.fitted_height_mm =
      h.lines_height_mm - 0.99 * internal::kHeightAgreement * std::hypot(120.0, 440.0);
  EXPECT_EQ(internal::CreditedRobots(h), 9);
}

TEST(CreditedRobots, AFitWithTheRobotsNotKeptStillContradictsTheLines) {
  // Fresh seed 1's ssl-2014 camera: the lines measure 5.02 +- 0.23 m and 8 robots decode there;
  // the fit with those robots measures 3.34 +- 0.25 m, not kept (the lines measure more finely).
  SetupHeight h = Chosen(5020.0, 230.0, 8, "not kept: the lines measure the height more finely");
  h.decided_by = "lines";
  h.lines_height_mm = 5020.0;
  h.lines_sd_mm = 230.0;
  h.lines_robots = 8;
  h.fitted_height_mm = 3340.0;
  h.fitted_sd_mm = 250.0;
  EXPECT_EQ(internal::CreditedRobots(h), 0);
  // Agreeing (4.20 +- 0.25 m: 2.4 combined standard errors), the lines' robots count.
  h.fitted_height_mm = 4200.0;
  EXPECT_EQ(internal::CreditedRobots(h), 8);
}

TEST(CreditedRobots, WithoutTheFitWithTheRobotsTheLinesHeightsRobotsCount) {
  EXPECT_EQ(internal::CreditedRobots(Chosen(11040.0, NAN, 9, "failed: unphysical")), 6);
}

TEST(CreditedRobots, AHeightNothingMeasuresCountsTheLinesRobotsOnlyWhereNoHeightDecodesMore) {
  // Fresh seed 58's ssl-2014 camera: the lines 0.78 +- 19.45 m and no robot through them, 7 from
  // 2.7 m up; the fit with the robots failed.
  SetupHeight h = Chosen(11040.0, NAN, 7, "failed: unphysical");
  h.lines_height_mm = 780.0;
  h.lines_sd_mm = 19450.0;
  h.lines_robots = 0;
  h.scan = {{780.0, 156.0, 0, NAN}, {2730.0, 546.0, 7, 4.0}, {11040.0, 2220.0, 7, 4.0}};
  EXPECT_EQ(internal::CreditedRobots(h), 0);
  // 5 through the lines' camera, 10 at other heights (few-lines view 8): luck, not the scale.
  h.lines_robots = 5;
  h.scan[0].robots = 5;
  h.scan[1].robots = h.scan[2].robots = 10;
  EXPECT_EQ(internal::CreditedRobots(h), 0);
  // 6 through the lines' camera and at every height (fresh seed 3 at standout_delta_e 14,
  // segment_k 40): the floor's scale decodes them, whatever the height.
  h.lines_robots = 6;
  for (SetupHeightTry& t : h.scan) t.robots = 6;
  EXPECT_EQ(internal::CreditedRobots(h), 6);
  h.lines_sd_mm = NAN;  // the lines' fit has no covariance: the same
  EXPECT_EQ(internal::CreditedRobots(h), 6);
  h.lines_robots = 0;
  // The robots' fit measures it, and the lines say nothing against it.
  h.fitted = "kept";
  h.sd_mm = h.fitted_sd_mm = 240.0;
  EXPECT_EQ(internal::CreditedRobots(h), 7);
  // Kept however coarse (the lines do not measure the height): it credits what the lines' camera
  // would, here nothing (7 robots decode higher up than the lines' camera).
  h.sd_mm = h.fitted_sd_mm = 3000.0;
  EXPECT_EQ(internal::CreditedRobots(h), 0);
}

TEST(CreditedRobots, AGivenHeightCountsItsRobotsWhereTheLinesMeasureTheFocalLength) {
  // The lines fix f / h to 4 %: the given height fixes f, and the robots through it count.
  SetupHeight h = Chosen(3437.0, NAN, 10, "");
  h.decided_by = "given";
  h.lines_height_mm = 3437.0;
  h.lines_sd_mm = 130.0;
  EXPECT_EQ(internal::CreditedRobots(h), 10);
  // Few-lines view 8: a corner's lines leave f / h open, so the focal length the given height
  // implies is the fit's luck, and so are the 8 robots decoded through it.
  h.lines_sd_mm = 1900.0;
  EXPECT_EQ(internal::CreditedRobots(h), 0);
  h.lines_sd_mm = NAN;  // no covariance: nothing measured
  EXPECT_EQ(internal::CreditedRobots(h), 0);
}

}  // namespace
}  // namespace patlab::formats
