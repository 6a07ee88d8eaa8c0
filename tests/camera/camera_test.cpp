#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/formats/calibration_file.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../frame_test_util.h"

namespace patlab::camera {
namespace {

constexpr double kTol = 1e-9;

// A camera 4000 mm above the floor looking straight down, f = 500 px, no distortion: the plane
// at height h is seen at 500 / (4000 - h) px per mm.
PinholeCamera Overhead(double k1 = 0.0, double k2 = 0.0) {
  const Calibration cal = formats::ParseCalibration(
      "model = \"pinhole\"\n[pinhole]\nfx_px = 500\nfy_px = 500\ncx_px = 320\ncy_px = 240\n"
      "k1 = " +
          std::to_string(k1) + "\nk2 = " + std::to_string(k2) +
          "\ncamera_position_mm = [100, 200, 4000]\nyaw_deg = 0\n",
      "c.toml");
  return cal.camera.pinhole();
}

TEST(Camera, OverheadPinholeMapsTheImageCentreBelowTheCamera) {
  const CameraModel cam = CameraModel::Pinhole(Overhead());
  const Vec2 w = *cam.PixelToWorld(Vec2(320, 240), 140);
  EXPECT_NEAR(w.x(), 100, kTol);
  EXPECT_NEAR(w.y(), 200, kTol);
  // One pixel right is +x, one pixel down is -y (image y points down, world y up).
  const Vec2 right = *cam.PixelToWorld(Vec2(321, 240), 140);
  const Vec2 down = *cam.PixelToWorld(Vec2(320, 241), 140);
  EXPECT_NEAR(right.x() - 100, 3860.0 / 500.0, kTol);
  EXPECT_NEAR(down.y() - 200, -3860.0 / 500.0, kTol);
  EXPECT_NEAR(cam.AreaScale(Vec2(100, 400), 140), std::pow(3860.0 / 500.0, 2), 1e-6);
}

TEST(Camera, PinholeRoundTripWithDistortion) {
  const CameraModel cam = CameraModel::Pinhole(Overhead(-0.25, 0.05));
  for (double u : {0.0, 100.5, 320.0, 639.0}) {
    for (double v : {0.0, 240.0, 479.0}) {
      for (double h : {0.0, 21.5, 140.0}) {
        const auto w = cam.PixelToWorld(Vec2(u, v), h);
        ASSERT_TRUE(w.has_value());
        const Vec2 back = *cam.WorldToPixel(*w, h);
        EXPECT_NEAR(back.x(), u, 1e-9);
        EXPECT_NEAR(back.y(), v, 1e-9);
      }
    }
  }
}

TEST(Camera, BarrelDistortionPullsCornersIn) {
  // With k1 < 0 a world point far from the axis appears closer to the image centre.
  const CameraModel plain = CameraModel::Pinhole(Overhead());
  const CameraModel barrel = CameraModel::Pinhole(Overhead(-0.2));
  const Vec2 world(100 + 2000, 200 - 1500);
  const Vec2 p = *plain.WorldToPixel(world, 0);
  const Vec2 b = *barrel.WorldToPixel(world, 0);
  EXPECT_LT((b - Vec2(320, 240)).norm(), (p - Vec2(320, 240)).norm());
  // Distorted radius = r (1 + k1 r^2) on normalised coordinates (r = 2500 / 4000).
  const double r = 2500.0 / 4000.0;
  EXPECT_NEAR((b - Vec2(320, 240)).norm(), 500 * r * (1 - 0.2 * r * r), 1e-9);
}

TEST(Camera, NothingBeyondTheFoldOfTheDistortionIsProjected) {
  // k1 = -0.3: r (1 + k1 r^2) stops growing at r^2 = 1 / 0.9, i.e. 4000 mm / 1.054 = 4216 mm
  // from the nadir on the floor. Points beyond it would land back inside the image.
  const CameraModel cam = CameraModel::Pinhole(Overhead(-0.3));
  EXPECT_TRUE(cam.WorldToPixel(Vec2(100 + 4100, 200), 0).has_value());
  EXPECT_FALSE(cam.WorldToPixel(Vec2(100 + 4300, 200), 0).has_value());
  EXPECT_FALSE(cam.WorldToPixel(Vec2(100, 200 - 9000), 0).has_value());
}

TEST(Camera, OpenCvExtrinsicsAgreeWithOverheadForm) {
  // Camera looking down: rotation of pi about x maps world (x, y, z) to camera (x, -y, -z).
  const Calibration cal = formats::ParseCalibration(
      "model = \"pinhole\"\n[pinhole]\nfx_px = 500\nfy_px = 500\ncx_px = 320\ncy_px = 240\n"
      "rotation_rodrigues = [3.141592653589793, 0, 0]\ntranslation_mm = [-100, 200, 4000]\n",
      "c.toml");
  const CameraModel overhead = CameraModel::Pinhole(Overhead());
  for (const Vec2& px : {Vec2(0, 0), Vec2(500, 100), Vec2(320, 240)}) {
    const Vec2 a = *cal.camera.PixelToWorld(px, 140), b = *overhead.PixelToWorld(px, 140);
    EXPECT_NEAR(a.x(), b.x(), 1e-6);
    EXPECT_NEAR(a.y(), b.y(), 1e-6);
  }
}

TEST(Camera, HomographyForAPlaneHeight) {
  // The pattern sheet: 1 px = 1 mm, y up, origin at the bottom-left of an 800 px image.
  const Calibration cal = formats::ParseCalibration(
      "model = \"homography\"\n[[homography]]\nheight_mm = 0\n"
      "matrix = [[1, 0, 0], [0, -1, 800], [0, 0, 1]]\n[heights]\ndefault_mm = 0\n",
      "h.toml");
  const Vec2 w = *cal.camera.PixelToWorld(Vec2(100, 700), 0);
  EXPECT_NEAR(w.x(), 100, kTol);
  EXPECT_NEAR(w.y(), 100, kTol);
  EXPECT_NEAR(cal.camera.AreaScale(Vec2(3, 4), 0), 1.0, kTol);
  EXPECT_FALSE(cal.camera.PixelToWorld(Vec2(100, 700), 140).has_value());
  EXPECT_FALSE(cal.camera.SupportsHeight(140));
  const Vec2 p = *cal.camera.WorldToPixel(Vec2(100, 100), 0.2);
  EXPECT_NEAR(p.y(), 700, kTol);
}

TEST(Camera, ProjectiveHomographyMatchesItsDefinition) {
  Eigen::Matrix3d h;
  h << 2, 0.1, 5, -0.2, 1.5, 7, 1e-3, 2e-3, 1;
  const CameraModel cam = CameraModel::Homographies({PlaneHomography{50, h}});
  const Eigen::Vector3d w = h * Eigen::Vector3d(10, 20, 1);
  const Vec2 expect(w.x() / w.z(), w.y() / w.z());
  EXPECT_NEAR((*cam.PixelToWorld(Vec2(10, 20), 50) - expect).norm(), 0, 1e-12);
  EXPECT_NEAR((*cam.WorldToPixel(expect, 50) - Vec2(10, 20)).norm(), 0, 1e-9);
}

TEST(Camera, RecordedResidualsAreReadAndLookedUpByHeight) {
  const std::string head =
      "model = \"homography\"\n[[homography]]\nheight_mm = 0\n"
      "matrix = [[1, 0, 0], [0, -1, 800], [0, 0, 1]]\n[heights]\ndefault_mm = 0\n";
  // An old file: no rows, residual 0.
  EXPECT_EQ(formats::ParseCalibration(head, "c.toml").ResidualRmsMm(0.0), 0.0);
  const Calibration cal = formats::ParseCalibration(
      head +
          "[[residual]]\nheight_mm = 140\nrms_mm = 8.5\nworst_mm = 30\nmeasured = false\n"
          "[[residual]]\nheight_mm = 0\nrms_mm = 3.25\n",
      "c.toml");
  ASSERT_EQ(cal.residuals.size(), 2u);  // sorted by height
  EXPECT_EQ(cal.residuals[0].height_mm, 0.0);
  EXPECT_EQ(cal.residuals[0].worst_mm, 3.25);  // defaults to rms_mm
  EXPECT_TRUE(cal.residuals[0].measured);
  EXPECT_FALSE(cal.residuals[1].measured);
  EXPECT_EQ(cal.ResidualRmsMm(0.0), 3.25);
  EXPECT_EQ(cal.ResidualRmsMm(140.3), 8.5);
  EXPECT_EQ(cal.ResidualRmsMm(100.0), 8.5);  // the nearest height
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(head + "[[residual]]\nheight_mm = 0\nrms_mm = -1\n", "c.toml"),
      "c.toml:9: rms_mm is -1 in [[residual]] 1; expected a residual >= 0 (mm)");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(head + "[[residual]]\nheight_mm = 0\nrms_mm = 2\nworst_mm = 1\n",
                                "c.toml"),
      "c.toml:10: worst_mm is 1 in [[residual]] 1; expected at least rms_mm (2)");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(head + "[[residual]]\nheight_mm = 0\nrms_mm = 2\n[[residual]]\n"
                                       "height_mm = 0.2\nrms_mm = 2\n",
                                "c.toml"),
      "c.toml:11: height_mm 0.2 in [[residual]] 2 repeats an earlier residual; expected one per "
      "height");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(head + "[[residual]]\nheight_mm = 0\nrms = 2\n", "c.toml"),
      "c.toml:9: unknown key 'rms' in [[residual]] 1; expected one of: height_mm, rms_mm, "
      "worst_mm, measured");
}

