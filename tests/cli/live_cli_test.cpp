// patlab live end to end: the golden frame looped as a frame list, packets sent to 127.0.0.1 on
// a port of the test's own socket, decoded with the classes protoc generated from proto/ and
// compared field by field with `patlab detect`'s output for the same frame; the --log file read
// back message for message; the --jsonl lines; bad flags and sources.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>

#include "../test_util.h"
#include "messages_robocup_ssl_wrapper.pb.h"
#include "patlab/live/packet.h"
#include "patlab/live/ssl_log.h"

namespace patlab {
namespace {

using testing::kGoldenFrame;
using testing::kPatlab;
using testing::RunCommand;
using testing::TempDir;

const std::string kFiles = " -t " + kGoldenFrame + "thresholds.toml -c " + kGoldenFrame +
                           "calibration.toml -s " + kGoldenFrame + "detector.toml";

struct Receiver {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  uint16_t port = 0;
  Receiver() {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    socklen_t size = sizeof addr;
    EXPECT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &size), 0);
    port = ntohs(addr.sin_port);
  }
  ~Receiver() { close(fd); }
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

// patlab detect's CSV rows (team, id, x, y, theta) keyed by team and id.
struct DetectRow {
  double x = 0, y = 0, theta = 0;
};
std::map<std::pair<std::string, int>, DetectRow> DetectRows() {
  const testing::CommandResult r = RunCommand(kPatlab + " detect " + kGoldenFrame + "png" + kFiles);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::map<std::pair<std::string, int>, DetectRow> rows;
  std::istringstream lines(r.out);
  std::string line;
  std::getline(lines, line);  // frame,pattern,team,id,status,x_mm,y_mm,theta_rad,...
  while (std::getline(lines, line)) {
    std::vector<std::string> c;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    if (c.size() < 8) continue;
    rows[{c[2], std::stoi(c[3])}] = {std::stod(c[5]), std::stod(c[6]), std::stod(c[7])};
  }
  return rows;
}

void ExpectAsDetect(const google::protobuf::RepeatedPtrField<SSL_DetectionRobot>& robots,
                    const std::string& team,
                    const std::map<std::pair<std::string, int>, DetectRow>& rows, int* matched) {
  for (const SSL_DetectionRobot& r : robots) {
    ASSERT_TRUE(r.has_robot_id() && r.has_orientation() && r.has_height());
    const auto it = rows.find({team, static_cast<int>(r.robot_id())});
    ASSERT_NE(it, rows.end()) << team << " " << r.robot_id();
    // detect prints 2 decimals of mm and 4 of radians; the packet holds floats.
    EXPECT_NEAR(r.x(), it->second.x, 0.006);
    EXPECT_NEAR(r.y(), it->second.y, 0.006);
    EXPECT_NEAR(r.orientation(), it->second.theta, 0.00006);
    ++*matched;
  }
}

TEST(LiveCli, PacketsLogAndJsonMatchDetect) {
  const auto rows = DetectRows();
  ASSERT_EQ(rows.size(), 10u);
  TempDir dir;
  Receiver receiver;
  const testing::CommandResult r = RunCommand(
      kPatlab + " live " + kGoldenFrame + "png --loop --max-frames 4 --list-rate 100" + kFiles +
      " --camera-id 5 --field " + PATLAB_SOURCE_DIR + "/experiments/fields/ssl-div-b.toml" +
      " --send 127.0.0.1:" + std::to_string(receiver.port) + " --log " + dir.Path("live.log") +
      " --jsonl " + dir.Path("live.jsonl") + " --stats");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("end to end"), std::string::npos) << r.err;
  const std::vector<std::string> packets = receiver.ReceiveAll();
  const live::SslLog log = live::ReadSslLog(dir.Path("live.log"));
  ASSERT_EQ(log.messages.size(), packets.size());
  EXPECT_EQ(log.truncated, 0);
  std::istringstream jsonl(testing::ReadFile(dir.Path("live.jsonl")));
  int detections = 0, geometry = 0;
  for (size_t i = 0; i < packets.size(); ++i) {
    EXPECT_EQ(log.messages[i].bytes, packets[i]) << "message " << i;
    EXPECT_EQ(log.messages[i].type, 2);
    SSL_WrapperPacket packet;
    ASSERT_TRUE(packet.ParseFromString(packets[i]));
    if (packet.has_geometry()) {
      ++geometry;
      EXPECT_EQ(packet.geometry().field().field_length(), 9000);  // ssl-div-b: 9000 x 6000
      EXPECT_EQ(packet.geometry().field().field_width(), 6000);
      ASSERT_EQ(packet.geometry().calib_size(), 1);
      EXPECT_EQ(packet.geometry().calib(0).camera_id(), 5u);
    }
    if (!packet.has_detection()) continue;
    const SSL_DetectionFrame& f = packet.detection();
    EXPECT_EQ(f.camera_id(), 5u);
    EXPECT_GT(f.t_sent(), f.t_capture());
    int matched = 0;
    ExpectAsDetect(f.robots_blue(), "blue", rows, &matched);
    ExpectAsDetect(f.robots_yellow(), "yellow", rows, &matched);
    EXPECT_EQ(matched, 10);
    EXPECT_EQ(f.balls_size(), 1);
    std::string line;
    ASSERT_TRUE(std::getline(jsonl, line));
    const std::optional<live::SslPacket> back = live::ParsePacket(packets[i]);
    EXPECT_EQ(line, live::DetectionJson(*back->detection));
    ++detections;
  }
  EXPECT_GE(detections, 1);
  EXPECT_EQ(geometry, 1);
}

