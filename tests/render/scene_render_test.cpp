#include "patlab/render/scene_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "../frame_test_util.h"
#include "../test_util.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/formats/scene_file.h"

namespace patlab::render {
namespace {

using testing::kGolden;
const std::string kPatterns = std::string(PATLAB_SOURCE_DIR) + "/patterns/";

// The golden frame's camera: 4 m up, tilted 4 deg, k1 = -0.18, 640x480.
camera::Calibration GoldenCalibration() {
  return formats::LoadCalibration(kGolden + "ssl-frame.calibration.toml");
}

// A scene of the SSL standard pattern with a grey field, no robots, no ball, no blur or noise.
FieldScene EmptyScene() {
  FieldScene scene;
  detect::DetectorPattern worn =
      formats::MakeDetectorPattern(formats::LoadPatternFile(kPatterns + "ssl-standard.toml"), {},
                                   kPatterns + "ssl-standard.codebook.toml", {});
  scene.pattern = worn.pattern;
  scene.codebook = worn.codebook;
  scene.colours = {{"field", {40, 100, 50}}, {"body", {30, 30, 34}},   {"blue", {35, 75, 210}},
                   {"pink", {240, 95, 185}}, {"green", {70, 215, 95}}, {"orange", {250, 125, 25}}};
  scene.options.blur_sigma_px = 0.0;
  scene.options.noise_sigma_levels = 0.0;
  return scene;
}

// The centroid of the pixels weighted by how much of `colour` they show on the red channel
// (field 40 -> 0, colour -> 1): the coverage-weighted centroid of the drawn disc.
Vec2 CoverageCentroid(const camera::Image& image, int field_r, int colour_r) {
  double sum = 0.0, sx = 0.0, sy = 0.0;
  for (int y = 0; y < image.height_px; ++y) {
    for (int x = 0; x < image.width_px; ++x) {
      const double w = static_cast<double>(image.Row(y)[3 * x] - field_r) /
                       static_cast<double>(colour_r - field_r);
      sum += w;
      sx += w * x;
      sy += w * y;
    }
  }
  return Vec2(sx / sum, sy / sum);
}

// A disc of 60 mm radius (about 12 px) off the image centre, through the golden camera's tilt
// and distortion: its coverage-weighted centroid is where the camera model maps its centre.
// Error budget (px): the centroid of a projected disc is not the projection of its centre, by
// about f (r/Z)^2 tan(view angle) = 800 (60/3980)^2 0.25 = 0.05 for a 14 deg view angle here,
// and the 4 x 4 sub-sampled coverage is off by up to 1/16 on each of ~75 boundary pixels
// (random signs: sqrt(75) / 16 / sqrt(3) * 12 px / 450 px^2 = 0.01). Hence 0.1 px; a y axis
// flipped or a pixel-centre convention off by half a pixel moves it by far more.
TEST(SceneRender, DiscCentroidLandsWhereTheCameraMapsItsCentre) {
  const camera::Calibration cal = GoldenCalibration();
  FieldScene scene = EmptyScene();
  scene.options.ball_radius_mm = 60.0;
  scene.options.blur_sigma_px = 0.7;  // symmetric: moves no centroid
  for (const Vec2& ball : {Vec2(700.0, 500.0), Vec2(-900.0, -600.0)}) {
    scene.ball_mm = ball;
    const camera::Image image = RenderScene(scene, cal.camera);
    const Vec2 expected = *cal.camera.WorldToPixel(ball, scene.options.ball_radius_mm);
    const Vec2 centroid = CoverageCentroid(image, 40, 250);
    EXPECT_NEAR(centroid.x(), expected.x(), 0.1);
    EXPECT_NEAR(centroid.y(), expected.y(), 0.1);
  }
}

// Without robots or ball the frame is the field colour plus noise. Rounding adds a uniform
// error of variance 1/12 (Sheppard), so the sample variance of N = 3 W H levels estimates
// sigma^2 + 1/12 with standard error (sigma^2 + 1/12) sqrt(2 / (N - 1)); the mean estimates the
// field level with standard error sigma / sqrt(N); neighbouring pixels are independent, so
// their correlation is 0 with standard error 1 / sqrt(N). Each within 4 standard errors.
TEST(SceneRender, NoiseHasTheRequestedSigmaAndIsIndependentBetweenPixels) {
  FieldScene scene = EmptyScene();
  scene.colours["field"] = {128, 128, 128};
  scene.options.width_px = 128;
  scene.options.height_px = 96;
  scene.options.noise_sigma_levels = 4.0;
  const camera::Image image = RenderScene(scene, GoldenCalibration().camera);
  const double n = static_cast<double>(image.data.size());
  double sum = 0.0, sum2 = 0.0, lag = 0.0;
  for (size_t i = 0; i < image.data.size(); ++i) {
    const double d = image.data[i] - 128.0;
    sum += d;
    sum2 += d * d;
    if (i + 3 < image.data.size()) lag += d * (image.data[i + 3] - 128.0);  // next pixel
  }
  const double mean = sum / n;
  const double variance = (sum2 - n * mean * mean) / (n - 1);
  const double expected_variance = 16.0 + 1.0 / 12.0;
  EXPECT_NEAR(mean, 0.0, 4.0 * 4.0 / std::sqrt(n));
  EXPECT_NEAR(variance, expected_variance, 4.0 * expected_variance * std::sqrt(2.0 / (n - 1)));
  EXPECT_NEAR(lag / (n - 3) / expected_variance, 0.0, 4.0 / std::sqrt(n));
}

TEST(SceneRender, SameSeedSameImageOtherSeedOtherNoise) {
  FieldScene scene = EmptyScene();
  scene.options.width_px = 64;
  scene.options.height_px = 48;
  scene.options.noise_sigma_levels = 3.0;
  scene.options.seed = 7;
  const camera::CameraModel camera = GoldenCalibration().camera;
  const camera::Image a = RenderScene(scene, camera);
  EXPECT_EQ(RenderScene(scene, camera).data, a.data);
  scene.options.seed = 8;
  const camera::Image b = RenderScene(scene, camera);
  // Two independent draws of sigma 3 round to the same level with probability ~0.1.
  size_t differ = 0;
  for (size_t i = 0; i < a.data.size(); ++i) differ += a.data[i] != b.data[i];
  EXPECT_GT(differ, a.data.size() / 2);
}

// Blur spreads an edge over more pixels but keeps the disc where it is.
TEST(SceneRender, BlurSoftensEdgesWithoutMovingThem) {
  const camera::Calibration cal = GoldenCalibration();
  FieldScene scene = EmptyScene();
  scene.options.ball_radius_mm = 60.0;
  scene.ball_mm = Vec2(0.0, 0.0);
  auto mixed = [](const camera::Image& image) {
    int count = 0;
    for (size_t i = 0; i < image.data.size(); i += 3)
      count += image.data[i] > 42 && image.data[i] < 248;
    return count;
  };
  const camera::Image sharp = RenderScene(scene, cal.camera);
  scene.options.blur_sigma_px = 1.5;
  const camera::Image soft = RenderScene(scene, cal.camera);
  EXPECT_GT(mixed(soft), 2 * mixed(sharp));
  const Vec2 a = CoverageCentroid(sharp, 40, 250), b = CoverageCentroid(soft, 40, 250);
  EXPECT_NEAR((a - b).norm(), 0.0, 0.01);
}

// A robot is its black top cover with the pattern on it: the key in the team colour at the
// pose, the ID dots in their codebook colours (ID 0 = pink, pink, green, pink).
TEST(SceneRender, RobotWearsItsTeamAndIdColours) {
  FieldScene scene = EmptyScene();
  EXPECT_EQ(PatchColours(scene.pattern, scene.codebook, "blue", 0),
            (std::vector<std::string>{"blue", "pink", "pink", "green", "pink"}));
  const camera::Calibration cal = GoldenCalibration();
  scene.robots.push_back({"blue", 0, Pose2{-300.0, 200.0, 0.5}});
  const camera::Image image = RenderScene(scene, cal.camera);
  auto pixel_at = [&](const Vec2& model_mm) {
    const Vec2 p = *cal.camera.WorldToPixel(scene.robots[0].pose.Apply(model_mm), 140.0);
    const uint8_t* rgb = image.Row(static_cast<int>(std::lround(p.y()))) + 3 * std::lround(p.x());
    return Rgb{rgb[0], rgb[1], rgb[2]};
  };
  EXPECT_EQ(pixel_at(Vec2(0, 0)), (Rgb{35, 75, 210}));         // key
  EXPECT_EQ(pixel_at(Vec2(35, 54.772)), (Rgb{240, 95, 185}));  // front-left: pink
  EXPECT_EQ(pixel_at(Vec2(-54.772, 35)), (Rgb{70, 215, 95}));  // back-left: green
  EXPECT_EQ(pixel_at(Vec2(-80, 0)), (Rgb{30, 30, 34}));        // top cover
  EXPECT_EQ(pixel_at(Vec2(0, 120)), (Rgb{40, 100, 50}));       // field
}

TEST(SceneRender, TruthCsvListsThePosesExactly) {
  FieldScene scene = EmptyScene();
  scene.robots = {{"blue", 3, Pose2{-400.0, 850.0, 3.13}}, {"yellow", 15, Pose2{0.1, -2.5, -0.6}}};
  EXPECT_EQ(TruthCsv(scene),
            "team,id,x_mm,y_mm,theta_rad\nblue,3,-400,850,3.13\nyellow,15,0.1,-2.5,-0.6\n");
}

TEST(SceneRender, CheckNamesEveryBrokenOption) {
  RenderOptions o;
  EXPECT_TRUE(Check(o).empty());
  o.width_px = 0;
  o.supersampling = 17;
  o.robot_height_mm = -1.0;
  o.robot_radius_mm = 600.0;
  o.ball_radius_mm = 0.0;
  o.blur_sigma_px = -0.5;
  o.noise_sigma_levels = NAN;
  std::vector<std::string> messages;
  for (const OptionsProblem& p : Check(o)) messages.push_back(p.message);
  EXPECT_EQ(messages, (std::vector<std::string>{
                          "width_px is 0; expected an integer in [1, 8192]",
                          "supersampling is 17; expected an integer in [1, 16]",
                          "robot_height_mm is -1; expected a number in [0, 1000] (mm)",
                          "robot_radius_mm is 600; expected a number in [0, 500] (mm)",
                          "ball_radius_mm is 0; expected a number in (0, 500] (mm)",
                          "blur_sigma_px is -0.5; expected a number in [0, 10] (px)",
                          "noise_sigma_levels is nan; expected a number in [0, 64] (8-bit levels)",
                      }));
  EXPECT_INPUT_ERROR(Validate(o), "width_px is 0; expected an integer in [1, 8192]");
}

TEST(SceneRender, RefusesWhatItCannotDraw) {
  const camera::CameraModel camera = GoldenCalibration().camera;
  FieldScene scene = EmptyScene();
  scene.robots.push_back({"yellow", 0, Pose2{}});
  EXPECT_INPUT_ERROR(RenderScene(scene, camera),
                     "colour \"yellow\" has no RGB; expected the scene's colours to list it");
  scene.robots[0] = {"blue", 16, Pose2{}};
  EXPECT_INPUT_ERROR(
      RenderScene(scene, camera),
      "id 16 is not in the codebook of pattern \"ssl-standard\"; expected one of its 16 IDs");
}

TEST(SceneRender, NeedsAPinholeCameraAboveTheScene) {
  const camera::CameraModel camera = GoldenCalibration().camera;
  FieldScene scene = EmptyScene();
  EXPECT_INPUT_ERROR(
      RenderScene(scene, camera::CameraModel::Homographies({camera::PlaneHomography{}})),
      "the camera is a homography; expected a pinhole camera to render with");
  scene.options.robot_height_mm = 900.0;
  camera::PinholeCamera low = camera.pinhole();
  low.translation_mm = -low.rotation * Eigen::Vector3d(0, 0, 800);  // centre 800 mm up
  EXPECT_INPUT_ERROR(RenderScene(scene, camera::CameraModel::Pinhole(low)),
                     "the camera centre is at height 800 mm; expected it above the robot tops "
                     "and the ball");
}

// Scene files: every problem at its line.
class SceneFileTest : public ::testing::Test {
 protected:
  // Parses the golden scene's header lines (1-3: calibration, pattern, codebook) plus `body`.
  static void Parse(const std::string& body) {
    formats::ParseSceneFile(
        "calibration = \"ssl-frame.calibration.toml\"\n"
        "pattern = \"../../../patterns/ssl-standard.toml\"\n"
        "codebook = \"../../../patterns/ssl-standard.codebook.toml\"\n" +
            body,
        "s.toml", kGolden);
  }
  // Lines 4-9.
  const std::string colours_ =
      "[colours]\nfield = [1, 2, 3]\nbody = [0, 0, 0]\nblue = [0, 0, 255]\n"
      "pink = [255, 0, 255]\ngreen = [0, 255, 0]\n";
};

TEST_F(SceneFileTest, ReadsTheGoldenScene) {
  const formats::SceneFile file = formats::LoadSceneFile(kGolden + "ssl-frame.toml");
  EXPECT_EQ(file.scene.robots.size(), 10u);
  EXPECT_EQ(file.scene.options.width_px, 640);
  EXPECT_EQ(file.scene.options.height_px, 480);
  EXPECT_EQ(file.scene.options.seed, 2003u);
  EXPECT_EQ(file.scene.colours.at("pink"), (Rgb{240, 95, 185}));
  ASSERT_TRUE(file.scene.ball_mm.has_value());
  EXPECT_EQ(*file.scene.ball_mm, Vec2(150.0, -350.0));
  EXPECT_EQ(file.scene.robots[1].team, "blue");
  EXPECT_EQ(file.scene.robots[1].id, 3);
  EXPECT_EQ(file.scene.robots[1].pose.theta_rad, 3.13);
}

TEST_F(SceneFileTest, ReportsRenderOptionsAtTheirLine) {
  EXPECT_INPUT_ERROR(
      Parse("[render]\nnoise_sigma_levels = 100\n" + colours_),
      "s.toml:5: noise_sigma_levels is 100; expected a number in [0, 64] (8-bit levels)");
  EXPECT_INPUT_ERROR(Parse("[render]\nblur = 1\n"),
                     "s.toml:5: unknown key 'blur' in [render]; expected one of: supersampling, "
                     "robot_height_mm, robot_radius_mm, ball_radius_mm, blur_sigma_px, "
                     "noise_sigma_levels, seed");
}

TEST_F(SceneFileTest, ReportsRobotsAtTheirLine) {
  EXPECT_INPUT_ERROR(
      Parse(colours_ + "[[robot]]\nteam = \"yellow\"\nid = 1\nx_mm = 0\ny_mm = 0\ntheta_rad = 0\n"),
      "s.toml:11: team \"yellow\" has no RGB in [colours]; expected a colour listed there");
  EXPECT_INPUT_ERROR(
      Parse(colours_ + "[[robot]]\nteam = \"blue\"\nid = 99\nx_mm = 0\ny_mm = 0\ntheta_rad = 0\n"),
      "s.toml:12: id 99 is not in the codebook of pattern \"ssl-standard\"; expected one of its "
      "16 IDs");
  EXPECT_INPUT_ERROR(Parse(colours_ + "[[robot]]\nteam = \"blue\"\nx_mm = 0\n"),
                     "s.toml:10: missing id in [[robot]] 1; expected an integer");
}

TEST_F(SceneFileTest, ReportsTheBallAtItsLine) {
  EXPECT_INPUT_ERROR(Parse(colours_ + "[ball]\nx_mm = 0\ny_mm = 0\n"),
                     "s.toml:11: ball colour \"orange\" has no RGB in [colours]; expected a "
                     "colour listed there");
}

TEST_F(SceneFileTest, ReportsColoursAtTheirLine) {
  EXPECT_INPUT_ERROR(
      Parse("[colours]\nfield = [1, 2]\n"),
      "s.toml:5: field in [colours] is not [R, G, B]; expected three integers in 0..255");
  EXPECT_INPUT_ERROR(Parse("[colours]\nfield = [1, 2, 3]\n"),
                     "s.toml:4: [colours] has no \"body\"; expected the RGB of the field and of "
                     "the robots' top covers");
}

TEST_F(SceneFileTest, NeedsAReadablePinholeCalibrationWithAnImageSize) {
  EXPECT_INPUT_ERROR(
      formats::ParseSceneFile("calibration = \"nowhere.toml\"\n", "s.toml", "/tmp"),
      "s.toml:1: calibration file \"/tmp/nowhere.toml\" cannot be read; expected a readable file");
  const std::string dir = vision::testing::ScratchDir();
  vision::testing::WriteText(dir + "/h.toml",
                             "model = \"homography\"\n[[homography]]\nheight_mm = 0\n"
                             "matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n");
  EXPECT_INPUT_ERROR(formats::ParseSceneFile("calibration = \"h.toml\"\n", "s.toml", dir),
                     "s.toml:1: calibration " + dir +
                         "/h.toml is a homography; expected a pinhole camera to render with");
  vision::testing::WriteText(
      dir + "/p.toml",
      "model = \"pinhole\"\n[pinhole]\nfx_px = 1\nfy_px = 1\ncx_px = 0\ncy_px = 0\n"
      "camera_position_mm = [0, 0, 4000]\n");
  EXPECT_INPUT_ERROR(formats::ParseSceneFile("calibration = \"p.toml\"\n", "s.toml", dir),
                     "s.toml:1: calibration " + dir +
                         "/p.toml has no image_size_px; expected the size of the frame to render");
}

}  // namespace
}  // namespace patlab::render