TEST(Camera, CalibrationErrorsNameFileAndLine) {
  EXPECT_INPUT_ERROR(formats::ParseCalibration("model = \"fisheye\"\n", "c.toml"),
                     "c.toml:1: model is \"fisheye\"; expected \"pinhole\" or \"homography\"");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(
          "model = \"pinhole\"\n[pinhole]\nfx_px = -5\nfy_px = 1\ncx_px = 0\ncy_px = 0\n"
          "camera_position_mm = [0, 0, 1]\n",
          "c.toml"),
      "c.toml:3: fx_px in [pinhole] is -5; expected > 0");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(
          "model = \"pinhole\"\n[pinhole]\nfx_px = 5\nfy_px = 1\ncx_px = 0\ncy_px = 0\n", "c.toml"),
      "c.toml:3: [pinhole] needs exactly one form of extrinsics; expected rotation_rodrigues and "
      "translation_mm, or camera_position_mm and yaw_deg");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(
          "model = \"pinhole\"\n[pinhole]\nfx_px = 5\nfy_px = 1\ncx_px = 0\ncy_px = 0\n"
          "camera_position_mm = [0, 0]\n",
          "c.toml"),
      "c.toml:7: camera_position_mm in [pinhole] is malformed; expected [x, y, z] in mm");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration("model = \"homography\"\n[[homography]]\nheight_mm = 0\n"
                                "matrix = [[1, 2, 3], [2, 4, 6], [0, 0, 1]]\n",
                                "h.toml"),
      "h.toml:4: matrix in [[homography]] 1 is singular; expected an invertible homography");
  EXPECT_INPUT_ERROR(
      formats::ParseCalibration(
          "model = \"homography\"\n[[homography]]\nheight_mm = 0\nmatrix = [[1, 0], [0, 1]]\n",
          "h.toml"),
      "h.toml:4: matrix in [[homography]] 1 is malformed; expected 3 rows of 3 numbers");
  EXPECT_INPUT_ERROR(formats::ParseCalibration("model = \"homography\"\n", "h.toml"),
                     "h.toml:1: model = \"homography\" needs [[homography]] tables; expected "
                     "height_mm and matrix");
  EXPECT_INPUT_ERROR(formats::ParseCalibration(
                         "model = \"homography\"\n[[homography]]\nheight_mm = 0\n"
                         "matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n[heights]\nball = \"low\"\n",
                         "h.toml"),
                     "h.toml:6: ball in [heights] is a string; expected a number");
}

