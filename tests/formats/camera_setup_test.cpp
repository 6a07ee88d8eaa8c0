// The pieces of patlab setup that need no frame: the tolerances chosen from the measured scale,
// mapping error and patch size (formats/camera_setup.h), the --landmark form, setup folders.
#include "patlab/formats/camera_setup.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "../expect_error.h"
#include "../test_util.h"

namespace patlab::vision {
namespace {

TEST(SetupTolerances, FollowTheScaleTheMappingErrorAndThePatchSize) {
  const detect::DetectorOptions base;
  // A fine camera (1 mm/px), a good calibration, big patches: the floors of each bound.
  detect::DetectorOptions t = SetupTolerances(base, 1.0, 0.5, 20.0);
  EXPECT_DOUBLE_EQ(t.patch_sigma_mm, 2.0);
  EXPECT_DOUBLE_EQ(t.reach_margin_mm, 20.0);
  EXPECT_DOUBLE_EQ(t.area_ratio_min, 0.4);  // 0.5 (18.94 / 20)^2 = 0.45, capped
  // A coarse camera (10 mm/px), 8 mm mapping error, 2.5 px patches.
  t = SetupTolerances(base, 10.0, 8.0, 2.5);
  EXPECT_DOUBLE_EQ(t.patch_sigma_mm, 4.0);            // 0.4 px
  EXPECT_DOUBLE_EQ(t.reach_margin_mm, 3 * 8.0 + 20);  // 3 errors + 2 px
  EXPECT_NEAR(t.area_ratio_min, 0.5 * std::pow(1.44 / 2.5, 2), 1e-12);
  EXPECT_DOUBLE_EQ(t.area_ratio_max, 2.5);
  // A patch a pixel across: the floor of 0.1; an unknown mapping error counts as 0.
  t = SetupTolerances(base, 10.0, std::nan(""), 1.0);
  EXPECT_DOUBLE_EQ(t.area_ratio_min, 0.1);
  EXPECT_DOUBLE_EQ(t.reach_margin_mm, 20.0);
  EXPECT_EQ(t.estimator, base.estimator);  // what setup does not choose stays
}

TEST(SetupLandmarks, ParseNameAndPixel) {
  const SetupLandmark l = ParseLandmark("corner_pos_left=700.5,-3e1");
  EXPECT_EQ(l.name, "corner_pos_left");
  EXPECT_DOUBLE_EQ(l.pixel.x(), 700.5);
  EXPECT_DOUBLE_EQ(l.pixel.y(), -30.0);
  for (const char* bad : {"centre", "centre=1", "centre=1,2,3", "=1,2", "centre=x,2", "c=1,nan"}) {
    EXPECT_INPUT_ERROR(ParseLandmark(bad), std::string("--landmark '") + bad +
                                               "'; expected NAME=X,Y (a landmark of the field "
                                               "and its pixel)");
  }
}

TEST(SetupFolder, NamesItsFilesRelativeToTheFolder) {
  testing::TempDir dir;
  std::ofstream(dir.Path("setup.toml"))
      << "calibration = \"c.toml\"\nthresholds = \"t.toml\"\nsettings = \"/abs/s.toml\"\n";
  const SetupFiles f = LoadSetupFiles(dir.Path(""));
  EXPECT_EQ(f.calibration, dir.Path("c.toml"));
  EXPECT_EQ(f.thresholds, dir.Path("t.toml"));
  EXPECT_EQ(f.settings, "/abs/s.toml");
  std::ofstream(dir.Path("setup.toml")) << "calibration = \"c.toml\"\n";
  EXPECT_INPUT_ERROR(LoadSetupFiles(dir.Path("")),
                     dir.Path("setup.toml") +
                         ":1: missing or non-text key 'thresholds'; expected calibration, "
                         "thresholds and settings file names");
  EXPECT_INPUT_ERROR(LoadSetupFiles(dir.Path("nowhere")),
                     "--setup " + dir.Path("nowhere") +
                         ": no setup.toml in it; expected a folder written by patlab setup");
}

}  // namespace
}  // namespace patlab::vision