// --hold-ids on a frame whose every robot is read clearly holds nothing: the JSON lines are those
// of the run without it, line for line (but for the send times), and --stats says "ids held 0".
TEST(LiveCli, HoldIdsOnClearFramesChangesNothing) {
  TempDir dir;
  std::vector<std::string> runs;
  for (const std::string flag : {"", " --hold-ids"}) {
    const std::string out = dir.Path("live" + std::to_string(runs.size()) + ".jsonl");
    const testing::CommandResult r =
        RunCommand(kPatlab + " live " + kGoldenFrame + "png --loop --max-frames 5 --rate max" +
                   kFiles + " --send 127.0.0.1:9 --jsonl " + out + " --stats" + flag);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("; ids held 0\n"), std::string::npos) << r.err;
    std::string lines;
    std::istringstream in(testing::ReadFile(out));
    for (std::string line; std::getline(in, line);) {
      // The robots and balls: from "balls" on (frame numbers and times differ between runs).
      lines += line.substr(line.find("\"balls\"")) + "\n";
    }
    EXPECT_EQ(lines.find("id_held"), std::string::npos);
    runs.push_back(lines.substr(0, lines.find('\n')));  // the first frame (others may drop)
  }
  EXPECT_EQ(runs[0], runs[1]);
}

TEST(LiveCli, BadInputNamesTheFlag) {
  const std::string base = kPatlab + " live " + kGoldenFrame + "png" + kFiles;
  struct Case {
    std::string flags, message;
  };
  const std::vector<Case> cases = {
      {" --send 127.0.0.1",
       "--send is '127.0.0.1'; expected ADDRESS:PORT with a dotted IPv4 "
       "address and a port in 1..65535, e.g. 127.0.0.1:10006"},
      {" --send 127.0.0.1:1 --rate fast", "--rate is \"fast\"; expected \"native\" or \"max\""},
      {" --send 127.0.0.1:1 --max-frames=-1", "--max-frames is -1; expected >= 0"},
      {" --send 127.0.0.1:1 --camera-id 0,1",
       "--camera-id has 2 id(s) for 1 SOURCE(s); expected "
       "one per SOURCE"},
      {" --send 127.0.0.1:1 --ttl 300", "--ttl is 300; expected 0..255"},
  };
  for (const Case& c : cases) {
    const testing::CommandResult r = RunCommand(base + c.flags);
    EXPECT_EQ(r.exit_code, 2) << c.flags << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.flags << "\n" << r.err;
  }
  const testing::CommandResult missing =
      RunCommand(kPatlab + " live /nonexistent/clip.mkv" + kFiles + " --send 127.0.0.1:1");
  EXPECT_EQ(missing.exit_code, 2) << missing.err;
  EXPECT_NE(missing.err.find("/nonexistent/clip.mkv: cannot open"), std::string::npos)
      << missing.err;
}

}  // namespace
}  // namespace patlab