// BinImage: each k x k block's mean, rounded, in RGB whatever the frame's format; the rows and
// columns that fill no block are dropped.
TEST(BinImage, EachPixelIsItsBlocksMean) {
  Image image = Image::Rgb(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x)
      for (int c = 0; c < 3; ++c) image.Row(y)[3 * x + c] = static_cast<uint8_t>(10 * x + y + c);
  Image binned;
  BinImage(image, 2, &binned);
  ASSERT_EQ(binned.width_px, 2);
  ASSERT_EQ(binned.height_px, 1);
  // Block (0, 0): x 0..1, y 0..1 -> mean of 0, 10, 1, 11 (+c) = 5.5 -> 6; block (1, 0): 25.5 -> 26.
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(binned.Row(0)[c], 6 + c);
    EXPECT_EQ(binned.Row(0)[3 + c], 26 + c);
  }
  BinImage(image, 1, &binned);
  EXPECT_EQ(binned.data, image.data);
  // A UYVY frame is binned as its RGB conversion.
  Image even = Image::Rgb(4, 2);
  for (size_t i = 0; i < even.data.size(); ++i) even.data[i] = static_cast<uint8_t>(37 * i % 251);
  const Image uyvy = ToUyvy(even);
  Image from_uyvy, from_rgb;
  BinImage(uyvy, 2, &from_uyvy);
  BinImage(ToRgb(uyvy), 2, &from_rgb);
  EXPECT_EQ(from_uyvy.data, from_rgb.data);
  EXPECT_EQ(from_uyvy.format, PixelFormat::kRgb8);
}

