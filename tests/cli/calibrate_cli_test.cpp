// patlab calibrate end to end: the shared real SSL frame's measured lines and points (the input
// file is in the repository; the frame itself is not needed), the binary run as a user would.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "../test_util.h"
#include "patlab/camera/camera.h"
#include "patlab/formats/calibration_file.h"

namespace patlab::cli {
namespace {

using testing::kPatlab;
using testing::RunCommand;

const std::string kInput =
    std::string(PATLAB_SOURCE_DIR) + "/tests/data/vision/ssl-2008.calibration-input.toml";

double Number(const std::string& text, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(pattern))) {
    ADD_FAILURE() << "no match for " << pattern << " in\n" << text;
    return -1;
  }
  return std::stod(m[1]);
}

TEST(CalibrateCli, FitsTheRealSslFrameFromItsFieldLines) {
  testing::TempDir dir;
  const std::string cal = dir.Path("cal/calibration.toml"), res = dir.Path("cal/residuals.csv");
  const auto r = RunCommand(kPatlab + " calibrate " + kInput + " --out " + dir.Path("cal"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 95 pixels of the white lines' centres and 7 crossings read off by eye: about a pixel RMS
  // (the lines are 2-3 px wide, the crossings good to 2 px), about 1 cm on the floor. The
  // calibration fitted outside patlab to this frame had 34 mm RMS.
  EXPECT_LT(Number(r.out, R"(residuals: RMS ([0-9.]+) px)"), 1.6);
  EXPECT_LT(Number(r.out, R"(\n  0 +95 +[0-9.]+ +[0-9.]+ +([0-9.]+))"), 12.0);
  EXPECT_NE(r.out.find("warning: the focal length is not determined"), std::string::npos);
  // The file is a calibration patlab detect reads, with the input's plane heights.
  const camera::Calibration c = formats::LoadCalibration(cal);
  EXPECT_EQ(c.image_width_px, 780);
  EXPECT_EQ(c.default_height_mm, 140.0);
  EXPECT_EQ(c.HeightOf("orange"), 21.5);
  // The centre mark maps to the field's centre, and the residual file has a row per pixel.
  const auto centre = c.camera.PixelToWorld(Vec2(387.4, 524.5), 0.0);
  ASSERT_TRUE(centre.has_value());
  EXPECT_LT(centre->norm(), 40.0);
  const std::string csv = testing::ReadFile(res);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 96);
}

TEST(CalibrateCli, BadInputIsExit2WithNothingWritten) {
  testing::TempDir dir;
  const std::string in = dir.Write("in.toml",
                                   "image_size_px = [780, 580]\n[[point]]\n"
                                   "world_mm = [0, 0]\npixel = [1, 2]\n");
  const auto r = RunCommand(kPatlab + " calibrate " + in + " --out " + dir.Path("cal.toml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "patlab calibrate: " + in +
                       ": the input has 1 known points on its best-covered plane; expected at "
                       "least 4 [[point]] tables on one plane height (the fit starts from their "
                       "homography)\n");
  EXPECT_FALSE(std::filesystem::exists(dir.Path("cal.toml")));
  const auto missing = RunCommand(kPatlab + " calibrate " + in);
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(missing.err,
            "patlab calibrate: missing --out DIR; expected the directory to write to\n");
}

TEST(CalibrateCli, AFoldedFitIsExit2WithItsNumbersAndNothingWritten) {
  // The real frame's input with the focal length held at 600 px and k1 at -0.6: the lens the fit
  // must keep folds where 1 - 1.8 r^2 = 0, r = 0.745, at the image radius 0.745 (1 - 0.6 / 1.8)
  // = 0.497 (298 px at f = 600), inside the 780 x 580 frame (its corners are 0.8 or more away
  // from any principal point inside the image).
  testing::TempDir dir;
  std::string text = testing::ReadFile(kInput);
  const std::string fix = "fix = [\"aspect\", \"k2\"]";
  ASSERT_NE(text.find(fix), std::string::npos);
  text.replace(text.find(fix), fix.size(),
               "fix = [\"focal\", \"aspect\", \"k1\", \"k2\"]\nfocal_px = 600\nk1 = -0.6");
  const std::string field = "../../../experiments/fields/ssl-2009.toml";
  text.replace(text.find(field), field.size(),
               std::string(PATLAB_SOURCE_DIR) + "/experiments/fields/ssl-2009.toml");
  const std::string in = dir.Write("folded.toml", text);
  const auto r = RunCommand(kPatlab + " calibrate " + in + " --out " + dir.Path("cal"));
  EXPECT_EQ(r.exit_code, 2) << r.out;
  const std::string head = "patlab calibrate: " + in +
                           ": the fitted camera is not usable: its distortion folds at r = 0.497 "
                           "(radius 298 px) inside the image's ";
  EXPECT_EQ(r.err.substr(0, head.size()), head) << r.err;
  EXPECT_NE(r.err.find(": k1 = -0.6, k2 = 0; expected a lens that shows every pixel once"),
            std::string::npos)
      << r.err;
  const double image_r = Number(r.err, R"(inside the image's ([0-9.]+):)");
  EXPECT_GT(image_r, 0.8);
  EXPECT_LT(image_r, 1.62);  // hypot(780, 580) / 600: no corner is farther
  EXPECT_TRUE(r.out.empty());
  EXPECT_FALSE(std::filesystem::exists(dir.Path("cal")));
}

}  // namespace
}  // namespace patlab::cli
