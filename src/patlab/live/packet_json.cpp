// The JSON line of a detection (packet.h DetectionJson): the protobuf field names, numbers as the
// packet carries them (floats widened to double and written to round-trip, core/format.h).
#include "patlab/core/format.h"
#include "patlab/live/packet.h"

namespace patlab::live {

namespace {

// A float field as the packet holds it.
std::string Float(double v) { return FormatRoundTrip(static_cast<double>(static_cast<float>(v))); }

std::string RobotJson(const SslRobot& r) {
  std::string s = "{\"confidence\":" + Float(r.confidence);
  if (r.robot_id >= 0) s += ",\"robot_id\":" + std::to_string(r.robot_id);
  if (r.id_held) s += ",\"id_held\":true";
  s += ",\"x\":" + Float(r.x_mm) + ",\"y\":" + Float(r.y_mm) +
       ",\"orientation\":" + Float(r.orientation_rad) + ",\"pixel_x\":" + Float(r.pixel_x) +
       ",\"pixel_y\":" + Float(r.pixel_y) + ",\"height\":" + Float(r.height_mm) + "}";
  return s;
}

std::string BallJson(const SslBall& b) {
  return "{\"confidence\":" + Float(b.confidence) + ",\"area\":" + std::to_string(b.area_px) +
         ",\"x\":" + Float(b.x_mm) + ",\"y\":" + Float(b.y_mm) + ",\"z\":" + Float(b.z_mm) +
         ",\"pixel_x\":" + Float(b.pixel_x) + ",\"pixel_y\":" + Float(b.pixel_y) + "}";
}

template <typename T, typename F>
std::string Array(const std::vector<T>& items, F item_json) {
  std::string s = "[";
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) s += ",";
    s += item_json(items[i]);
  }
  return s + "]";
}

}  // namespace

std::string DetectionJson(const SslDetection& d) {
  return "{\"frame_number\":" + std::to_string(d.frame_number) +
         ",\"t_capture\":" + FormatRoundTrip(d.t_capture_s) +
         ",\"t_sent\":" + FormatRoundTrip(d.t_sent_s) +
         ",\"camera_id\":" + std::to_string(d.camera_id) +
         ",\"balls\":" + Array(d.balls, BallJson) +
         ",\"robots_yellow\":" + Array(d.robots_yellow, RobotJson) +
         ",\"robots_blue\":" + Array(d.robots_blue, RobotJson) + "}";
}

}  // namespace patlab::live
