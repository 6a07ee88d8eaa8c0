// SSL packets from detections (live/packet.h): the golden frame's robots and ball against its
// committed expected detections and the scene's truth, decoded with the classes protoc generated
// from proto/; the geometry of a shipped field against the sizes its file states; a camera's
// quaternion against a hand-computed rotation.
#include "patlab/live/packet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../frame_test_util.h"
#include "../test_util.h"
#include "messages_robocup_ssl_wrapper.pb.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/vision/frame_io.h"

namespace patlab::live {
namespace {

using patlab::testing::kGolden;

// The golden frame's detector; with binning k, for the frame k times larger (its camera resized),
// which it bins k x k.
vision::FrameDetector GoldenDetector(int binning = 1) {
  vision::FrameDetectorOptions options;
  const std::string settings = kGolden + "ssl-frame.detector.toml";
  vision::ApplyFrameSettings(formats::LoadFrameSettings(settings), &options);
  options.binning = binning;
  const camera::Calibration calibration =
      formats::LoadCalibration(kGolden + "ssl-frame.calibration.toml");
  return vision::FrameDetector(formats::LoadThresholds(kGolden + "ssl-frame.thresholds.toml"),
                               calibration.Resized(binning, binning * calibration.image_width_px,
                                                   binning * calibration.image_height_px),
                               formats::LoadDetectorSettings(settings), options);
}

// (id, x, y, theta) of tests/data/golden/ssl-frame.expected.csv, by team.
struct Expected {
  int id;
  double x, y, theta;
};
const std::vector<Expected> kBlue = {{0, -1100.23, 699.81, 0.2964},
                                     {3, -399.88, 850.20, 3.1320},
                                     {7, 299.93, 650.12, -1.1996},
                                     {9, 1000.00, 800.00, 1.9939},
                                     {12, -900.05, -100.12, -3.1312}};
const std::vector<Expected> kYellow = {{1, -199.96, 100.10, 1.5688},
                                       {5, 599.85, -0.10, -0.5961},
                                       {8, 1150.19, -299.76, 3.0975},
                                       {14, -700.07, -750.32, -2.3969},
                                       {15, 500.30, -799.92, 0.9013}};

// The CSV's 2 and 4 decimals, and the packet's float (7 significant digits of 1000 mm).
void ExpectRobots(const google::protobuf::RepeatedPtrField<SSL_DetectionRobot>& robots,
                  const std::vector<Expected>& expected) {
  ASSERT_EQ(robots.size(), static_cast<int>(expected.size()));
  for (int i = 0; i < robots.size(); ++i) {
    const SSL_DetectionRobot& r = robots[i];
    const Expected& e = expected[static_cast<size_t>(i)];
    ASSERT_TRUE(r.has_robot_id());
    EXPECT_EQ(static_cast<int>(r.robot_id()), e.id);
    EXPECT_NEAR(r.x(), e.x, 0.006);
    EXPECT_NEAR(r.y(), e.y, 0.006);
    EXPECT_NEAR(r.orientation(), e.theta, 0.0001);
    EXPECT_GT(r.confidence(), 0.99f);
    EXPECT_TRUE(r.has_height());
  }
}

TEST(Packet, GoldenFrameDecodesToItsExpectedDetections) {
  vision::FrameDetector frames = GoldenDetector();
  const vision::FrameResult& result = frames.DetectFile(kGolden + "ssl-frame.png");
  const SslDetection detection =
      DetectionOfFrame(result, frames, FrameStamp{42, 1000.25, 1000.5, 3});
  SSL_WrapperPacket packet;
  ASSERT_TRUE(packet.ParseFromString(SerializeDetection(detection)));
  ASSERT_TRUE(packet.has_detection());
  EXPECT_FALSE(packet.has_geometry());
  const SSL_DetectionFrame& f = packet.detection();
  EXPECT_EQ(f.frame_number(), 42u);
  EXPECT_EQ(f.t_capture(), 1000.25);
  EXPECT_EQ(f.t_sent(), 1000.5);
  EXPECT_EQ(f.camera_id(), 3u);
  ExpectRobots(f.robots_blue(), kBlue);
  ExpectRobots(f.robots_yellow(), kYellow);
  // The scene's ball (tests/data/golden/ssl-frame.toml [ball]).
  ASSERT_EQ(f.balls_size(), 1);
  EXPECT_GT(f.balls(0).area(), 0u);
}

TEST(Packet, RobotPixelIsWhereTheCameraSeesThePose) {
  vision::FrameDetector frames = GoldenDetector();
  const vision::FrameResult& result = frames.DetectFile(kGolden + "ssl-frame.png");
  const SslDetection d = DetectionOfFrame(result, frames, FrameStamp{});
  ASSERT_FALSE(d.robots_blue.empty());
  const SslRobot& r = d.robots_blue.front();
  const camera::Calibration& calibration = frames.pipeline().calibration();
  EXPECT_EQ(r.height_mm, calibration.HeightOf("blue"));
  const std::optional<Vec2> back =
      calibration.camera.PixelToWorld(Vec2(r.pixel_x, r.pixel_y), r.height_mm);
  ASSERT_TRUE(back.has_value());
  EXPECT_NEAR(back->x(), r.x_mm, 1e-6);
  EXPECT_NEAR(back->y(), r.y_mm, 1e-6);
}

// A frame binned for detection ([frame] binning) is still reported in its own pixels, those of
// the camera the geometry packet describes: the golden frame at twice its size, each pixel a 2 x 2
// block, puts every robot and the ball at twice the golden frame's pixel plus a half, the ball's
// area four times as large.
TEST(Packet, BinnedFramesArePlacedInTheirOwnPixels) {
  vision::FrameDetector golden = GoldenDetector();
  const SslDetection plain =
      DetectionOfFrame(golden.DetectFile(kGolden + "ssl-frame.png"), golden, FrameStamp{});
  vision::FrameDetector binned = GoldenDetector(2);
  const camera::Image doubled =
      vision::testing::BlockUpsampled(vision::ReadFrameFile(kGolden + "ssl-frame.png", 0, 0), 2);
  const SslDetection d = DetectionOfFrame(binned.Detect(doubled, "doubled"), binned, FrameStamp{});
  ASSERT_EQ(d.robots_blue.size(), kBlue.size());
  ASSERT_EQ(d.robots_blue.size(), plain.robots_blue.size());
  for (size_t i = 0; i < d.robots_blue.size(); ++i) {
    EXPECT_NEAR(d.robots_blue[i].pixel_x, 2.0 * plain.robots_blue[i].pixel_x + 0.5, 1e-6);
    EXPECT_NEAR(d.robots_blue[i].pixel_y, 2.0 * plain.robots_blue[i].pixel_y + 0.5, 1e-6);
  }
  ASSERT_EQ(d.balls.size(), 1u);
  ASSERT_EQ(plain.balls.size(), 1u);
  EXPECT_EQ(d.balls[0].area_px, 4 * plain.balls[0].area_px);
  EXPECT_NEAR(d.balls[0].pixel_x, 2.0 * plain.balls[0].pixel_x + 0.5, 1e-9);
  EXPECT_NEAR(d.balls[0].pixel_y, 2.0 * plain.balls[0].pixel_y + 0.5, 1e-9);
}

TEST(Packet, ReadsBackWhatItWrote) {
  SslDetection d{7, 1.5, 2.5, 1, {{1.0, 30, 10.0, -20.0, 21.5, 100.0, 200.0}}, {}, {}};
  d.robots_blue.push_back({0.5, -1, 100.0, 200.0, 0.25, 300.0, 400.0, 150.0});
  const std::optional<SslPacket> back = ParsePacket(SerializeDetection(d));
  ASSERT_TRUE(back.has_value() && back->detection.has_value());
  EXPECT_EQ(back->detection->frame_number, 7u);
  ASSERT_EQ(back->detection->robots_blue.size(), 1u);
  EXPECT_EQ(back->detection->robots_blue[0].robot_id, -1);  // not sent
  EXPECT_EQ(back->detection->balls[0].area_px, 30);
  EXPECT_EQ(back->detection->balls[0].z_mm, 21.5);
  EXPECT_FALSE(ParsePacket("\xff\xff\xff").has_value());
}

TEST(Packet, JsonHasTheMessageFieldNames) {
  SslDetection d{7, 1.5, 2.5, 1, {{1.0, 30, 10.0, -20.0, 21.5, 100.0, 200.0}}, {}, {}};
  d.robots_blue.push_back({0.5, 4, 100.0, 200.0, 0.25, 300.0, 400.0, 150.0});
  EXPECT_EQ(DetectionJson(d),
            "{\"frame_number\":7,\"t_capture\":1.5,\"t_sent\":2.5,\"camera_id\":1,"
            "\"balls\":[{\"confidence\":1,\"area\":30,\"x\":10,\"y\":-20,\"z\":21.5,"
            "\"pixel_x\":100,\"pixel_y\":200}],\"robots_yellow\":[],"
            "\"robots_blue\":[{\"confidence\":0.5,\"robot_id\":4,\"x\":100,\"y\":200,"
            "\"orientation\":0.25,\"pixel_x\":300,\"pixel_y\":400,\"height\":150}]}");
}

TEST(Packet, GeometryOfTheSsl2009Field) {
  // experiments/fields/ssl-2009.toml states field_length 6050, field_width 4050.
  const calib::Field field =
      formats::LoadField(std::string(PATLAB_SOURCE_DIR) + "/experiments/fields/ssl-2009.toml");
  SSL_WrapperPacket packet;
  ASSERT_TRUE(packet.ParseFromString(SerializeGeometry(GeometryOf(field, {}))));
  ASSERT_TRUE(packet.has_geometry());
  const SSL_GeometryFieldSize& f = packet.geometry().field();
  EXPECT_EQ(f.field_length(), 6050);
  EXPECT_EQ(f.field_width(), 4050);
  EXPECT_EQ(f.field_lines_size(), static_cast<int>(field.lines.size()));
  EXPECT_EQ(f.field_arcs_size(), static_cast<int>(field.circles.size()));
  // The centre circle is whole; the defense arc about (3025, 175) runs from 90 to 180 degrees.
  EXPECT_EQ(f.field_arcs(0).a2() - f.field_arcs(0).a1(), static_cast<float>(2 * std::numbers::pi));
  EXPECT_EQ(f.field_arcs(1).name(), "defense_arc_left_pos");
  EXPECT_EQ(f.field_arcs(1).a1(), static_cast<float>(std::numbers::pi / 2));
  EXPECT_EQ(f.field_arcs(1).a2(), static_cast<float>(std::numbers::pi));
  const SSL_FieldLineSegment& halfway = f.field_lines(4);
  EXPECT_EQ(halfway.name(), "halfway");
  EXPECT_EQ(halfway.p1().y(), -2025.0f);
  EXPECT_EQ(packet.geometry().calib_size(), 0);
}

TEST(Packet, CameraQuaternionAndCentre) {
  // A camera turned 90 degrees about z: q = (0, 0, sin 45, cos 45); X_c = R X_w + t with
  // t = (100, 200, 3000), so the centre -R^T t = -(200, -100, 3000) for R = [[0,-1,0],[1,0,0],
  // [0,0,1]].
  camera::PinholeCamera p;
  p.fx_px = 500.0;
  p.fy_px = 520.0;
  p.rotation << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  p.translation_mm = Eigen::Vector3d(100, 200, 3000);
  camera::Calibration calibration;
  calibration.camera = camera::CameraModel::Pinhole(p);
  const std::optional<SslCameraCalibration> c = CameraCalibrationOf(calibration, 2);
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->focal_length_px, 510.0);
  EXPECT_NEAR(c->q0, 0.0, 1e-12);
  EXPECT_NEAR(c->q1, 0.0, 1e-12);
  EXPECT_NEAR(c->q2, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(c->q3, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(c->camera_world_x_mm, -200.0, 1e-9);
  EXPECT_NEAR(c->camera_world_y_mm, 100.0, 1e-9);
  EXPECT_NEAR(c->camera_world_z_mm, -3000.0, 1e-9);
  camera::Calibration homographies;
  homographies.camera = camera::CameraModel::Homographies({camera::PlaneHomography{}});
  EXPECT_FALSE(CameraCalibrationOf(homographies, 0).has_value());
}

}  // namespace
}  // namespace patlab::live
