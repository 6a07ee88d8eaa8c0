// Detections and field geometry into the SSL structs (packet.h). Serialization is in
// packet_proto.cpp, the JSON form in packet_json.cpp.
#include "patlab/live/packet.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace patlab::live {

namespace {

SslRobot RobotOf(const detect::Detection& d, const camera::Calibration& calibration,
                 const std::string& key_colour) {
  SslRobot robot;
  robot.confidence = d.confidence;
  robot.robot_id = d.id;
  robot.x_mm = d.pose.x_mm;
  robot.y_mm = d.pose.y_mm;
  robot.orientation_rad = d.pose.theta_rad;
  robot.height_mm = calibration.HeightOf(key_colour);
  const std::optional<Vec2> pixel =
      calibration.camera.WorldToPixel(Vec2(d.pose.x_mm, d.pose.y_mm), robot.height_mm);
  if (pixel) {
    robot.pixel_x = pixel->x();
    robot.pixel_y = pixel->y();
  }
  return robot;
}

void AddRobots(const vision::FrameResult& result, const vision::FrameDetector& frames,
               const SslColourNames& names, SslDetection* out) {
  if (!frames.has_detector()) return;
  const std::vector<std::string>& palette = frames.detector().config().palette;
  const camera::Calibration& calibration = frames.frame_calibration();  // the frames' pixels
  for (const detect::Detection& d : result.detections) {
    if (d.status == detect::DetectionStatus::kAmbiguous || d.team_colour < 0) continue;
    const std::string& colour = palette[static_cast<size_t>(d.team_colour)];
    if (colour == names.yellow) {
      out->robots_yellow.push_back(RobotOf(d, calibration, colour));
    } else if (colour == names.blue) {
      out->robots_blue.push_back(RobotOf(d, calibration, colour));
    }
  }
}

void AddBalls(const vision::FrameResult& result, const vision::FrameDetector& frames,
              const SslColourNames& names, SslDetection* out) {
  const int ball_class = frames.pipeline().thresholds().Find(names.ball);
  if (ball_class < 0) return;
  const double height_mm = frames.frame_calibration().HeightOf(names.ball);
  for (size_t i = 0; i < result.blobs.size(); ++i) {
    const detect::Blob& blob = result.blobs[i];
    if (blob.colour != ball_class) continue;
    SslBall ball;
    ball.confidence = 1.0;
    ball.x_mm = blob.position_mm.x();
    ball.y_mm = blob.position_mm.y();
    ball.z_mm = height_mm;
    if (i < result.blob_regions.size()) {
      ball.area_px = result.blob_regions[i].area_px;
      ball.pixel_x = result.blob_regions[i].centroid_px.x();
      ball.pixel_y = result.blob_regions[i].centroid_px.y();
    }
    out->balls.push_back(ball);
  }
}

bool StartsWith(const std::string& text, std::string_view prefix) {
  return text.size() >= prefix.size() && text.compare(0, prefix.size(), prefix) == 0;
}

// Length and width from the extent of the lines; the goal's from lines named goal_* other than
// the goal lines (a goal drawn as its posts and back).
void SetSizes(const calib::Field& field, SslGeometry* g) {
  double max_x = 0.0, max_y = 0.0, goal_y = 0.0, goal_x = 0.0, goal_line_x = 0.0;
  for (const calib::FieldLine& line : field.lines) {
    for (const Vec2& p : {line.from_mm, line.to_mm}) {
      const bool goal = StartsWith(line.name, "goal_") && !StartsWith(line.name, "goal_line");
      if (goal) {
        goal_y = std::max(goal_y, std::abs(p.y()));
        goal_x = std::max(goal_x, std::abs(p.x()));
      } else {
        max_x = std::max(max_x, std::abs(p.x()));
        max_y = std::max(max_y, std::abs(p.y()));
      }
      if (StartsWith(line.name, "goal_line")) goal_line_x = std::max(goal_line_x, std::abs(p.x()));
    }
  }
  g->field_length_mm = static_cast<int>(std::lround(2.0 * max_x));
  g->field_width_mm = static_cast<int>(std::lround(2.0 * max_y));
  g->goal_width_mm = static_cast<int>(std::lround(2.0 * goal_y));
  g->goal_depth_mm = goal_x > goal_line_x ? static_cast<int>(std::lround(goal_x - goal_line_x)) : 0;
}

}  // namespace

SslDetection DetectionOfFrame(const vision::FrameResult& result,
                              const vision::FrameDetector& frames, const FrameStamp& stamp,
                              const SslColourNames& names) {
  SslDetection out;
  out.frame_number = stamp.frame_number;
  out.t_capture_s = stamp.t_capture_s;
  out.t_sent_s = stamp.t_sent_s;
  out.camera_id = stamp.camera_id;
  AddBalls(result, frames, names, &out);
  AddRobots(result, frames, names, &out);
  return out;
}

std::optional<SslCameraCalibration> CameraCalibrationOf(const camera::Calibration& calibration,
                                                        uint32_t camera_id) {
  if (!calibration.camera.is_pinhole()) return std::nullopt;
  const camera::PinholeCamera& p = calibration.camera.pinhole();
  SslCameraCalibration c;
  c.camera_id = camera_id;
  c.focal_length_px = 0.5 * (p.fx_px + p.fy_px);
  c.principal_point_x = p.cx_px;
  c.principal_point_y = p.cy_px;
  c.distortion = p.k1;
  const Eigen::Quaterniond q(p.rotation);
  c.q0 = q.x();
  c.q1 = q.y();
  c.q2 = q.z();
  c.q3 = q.w();
  c.tx_mm = p.translation_mm.x();
  c.ty_mm = p.translation_mm.y();
  c.tz_mm = p.translation_mm.z();
  const Eigen::Vector3d centre = -p.rotation.transpose() * p.translation_mm;
  c.camera_world_x_mm = centre.x();
  c.camera_world_y_mm = centre.y();
  c.camera_world_z_mm = centre.z();
  c.image_width_px = calibration.image_width_px;
  c.image_height_px = calibration.image_height_px;
  return c;
}

SslGeometry GeometryOf(const calib::Field& field, const std::vector<camera::Calibration>& cameras) {
  SslGeometry g;
  SetSizes(field, &g);
  for (const calib::FieldLine& line : field.lines) {
    g.lines.push_back(
        {line.name, line.from_mm.x(), line.from_mm.y(), line.to_mm.x(), line.to_mm.y(), 10.0});
  }
  for (const calib::FieldCircle& circle : field.circles) {
    // The arc's extent (a full circle: 0 to 2 pi), in radians as SSL_FieldCircularArc has it.
    constexpr double kRad = std::numbers::pi / 180.0;
    g.arcs.push_back({circle.name, circle.centre_mm.x(), circle.centre_mm.y(), circle.radius_mm,
                      circle.from_deg * kRad, circle.to_deg * kRad, 10.0});
  }
  for (size_t id = 0; id < cameras.size(); ++id) {
    if (auto c = CameraCalibrationOf(cameras[id], static_cast<uint32_t>(id))) {
      g.cameras.push_back(*c);
    }
  }
  return g;
}

}  // namespace patlab::live
