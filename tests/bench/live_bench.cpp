// The live path on one core, frame in memory -> packet sent: per-stage and end-to-end latency
// (p50, p99, max) of `patlab live`'s detection thread for one frame, its second argument:
//   twelve    the performance target's frame (docs/live.md "Latency"): 780x580, 12 robots in the
//             SSL standard pattern (6 blue, 6 yellow) and a ball, rendered at startup by the
//             library's renderer (render::RenderScene) from tests/data/live/ssl-12-robots.toml,
//             detected with tests/data/golden/ssl-frame.{thresholds,detector}.toml and the
//             scene's calibration; needs nothing but the repository;
//   ssl-2008  the real 780x580 SSL frame ../shared/frames/ssl-field-2008.jpg (5 robots, 5 balls)
//             with tests/data/vision/ssl-2008.*; the golden frame when the shared frames are
//             absent;
//   golden    the 640x480 golden frame tests/data/golden/ssl-frame.png (10 robots, 1 ball).
// Stages as live_loop.h names them: 2 detect (vision + detector), 3 packet (SSL structs + protobuf
// serialization), 4 send (one UDP datagram to a socket of this program on 127.0.0.1, the SSL log
// write to a temporary file), and stage 2 split into the vision pipeline's stages
// (vision/pipeline.h: colour lookup, runs, regions, blobs to mm, detector) from the
// FrameDetector's TimeProfile. Prints a table; run (scripts/bench_live.sh runs `twelve` pinned to
// one core):
//   build/bench/live_bench [frames, default 2000] [twelve|ssl-2008|golden, default ssl-2008 when
//   the shared frames are there, else golden]
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
#include "patlab/formats/scene_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/live/live_loop.h"
#include "patlab/live/packet.h"
#include "patlab/live/ssl_log.h"
#include "patlab/live/udp_sender.h"
#include "patlab/render/scene_render.h"
#include "patlab/vision/frame_io.h"

namespace {

using namespace patlab;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

// `frame` is an image file, or for `twelve` a scene file rendered at startup.
struct Inputs {
  std::string frame, thresholds, calibration, settings;
  bool render = false;
};

constexpr const char* kUsage =
    "usage: live_bench [frames, default 2000] [twelve|ssl-2008|golden]\n"
    "  twelve    780x580, 12 robots and a ball, rendered from tests/data/live/ssl-12-robots.toml\n"
    "  ssl-2008  ../shared/frames/ssl-field-2008.jpg, 780x580, 5 robots and 5 balls (golden when "
    "absent)\n"
    "  golden    tests/data/golden/ssl-frame.png, 640x480, 10 robots and a ball\n";

Inputs Choose(const std::string& which) {
  const std::string root = PATLAB_SOURCE_DIR;
  if (which == "twelve") {
    const std::string golden = root + "/tests/data/golden/ssl-frame.";
    const std::string live = root + "/tests/data/live/ssl-12-robots.";
    return {live + "toml", golden + "thresholds.toml", live + "calibration.toml",
            golden + "detector.toml", true};
  }
  const std::string shared = root + "/../shared/frames/ssl-field-2008.jpg";
  if (which == "ssl-2008" && !fs::exists(shared)) {
    std::fprintf(stderr, "live_bench: %s is not there; benchmarking the golden frame instead\n",
                 shared.c_str());
  }
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

// The frame count and the frame's name of the command line; false when they are not valid.
bool ParseArguments(int argc, char** argv, int* frames, std::string* which) {
  *which = argc > 2 ? argv[2] : "";
  try {
    *frames = argc > 1 ? std::stoi(argv[1]) : 2000;
  } catch (const std::exception&) {
    return false;
  }
  return argc <= 3 && *frames >= 1 &&
         (which->empty() || *which == "twelve" || *which == "ssl-2008" || *which == "golden");
}

// The frame: read from its file, or rendered from its scene file.
camera::Image FrameImage(const Inputs& in) {
  if (!in.render) return vision::ReadFrame(in.frame);
  const formats::SceneFile scene = formats::LoadSceneFile(in.frame);
  return render::RenderScene(scene.scene, scene.calibration.camera);
}

}  // namespace

int main(int argc, char** argv) {
  int frames_to_run = 0;
  std::string which;
  if (!ParseArguments(argc, argv, &frames_to_run, &which)) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const Inputs in = Choose(which);
  vision::FrameDetectorOptions options;
  vision::ApplyFrameSettings(formats::LoadFrameSettings(in.settings), &options);
  options.collect_timing = true;  // per stage: a clock read per stage, tens of ns
  vision::FrameDetector frames(formats::LoadThresholds(in.thresholds),
                               formats::LoadCalibration(in.calibration),
                               formats::LoadDetectorSettings(in.settings), options);
  const camera::Image image = FrameImage(in);
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
  const std::string name =
      fs::path(in.frame).filename().string() + (in.render ? " (rendered)" : "");
  std::printf(
      "live_bench: %s, %dx%d, %zu robot%s and %zu ball%s per frame, %d frames, one thread\n",
      name.c_str(), image.width_px, image.height_px, robots, robots == 1 ? "" : "s", balls,
      balls == 1 ? "" : "s", frames_to_run);
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
