// An SSL log as measured tracks (log_track.h).
#include "patlab/live/log_track.h"

#include <map>

#include "patlab/core/error.h"
#include "patlab/live/packet.h"
#include "patlab/live/ssl_log.h"

namespace patlab::live {

namespace {

void AddRobots(const std::vector<SslRobot>& robots, const char* team, const SslDetection& d,
               const std::string& path, std::map<std::string, size_t>* index, LogTracks* out) {
  for (const SslRobot& r : robots) {
    if (r.robot_id < 0) continue;
    const std::string subject = std::string(team) + " " + std::to_string(r.robot_id);
    const std::string run = "camera " + std::to_string(d.camera_id);
    const auto [it, added] = index->emplace(subject + "\n" + run, out->tracks.size());
    if (added) {
      analysis::MeasuredTrack track;
      track.subject = subject;
      track.run = run;
      track.file = path;
      out->tracks.push_back(std::move(track));
    }
    analysis::MeasuredTrack& t = out->tracks[it->second];
    if (!t.frame.empty() && d.frame_number <= t.frame.back()) {
      ++out->skipped_frames;
      continue;
    }
    t.frame.push_back(d.frame_number);
    t.x.push_back(r.x_mm);
    t.y.push_back(r.y_mm);
    t.theta.push_back(r.orientation_rad);
  }
}

}  // namespace

LogTracks TracksOfSslLog(const std::string& path) {
  const SslLog log = ReadSslLog(path);
  LogTracks out;
  out.truncated = log.truncated;
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < log.messages.size(); ++i) {
    const SslLogMessage& m = log.messages[i];
    if (m.type != static_cast<int32_t>(SslMessageType::kVision2010)) continue;
    const std::optional<SslPacket> packet = ParsePacket(m.bytes);
    if (!packet) {
      throw InputError(path + ": message " + std::to_string(i + 1) +
                       ": not an SSL_WrapperPacket; expected SSL-Vision packets");
    }
    if (!packet->detection) continue;
    AddRobots(packet->detection->robots_yellow, "yellow", *packet->detection, path, &index, &out);
    AddRobots(packet->detection->robots_blue, "blue", *packet->detection, path, &index, &out);
  }
  return out;
}

}  // namespace patlab::live
