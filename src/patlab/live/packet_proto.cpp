// The SSL structs (packet.h) to and from the generated protobuf classes of proto/.
#include "messages_robocup_ssl_wrapper.pb.h"
#include "patlab/live/packet.h"

namespace patlab::live {

namespace {

float F(double v) { return static_cast<float>(v); }

void FillRobot(const SslRobot& r, SSL_DetectionRobot* out) {
  out->set_confidence(F(r.confidence));
  if (r.robot_id >= 0) out->set_robot_id(static_cast<uint32_t>(r.robot_id));
  out->set_x(F(r.x_mm));
  out->set_y(F(r.y_mm));
  out->set_orientation(F(r.orientation_rad));
  out->set_pixel_x(F(r.pixel_x));
  out->set_pixel_y(F(r.pixel_y));
  out->set_height(F(r.height_mm));
}

SslRobot RobotOf(const SSL_DetectionRobot& r) {
  SslRobot out;
  out.confidence = r.confidence();
  out.robot_id = r.has_robot_id() ? static_cast<int>(r.robot_id()) : -1;
  out.x_mm = r.x();
  out.y_mm = r.y();
  out.orientation_rad = r.orientation();
  out.pixel_x = r.pixel_x();
  out.pixel_y = r.pixel_y();
  out.height_mm = r.height();
  return out;
}

void FillDetection(const SslDetection& d, SSL_DetectionFrame* out) {
  out->set_frame_number(d.frame_number);
  out->set_t_capture(d.t_capture_s);
  out->set_t_sent(d.t_sent_s);
  out->set_camera_id(d.camera_id);
  for (const SslBall& b : d.balls) {
    SSL_DetectionBall* ball = out->add_balls();
    ball->set_confidence(F(b.confidence));
    ball->set_area(static_cast<uint32_t>(b.area_px));
    ball->set_x(F(b.x_mm));
    ball->set_y(F(b.y_mm));
    ball->set_z(F(b.z_mm));
    ball->set_pixel_x(F(b.pixel_x));
    ball->set_pixel_y(F(b.pixel_y));
  }
  for (const SslRobot& r : d.robots_yellow) FillRobot(r, out->add_robots_yellow());
  for (const SslRobot& r : d.robots_blue) FillRobot(r, out->add_robots_blue());
}

SslDetection DetectionOf(const SSL_DetectionFrame& f) {
  SslDetection d;
  d.frame_number = f.frame_number();
  d.t_capture_s = f.t_capture();
  d.t_sent_s = f.t_sent();
  d.camera_id = f.camera_id();
  for (const SSL_DetectionBall& b : f.balls()) {
    d.balls.push_back({b.confidence(), static_cast<int>(b.area()), b.x(), b.y(), b.z(), b.pixel_x(),
                       b.pixel_y()});
  }
  for (const SSL_DetectionRobot& r : f.robots_yellow()) d.robots_yellow.push_back(RobotOf(r));
  for (const SSL_DetectionRobot& r : f.robots_blue()) d.robots_blue.push_back(RobotOf(r));
  return d;
}

void FillCamera(const SslCameraCalibration& c, SSL_GeometryCameraCalibration* out) {
  out->set_camera_id(c.camera_id);
  out->set_focal_length(F(c.focal_length_px));
  out->set_principal_point_x(F(c.principal_point_x));
  out->set_principal_point_y(F(c.principal_point_y));
  out->set_distortion(F(c.distortion));
  out->set_q0(F(c.q0));
  out->set_q1(F(c.q1));
  out->set_q2(F(c.q2));
  out->set_q3(F(c.q3));
  out->set_tx(F(c.tx_mm));
  out->set_ty(F(c.ty_mm));
  out->set_tz(F(c.tz_mm));
  out->set_derived_camera_world_tx(F(c.camera_world_x_mm));
  out->set_derived_camera_world_ty(F(c.camera_world_y_mm));
  out->set_derived_camera_world_tz(F(c.camera_world_z_mm));
  if (c.image_width_px > 0) out->set_pixel_image_width(static_cast<uint32_t>(c.image_width_px));
  if (c.image_height_px > 0) out->set_pixel_image_height(static_cast<uint32_t>(c.image_height_px));
}

SslCameraCalibration CameraOf(const SSL_GeometryCameraCalibration& c) {
  SslCameraCalibration out;
  out.camera_id = c.camera_id();
  out.focal_length_px = c.focal_length();
  out.principal_point_x = c.principal_point_x();
  out.principal_point_y = c.principal_point_y();
  out.distortion = c.distortion();
  out.q0 = c.q0();
  out.q1 = c.q1();
  out.q2 = c.q2();
  out.q3 = c.q3();
  out.tx_mm = c.tx();
  out.ty_mm = c.ty();
  out.tz_mm = c.tz();
  out.camera_world_x_mm = c.derived_camera_world_tx();
  out.camera_world_y_mm = c.derived_camera_world_ty();
  out.camera_world_z_mm = c.derived_camera_world_tz();
  out.image_width_px = static_cast<int>(c.pixel_image_width());
  out.image_height_px = static_cast<int>(c.pixel_image_height());
  return out;
}

void FillGeometry(const SslGeometry& g, SSL_GeometryData* out) {
  SSL_GeometryFieldSize* field = out->mutable_field();
  field->set_field_length(g.field_length_mm);
  field->set_field_width(g.field_width_mm);
  field->set_goal_width(g.goal_width_mm);
  field->set_goal_depth(g.goal_depth_mm);
  field->set_boundary_width(g.boundary_width_mm);
  for (const SslLine& l : g.lines) {
    SSL_FieldLineSegment* line = field->add_field_lines();
    line->set_name(l.name);
    line->mutable_p1()->set_x(F(l.x1_mm));
    line->mutable_p1()->set_y(F(l.y1_mm));
    line->mutable_p2()->set_x(F(l.x2_mm));
    line->mutable_p2()->set_y(F(l.y2_mm));
    line->set_thickness(F(l.thickness_mm));
  }
  for (const SslArc& a : g.arcs) {
    SSL_FieldCircularArc* arc = field->add_field_arcs();
    arc->set_name(a.name);
    arc->mutable_center()->set_x(F(a.centre_x_mm));
    arc->mutable_center()->set_y(F(a.centre_y_mm));
    arc->set_radius(F(a.radius_mm));
    arc->set_a1(F(a.a1_rad));
    arc->set_a2(F(a.a2_rad));
    arc->set_thickness(F(a.thickness_mm));
  }
  for (const SslCameraCalibration& c : g.cameras) FillCamera(c, out->add_calib());
}

SslGeometry GeometryOf(const SSL_GeometryData& data) {
  SslGeometry g;
  const SSL_GeometryFieldSize& f = data.field();
  g.field_length_mm = f.field_length();
  g.field_width_mm = f.field_width();
  g.goal_width_mm = f.goal_width();
  g.goal_depth_mm = f.goal_depth();
  g.boundary_width_mm = f.boundary_width();
  for (const SSL_FieldLineSegment& l : f.field_lines()) {
    g.lines.push_back({l.name(), l.p1().x(), l.p1().y(), l.p2().x(), l.p2().y(), l.thickness()});
  }
  for (const SSL_FieldCircularArc& a : f.field_arcs()) {
    g.arcs.push_back(
        {a.name(), a.center().x(), a.center().y(), a.radius(), a.a1(), a.a2(), a.thickness()});
  }
  for (const SSL_GeometryCameraCalibration& c : data.calib()) g.cameras.push_back(CameraOf(c));
  return g;
}

}  // namespace

std::string SerializeDetection(const SslDetection& detection) {
  SSL_WrapperPacket packet;
  FillDetection(detection, packet.mutable_detection());
  return packet.SerializeAsString();
}

std::string SerializeGeometry(const SslGeometry& geometry) {
  SSL_WrapperPacket packet;
  FillGeometry(geometry, packet.mutable_geometry());
  return packet.SerializeAsString();
}

std::optional<SslPacket> ParsePacket(const std::string& bytes) {
  SSL_WrapperPacket packet;
  if (!packet.ParseFromString(bytes)) return std::nullopt;
  SslPacket out;
  if (packet.has_detection()) out.detection = DetectionOf(packet.detection());
  if (packet.has_geometry()) out.geometry = GeometryOf(packet.geometry());
  return out;
}

}  // namespace patlab::live
