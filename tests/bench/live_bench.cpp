// The live path on one core, frame in memory -> packet sent: per-stage and end-to-end latency
// (p50, p99, max) of `patlab live`'s detection thread for the 780x580 SSL test frame
// (../shared/frames/ssl-field-2008.jpg with tests/data/vision/ssl-2008.*; the 640x480 golden
// frame when the shared frames are absent). Stages as live_loop.h names them: 2 detect
// (vision + detector), 3 packet (SSL structs + protobuf serialization), 4 send (one UDP datagram
// to a socket of this program on 127.0.0.1, the SSL log write to a temporary file), and stage 2
// split into the vision pipeline's stages (vision/pipeline.h: colour lookup, runs, regions, blobs
// to mm, detector) from the FrameDetector's TimeProfile. Prints a table; run:
//   build/bench/live_bench [frames, default 2000] [golden|ssl-2008, default ssl-2008 when the
//   shared frames are there]
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "patlab/core/format.h"
#include "patlab/core/timeprofile.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/live/live_loop.h"
#include "patlab/live/packet.h"
#include "patlab/live/ssl_log.h"
#include "patlab/live/udp_sender.h"
#include "patlab/vision/frame_io.h"

namespace {

using namespace patlab;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

struct Inputs {
  std::string frame, thresholds, calibration, settings;
};

Inputs Choose(const std::string& which) {
  const std::string root = PATLAB_SOURCE_DIR;
  const std::string shared = root + "/../shared/frames/ssl-field-2008.jpg";
  if (which != "golden" && fs::exists(shared)) {
    const std::string data = root + "/tests/data/vision/ssl-2008.";
    return {shared, data + "thresholds.toml", data + "calibration.toml", data + "detector.toml"};
  }
  const std::string golden = root + "/tests/data/golden/ssl-frame.";
  return {golden + "png", golden + "thresholds.toml", golden + "calibration.toml",
          golden + "detector.toml"};
}

// A socket bound to 127.0.0.1 that receives what is sent (its buffer drained every frame).
int BoundSocket(uint16_t* port) {
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  socklen_t size = sizeof addr;
  getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &size);
  *port = ntohs(addr.sin_port);
  return fd;
}

double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

}  // namespace

int main(int argc, char** argv) {
  const int frames_to_run = argc > 1 ? std::stoi(argv[1]) : 2000;
  const Inputs in = Choose(argc > 2 ? argv[2] : "");
  vision::FrameDetectorOptions options;
  vision::ApplyFrameSettings(formats::LoadFrameSettings(in.settings), &options);
  options.collect_timing = true;  // per stage: a clock read per stage, tens of ns
  vision::FrameDetector frames(formats::LoadThresholds(in.thresholds),
                               formats::LoadCalibration(in.calibration),
                               formats::LoadDetectorSettings(in.settings), options);
  const camera::Image image = vision::ReadFrame(in.frame);
  uint16_t port = 0;
  const int receiver = BoundSocket(&port);
  live::UdpSender sender(live::ParseUdpAddress("127.0.0.1:" + std::to_string(port), "--send"), {});
  const std::string log_path = (fs::temp_directory_path() / "patlab_live_bench.log").string();
  live::SslLogWriter log(log_path);
  std::array<std::vector<double>, 4> ms;
  std::vector<std::pair<std::string, std::vector<double>>> stage_ms;  // vision's stages
  char drain[65536];
  size_t robots = 0, balls = 0;
  for (int i = 0; i < frames_to_run; ++i) {
    const Clock::time_point start = Clock::now();
    const vision::FrameResult& result = frames.Detect(image, "bench");
    const Clock::time_point detected = Clock::now();
    const live::SslDetection d = live::DetectionOfFrame(
        result, frames, {static_cast<uint32_t>(i), live::WallTimeSeconds(), 0.0, 0});
    const std::string bytes = live::SerializeDetection(d);
    const Clock::time_point packed = Clock::now();
    sender.Send(bytes);
    log.Write(0, live::SslMessageType::kVision2010, bytes);
    const Clock::time_point sent = Clock::now();
    robots = d.robots_blue.size() + d.robots_yellow.size();
    balls = d.balls.size();
    for (const TimeProfile::Entry& e : result.profile.entries()) {
      auto it = std::find_if(stage_ms.begin(), stage_ms.end(),
                             [&](const auto& s) { return s.first == e.stage; });
      if (it == stage_ms.end()) it = stage_ms.insert(stage_ms.end(), {std::string(e.stage), {}});
      it->second.push_back(1e3 * e.seconds);
    }
    ms[0].push_back(Ms(detected - start));
    ms[1].push_back(Ms(packed - detected));
    ms[2].push_back(Ms(sent - packed));
    ms[3].push_back(Ms(sent - start));
    while (recv(receiver, drain, sizeof drain, 0) > 0) {
    }
  }
  log.Close();
  fs::remove(log_path);
  close(receiver);
  std::printf("live_bench: %s, %dx%d, %zu robots and %zu balls per frame, %d frames, one thread\n",
              fs::path(in.frame).filename().c_str(), image.width_px, image.height_px, robots, balls,
              frames_to_run);
  std::printf("  %-18s %9s %9s %9s\n", "stage", "p50 ms", "p99 ms", "max ms");
  const auto row = [](const std::string& name, std::vector<double>& v) {
    double max_ms = 0.0;
    for (double x : v) max_ms = std::max(max_ms, x);
    std::printf("  %-18s %9s %9s %9s\n", name.c_str(),
                FormatFixed(live::Percentile(v, 50), 4).c_str(),
                FormatFixed(live::Percentile(v, 99), 4).c_str(), FormatFixed(max_ms, 4).c_str());
  };
  const char* names[] = {"2 detect", "3 packet", "4 send+log", "end to end"};
  for (size_t s = 0; s < ms.size(); ++s) {
    row(names[s], ms[s]);
    if (s == 0) {
      for (auto& [stage, v] : stage_ms) row("  " + stage, v);
    }
  }
  return 0;
}