// A camera resized by s sees at pixel s (p + 0.5) - 0.5 what it saw at p: a pinhole's focal
// lengths and principal point scale, a homography gains the change; resizing back is the
// camera itself.
TEST(CameraModel, AResizedCameraSeesAtThePixelsOfTheResizedFrame) {
  const CameraModel pinhole = CameraModel::Pinhole(Overhead(-0.1, 0.02));
  Eigen::Matrix3d h;
  h << 2.0, 0.1, -400.0, -0.05, -2.0, 300.0, 1e-5, 2e-5, 1.0;
  const CameraModel homography = CameraModel::Homographies({{0.0, h}});
  for (const CameraModel* camera : {&pinhole, &homography}) {
    for (const double s : {0.5, 1.0 / 3.0, 2.0}) {
      const CameraModel resized = camera->Resized(s);
      for (const Vec2& p : {Vec2(100.0, 80.0), Vec2(320.0, 240.0), Vec2(511.5, 7.25)}) {
        const auto want = camera->PixelToWorld(p, 0.0);
        const auto got = resized.PixelToWorld(s * (p + Vec2(0.5, 0.5)) - Vec2(0.5, 0.5), 0.0);
        ASSERT_TRUE(want && got);
        EXPECT_NEAR(got->x(), want->x(), 1e-6);
        EXPECT_NEAR(got->y(), want->y(), 1e-6);
      }
      const auto back = resized.Resized(1.0 / s).PixelToWorld(Vec2(200.0, 150.0), 0.0);
      EXPECT_NEAR(back->x(), camera->PixelToWorld(Vec2(200.0, 150.0), 0.0)->x(), 1e-6);
    }
  }
  const PinholeCamera binned = pinhole.Resized(0.5).pinhole();
  EXPECT_DOUBLE_EQ(binned.fx_px, 250.0);
  EXPECT_DOUBLE_EQ(binned.cx_px, 159.75);  // (320 + 0.5) / 2 - 0.5
  EXPECT_DOUBLE_EQ(binned.k1, -0.1);
  // A calibration keeps its heights and residuals and takes the size given.
  Calibration c;
  c.camera = pinhole;
  c.image_width_px = 640;
  c.image_height_px = 480;
  c.default_height_mm = 140.0;
  c.residuals = {{0.0, 1.5, 3.0, true}};
  const Calibration r = c.Resized(0.5, 320, 240);
  EXPECT_EQ(r.image_width_px, 320);
  EXPECT_EQ(r.image_height_px, 240);
  EXPECT_EQ(r.default_height_mm, 140.0);
  EXPECT_EQ(r.ResidualRmsMm(0.0), 1.5);
  c.image_width_px = c.image_height_px = 0;  // any size: stays any size
  EXPECT_EQ(c.Resized(0.5, 320, 240).image_width_px, 0);
}

}  // namespace
}  // namespace patlab::camera
