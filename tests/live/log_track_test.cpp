// An SSL log as measured tracks (live/log_track.h): packets written by hand, read back as one
// track per robot and camera, frames not after the last skipped and counted.
#include "patlab/live/log_track.h"

#include <gtest/gtest.h>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/live/packet.h"
#include "patlab/live/ssl_log.h"

namespace patlab::live {
namespace {

SslDetection Frame(uint32_t number, uint32_t camera, double x) {
  SslDetection d;
  d.frame_number = number;
  d.camera_id = camera;
  d.robots_blue.push_back({0.9, 3, x, 2.0 * x, 0.5, 0, 0, 0});
  d.robots_blue.push_back({0.9, -1, 7.0, 7.0, 0.0, 0, 0, 0});  // no ID: skipped
  d.robots_yellow.push_back({0.9, 5, -x, 0.0, -0.25, 0, 0, 0});
  return d;
}

TEST(LogTrack, OneTrackPerRobotAndCamera) {
  patlab::testing::TempDir dir;
  const std::string path = dir.Path("match.log");
  {
    SslLogWriter log(path);
    log.Write(0, SslMessageType::kVision2010, SerializeGeometry(SslGeometry{}));
    for (const SslDetection& d : {Frame(1, 0, 10.0), Frame(2, 0, 20.0), Frame(2, 0, 99.0),
                                  Frame(3, 0, 30.0), Frame(7, 1, 70.0)}) {
      log.Write(0, SslMessageType::kVision2010, SerializeDetection(d));
    }
    log.Write(0, SslMessageType::kRefbox2013, "not vision");
  }
  const LogTracks got = TracksOfSslLog(path);
  ASSERT_EQ(got.tracks.size(), 4u);
  EXPECT_EQ(got.skipped_frames, 2);  // frame 2 again, for blue 3 and yellow 5
  const analysis::MeasuredTrack& blue = got.tracks[0];
  EXPECT_EQ(blue.subject, "yellow 5");
  EXPECT_EQ(got.tracks[1].subject, "blue 3");
  EXPECT_EQ(got.tracks[1].run, "camera 0");
  EXPECT_EQ(got.tracks[1].frame, (std::vector<int64_t>{1, 2, 3}));
  EXPECT_EQ(got.tracks[1].x, (std::vector<double>{10.0, 20.0, 30.0}));
  EXPECT_EQ(got.tracks[1].y, (std::vector<double>{20.0, 40.0, 60.0}));
  EXPECT_EQ(got.tracks[1].theta, (std::vector<double>{0.5, 0.5, 0.5}));
  EXPECT_EQ(blue.theta, (std::vector<double>{-0.25, -0.25, -0.25}));
  EXPECT_EQ(got.tracks[3].subject, "blue 3");
  EXPECT_EQ(got.tracks[3].run, "camera 1");
  EXPECT_EQ(got.tracks[3].frame, (std::vector<int64_t>{7}));
}

TEST(LogTrack, UndecodableVisionMessageIsNamed) {
  patlab::testing::TempDir dir;
  const std::string path = dir.Path("bad.log");
  {
    SslLogWriter log(path);
    log.Write(0, SslMessageType::kVision2010, "\xff\xff\xff");
  }
  EXPECT_INPUT_ERROR(TracksOfSslLog(path),
                     path + ": message 1: not an SSL_WrapperPacket; expected SSL-Vision packets");
}

}  // namespace
}  // namespace patlab::live
