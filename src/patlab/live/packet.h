// SSL-Vision packets from patlab's detections: the detection frame of one camera and the
// geometry (field and camera calibrations), as plain structs and as the bytes of an
// SSL_WrapperPacket (proto/messages_robocup_ssl_wrapper.proto). The structs are what `patlab
// live --jsonl` writes and what a decoded packet reads back into, so that every consumer sees
// the same fields.
//
// Frame convention. SSL-Vision sends millimetres from the field centre, x along the field's
// length (towards the goal the receiving team defines as the opponent's), y 90 degrees counter-
// clockwise from x, orientations in radians counter-clockwise from +x. patlab's calibrations
// map pixels to the field files' frame (experiments/fields/*.toml: origin at the centre mark, x
// towards the "pos" goal, y to the left looking along +x, z up, mm), which is that convention
// with +x towards the "pos" goal: positions and headings are sent as the calibration gives them.
// A team that attacks the "neg" goal turns them by 180 degrees in its AI, as it would with
// SSL-Vision (docs/live.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "patlab/calib/field.h"
#include "patlab/camera/camera.h"
#include "patlab/vision/frame_detector.h"

namespace patlab::live {

struct SslRobot {
  double confidence = 0.0;  // the detection's confidence (detect::Detection::confidence), [0, 1]
  int robot_id = -1;        // codebook ID; -1: unknown (not sent)
  double x_mm = 0.0, y_mm = 0.0;
  double orientation_rad = 0.0;
  double pixel_x = 0.0, pixel_y = 0.0;  // where the pose's origin appears in the frame (px)
  double height_mm = 0.0;               // the plane the pattern was mapped on
  // robot_id was carried over from the robot's earlier frames (id_hold.h), not read in this
  // frame; not in the packet, written to the JSON line as "id_held":true.
  bool id_held = false;
};

struct SslBall {
  double confidence = 0.0;
  int area_px = 0;
  double x_mm = 0.0, y_mm = 0.0, z_mm = 0.0;  // z: the ball class's plane height
  double pixel_x = 0.0, pixel_y = 0.0;
};

// One camera's detections of one frame (SSL_DetectionFrame).
struct SslDetection {
  uint32_t frame_number = 0;
  double t_capture_s = 0.0;  // capture time, seconds since the Unix epoch
  double t_sent_s = 0.0;     // send time, seconds since the Unix epoch
  uint32_t camera_id = 0;
  std::vector<SslBall> balls;
  std::vector<SslRobot> robots_yellow;
  std::vector<SslRobot> robots_blue;
};

// What identifies a frame in the packet.
struct FrameStamp {
  uint32_t frame_number = 0;
  double t_capture_s = 0.0;
  double t_sent_s = 0.0;
  uint32_t camera_id = 0;
};

// The names a team colour and the ball have in the detector's palette and the thresholds'
// classes. Detections of other team colours are not sent (SSL-Vision knows two teams).
struct SslColourNames {
  std::string yellow = "yellow";
  std::string blue = "blue";
  std::string ball = "orange";  // a thresholds class of this name gives the balls; none: no balls
};

// The SSL detection of one frame's results. Robots: the detections whose key colour is the
// yellow or blue team's, with status ok or missing_patch (ambiguous ones, whose rotation is not
// known, are left out), robot_id when the ID is known; height (the key colour's plane) and pixel
// position through the FrameDetector's calibration. Balls: every blob of the ball class,
// confidence 1. Robots and balls keep the detector's fixed order (docs/architecture.md rule 2).
SslDetection DetectionOfFrame(const vision::FrameResult& result,
                              const vision::FrameDetector& frames, const FrameStamp& stamp,
                              const SslColourNames& names = {});

// A camera's calibration as SSL_GeometryCameraCalibration (SSL-Vision's pinhole: one focal
// length, principal point, one radial distortion coefficient, the world-to-camera rotation as a
// unit quaternion and the translation). nullopt for a homography calibration, which has no
// such parameters.
struct SslCameraCalibration {
  uint32_t camera_id = 0;
  double focal_length_px = 0.0;  // the mean of fx and fy
  double principal_point_x = 0.0, principal_point_y = 0.0;
  double distortion = 0.0;  // patlab's k1 (Brown-Conrady on normalised coordinates)
  double q0 = 0.0, q1 = 0.0, q2 = 0.0, q3 = 1.0;  // x, y, z, w of the world -> camera rotation
  double tx_mm = 0.0, ty_mm = 0.0, tz_mm = 0.0;   // X_camera = R X_world + t
  double camera_world_x_mm = 0.0, camera_world_y_mm = 0.0, camera_world_z_mm = 0.0;  // -R^T t
  int image_width_px = 0, image_height_px = 0;
};
std::optional<SslCameraCalibration> CameraCalibrationOf(const camera::Calibration& calibration,
                                                        uint32_t camera_id);

struct SslLine {
  std::string name;
  double x1_mm = 0.0, y1_mm = 0.0, x2_mm = 0.0, y2_mm = 0.0;
  double thickness_mm = 10.0;
};
struct SslArc {
  std::string name;
  double centre_x_mm = 0.0, centre_y_mm = 0.0, radius_mm = 0.0;
  double a1_rad = 0.0, a2_rad = 0.0;
  double thickness_mm = 10.0;
};
struct SslGeometry {
  int field_length_mm = 0, field_width_mm = 0, goal_width_mm = 0, goal_depth_mm = 0;
  int boundary_width_mm = 0;
  std::vector<SslLine> lines;
  std::vector<SslArc> arcs;
  std::vector<SslCameraCalibration> cameras;
};
// The geometry of `field` (calib/field.h): every line as a segment and every circle as a full
// arc, 10 mm thick (the rules' line width); field length and width from the lines' extent (the
// goal lines and touch lines); goal width and depth from lines named goal_* when the field has
// them, else 0. `cameras`: the calibrations in camera id order; homographies are left out.
SslGeometry GeometryOf(const calib::Field& field, const std::vector<camera::Calibration>& cameras);

// The bytes of an SSL_WrapperPacket holding the detection or the geometry.
std::string SerializeDetection(const SslDetection& detection);
std::string SerializeGeometry(const SslGeometry& geometry);

// A packet read back: the detection and/or geometry it holds; nullopt when the bytes are no
// SSL_WrapperPacket.
struct SslPacket {
  std::optional<SslDetection> detection;
  std::optional<SslGeometry> geometry;
};
std::optional<SslPacket> ParsePacket(const std::string& bytes);

// One JSON object (one line, no newline) with the detection's fields under the protobuf
// messages' field names: what `patlab live --jsonl` writes per frame. A robot whose ID was
// carried over (SslRobot::id_held) has "id_held":true after its robot_id, which no packet field
// has; other robots have no such key.
std::string DetectionJson(const SslDetection& detection);

}  // namespace patlab::live
