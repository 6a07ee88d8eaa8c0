// The live loop (live/live_loop.h) on the golden frame: every frame delivered is detected or
// counted as dropped; the packets sent to 127.0.0.1, the log and the JSON lines carry the same
// detections as a FrameDetector of the test's own; a stop request ends the loop with a valid
// log; each camera's frames are counted and the totals are their sums.
#include "patlab/live/live_loop.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "../test_util.h"
#include "patlab/formats/calibration_file.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/formats/field_file.h"
#include "patlab/formats/thresholds_file.h"
#include "patlab/live/ssl_log.h"
#include "patlab/live/udp_sender.h"

namespace patlab::live {
namespace {

using patlab::testing::kGolden;

LiveCamera GoldenCamera() {
  LiveCamera camera;
  camera.source = kGolden + "ssl-frame.png";
  camera.thresholds = formats::LoadThresholds(kGolden + "ssl-frame.thresholds.toml");
  camera.calibration = formats::LoadCalibration(kGolden + "ssl-frame.calibration.toml");
  camera.detector = formats::LoadDetectorSettings(kGolden + "ssl-frame.detector.toml");
  vision::ApplyFrameSettings(formats::LoadFrameSettings(kGolden + "ssl-frame.detector.toml"),
                             &camera.frame);
  return camera;
}

// A socket of the test bound to 127.0.0.1 on a port the system picks; reads what has arrived.
struct DrainingReceiver {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  uint16_t port = 0;
  DrainingReceiver() {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    socklen_t size = sizeof addr;
    EXPECT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &size), 0);
    port = ntohs(addr.sin_port);
    int buffer = 8 << 20;
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
  }
  ~DrainingReceiver() { close(fd); }
  std::vector<std::string> ReceiveAll() const {
    std::vector<std::string> packets;
    char data[65536];
    pollfd p{fd, POLLIN, 0};
    while (poll(&p, 1, 200) == 1) {
      const ssize_t n = recv(fd, data, sizeof data, 0);
      if (n <= 0) break;
      packets.emplace_back(data, static_cast<size_t>(n));
    }
    return packets;
  }
};

TEST(LiveLoop, PacketsLogAndJsonCarryTheFramesDetections) {
  patlab::testing::TempDir dir;
  DrainingReceiver receiver;
  UdpSender sender(ParseUdpAddress("127.0.0.1:" + std::to_string(receiver.port), "--send"), {});
  SslLogWriter log(dir.Path("live.log"));
  std::vector<std::string> lines;
  LiveOutputs outputs;
  outputs.sender = &sender;
  outputs.log = &log;
  outputs.jsonl = [&lines](std::string_view line) { lines.emplace_back(line); };
  outputs.field =
      formats::LoadField(std::string(PATLAB_SOURCE_DIR) + "/experiments/fields/ssl-div-b.toml");
  LiveOptions options;
  options.rate = LiveRate::kNative;
  options.source.list_rate_hz = 50.0;
  options.source.loop = true;
  options.max_frames = 6;
  std::atomic<bool> stop{false};
  const LiveStats stats = RunLive({GoldenCamera()}, options, outputs, stop);
  log.Close();

  EXPECT_EQ(stats.received, 6);
  EXPECT_EQ(stats.processed + stats.dropped, stats.received);
  EXPECT_EQ(stats.packets, stats.processed);
  EXPECT_EQ(stats.geometry_packets, 1);  // 6 frames at 50 Hz take 0.1 s
  ASSERT_EQ(stats.latency.size(), kLiveStageNames.size());
  EXPECT_EQ(lines.size(), static_cast<size_t>(stats.processed));

  // The test's own detector on the same frame.
  const LiveCamera camera = GoldenCamera();
  vision::FrameDetector frames(camera.thresholds, camera.calibration, camera.detector,
                               camera.frame);
  const SslDetection expected =
      DetectionOfFrame(frames.DetectFile(camera.source), frames, FrameStamp{});

  const std::vector<std::string> packets = receiver.ReceiveAll();
  const SslLog read = ReadSslLog(dir.Path("live.log"));
  ASSERT_EQ(packets.size(), static_cast<size_t>(stats.packets + stats.geometry_packets));
  ASSERT_EQ(read.messages.size(), packets.size());
  EXPECT_EQ(read.truncated, 0);
  size_t detections = 0;
  for (size_t i = 0; i < packets.size(); ++i) {
    EXPECT_EQ(read.messages[i].bytes, packets[i]);
    EXPECT_EQ(read.messages[i].type, static_cast<int32_t>(SslMessageType::kVision2010));
    const std::optional<SslPacket> packet = ParsePacket(packets[i]);
    ASSERT_TRUE(packet.has_value());
    if (i == 0) {
      ASSERT_TRUE(packet->geometry.has_value());  // the geometry goes out first
    }
    if (!packet->detection) continue;
    SslDetection got = *packet->detection;
    EXPECT_EQ(lines[detections], DetectionJson(got));
    ++detections;
    got.frame_number = 0;
    got.t_capture_s = got.t_sent_s = 0.0;
    SslDetection want = *ParsePacket(SerializeDetection(expected))->detection;
    EXPECT_EQ(DetectionJson(got), DetectionJson(want));
  }
  EXPECT_EQ(detections, static_cast<size_t>(stats.processed));
}

TEST(LiveLoop, StopRequestEndsWithAValidLog) {
  patlab::testing::TempDir dir;
  SslLogWriter log(dir.Path("stopped.log"));
  LiveOutputs outputs;
  outputs.log = &log;
  LiveOptions options;
  options.source.loop = true;  // would run for ever
  std::atomic<bool> stop{true};
  const LiveStats stats = RunLive({GoldenCamera()}, options, outputs, stop);
  log.Close();
  EXPECT_EQ(stats.processed, 0);
  EXPECT_EQ(ReadSslLog(dir.Path("stopped.log")).truncated, 0);
}

TEST(LiveLoop, EachCameraIsCountedAndTheTotalsAreTheirSums) {
  LiveOutputs outputs;
  LiveOptions options;
  options.source.list_rate_hz = 50.0;
  options.source.loop = true;
  options.max_frames = 4;
  LiveCamera second = GoldenCamera();
  second.camera_id = 3;
  std::atomic<bool> stop{false};
  const LiveStats stats = RunLive({GoldenCamera(), second}, options, outputs, stop);
  ASSERT_EQ(stats.cameras.size(), 2u);
  EXPECT_EQ(stats.cameras[0].camera_id, 0u);
  EXPECT_EQ(stats.cameras[1].camera_id, 3u);
  long received = 0, processed = 0, dropped = 0;
  for (const CameraFrameCounts& c : stats.cameras) {
    EXPECT_EQ(c.received, 4);
    EXPECT_EQ(c.processed + c.dropped, c.received);
    EXPECT_EQ(c.skipped, 0);
    received += c.received;
    processed += c.processed;
    dropped += c.dropped;
  }
  EXPECT_EQ(received, stats.received);
  EXPECT_EQ(processed, stats.processed);
  EXPECT_EQ(dropped, stats.dropped);
}

TEST(LiveLoop, PercentileIsTheNearestRank) {
  std::vector<double> v = {5, 1, 4, 2, 3};
  EXPECT_EQ(Percentile(v, 50), 3.0);
  EXPECT_EQ(Percentile(v, 99), 5.0);
  EXPECT_EQ(Percentile(v, 0), 1.0);
  std::vector<double> none;
  EXPECT_EQ(Percentile(none, 50), 0.0);
}

}  // namespace
}  // namespace patlab::live
