// An SSL log as measured tracks (analysis/analyze.h analysis::MeasuredTrack), so that `patlab
// analyze` can read what `patlab live --log` (or SSL-Vision) recorded: one track per robot seen,
// subject
// "<team> <id>" (team yellow or blue), run "camera <id>", frame the detection frame's number,
// x, y and theta as the packets carry them. Detections without an ID and packets without a
// detection (geometry) are skipped; a frame number not after the last of its track (a camera
// restarted) starts no new track but is skipped, counted in `skipped_frames`.
#pragma once

#include <string>
#include <vector>

#include "patlab/analysis/analyze.h"

namespace patlab::live {

struct LogTracks {
  std::vector<analysis::MeasuredTrack> tracks;  // in order of first appearance
  long skipped_frames = 0;
  int truncated = 0;  // the log's last message was cut (SslLog::truncated)
};

// InputError as ReadSslLog, and "<path>: message N: not an SSL_WrapperPacket" for vision messages
// (type 2) that do not decode.
LogTracks TracksOfSslLog(const std::string& path);

}  // namespace patlab::live
