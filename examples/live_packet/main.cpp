// A detection packet built with patlab's live room and read back with the generated SSL-Vision
// classes, both from the installed package: prints "robot 3 blue at 120 -40".
#include <cstdio>

#include "messages_robocup_ssl_wrapper.pb.h"
#include "patlab/live/live_loop.h"
#include "patlab/live/packet.h"

int main() {
  patlab::live::SslDetection detection;
  detection.camera_id = 1;
  patlab::live::SslRobot robot;
  robot.robot_id = 3;
  robot.x_mm = 120.0;
  robot.y_mm = -40.0;
  robot.confidence = 0.9;
  detection.robots_blue.push_back(robot);
  SSL_WrapperPacket packet;
  if (!packet.ParseFromString(patlab::live::SerializeDetection(detection)) ||
      packet.detection().robots_blue_size() != 1) {
    std::fprintf(stderr, "live_packet: the packet does not read back\n");
    return 1;
  }
  const SSL_DetectionRobot& read = packet.detection().robots_blue(0);
  std::printf("robot %u blue at %g %g\n", read.robot_id(), read.x(), read.y());
  return 0;
}
