// Holding robot IDs (live/id_hold.h) on synthetic detection sequences: a one- or two-frame
// flicker (unknown or another ID) is held and marked, a change read for k frames is not hidden,
// an unstable track holds nothing, a held ID never duplicates one the frame reads, and with the
// holder off every frame is its own decision, bit for bit.
#include "patlab/live/id_hold.h"

#include <gtest/gtest.h>

#include "../expect_error.h"

namespace patlab::live {
namespace {

SslRobot Robot(int id, double x_mm, double y_mm, double confidence = 0.8) {
  SslRobot r;
  r.robot_id = id;
  r.x_mm = x_mm;
  r.y_mm = y_mm;
  r.confidence = confidence;
  r.orientation_rad = 0.25;
  return r;
}

IdHoldOptions On() {
  IdHoldOptions o;
  o.enabled = true;  // radius 90 mm, stable after 3 reads, k = 3
  return o;
}

// One blue robot moving 20 mm a frame along x, read as `ids` in turn; what is sent per frame as
// (robot_id, id_held), and the confidence sent.
struct Sent {
  std::vector<int> ids;
  std::vector<bool> held;
  std::vector<double> confidence;
  int held_count = 0;
};
Sent Hold(const IdHoldOptions& options, const std::vector<int>& ids) {
  IdHolder holder(options);
  Sent sent;
  for (size_t f = 0; f < ids.size(); ++f) {
    SslDetection d;
    d.frame_number = static_cast<uint32_t>(f);
    d.robots_blue.push_back(Robot(ids[f], 20.0 * static_cast<double>(f), 100.0, 0.5 + 0.01 * f));
    sent.held_count += holder.Apply(&d);
    sent.ids.push_back(d.robots_blue[0].robot_id);
    sent.held.push_back(d.robots_blue[0].id_held);
    sent.confidence.push_back(d.robots_blue[0].confidence);
  }
  return sent;
}

TEST(IdHold, UnknownFlickerIsHeldAndMarked) {
  const Sent s = Hold(On(), {5, 5, 5, -1, 5, -1, -1, 5});
  EXPECT_EQ(s.ids, (std::vector<int>{5, 5, 5, 5, 5, 5, 5, 5}));
  EXPECT_EQ(s.held, (std::vector<bool>{false, false, false, true, false, true, true, false}));
  EXPECT_EQ(s.held_count, 3);
  for (size_t f = 0; f < s.confidence.size(); ++f) {
    EXPECT_EQ(s.confidence[f], 0.5 + 0.01 * f) << "frame " << f;  // the frame's own
  }
}

TEST(IdHold, MisreadForFewerThanKFramesIsHeld) {
  const Sent s = Hold(On(), {5, 5, 5, 7, 5, 7, 7, 5});
  EXPECT_EQ(s.ids, (std::vector<int>{5, 5, 5, 5, 5, 5, 5, 5}));
  EXPECT_EQ(s.held, (std::vector<bool>{false, false, false, true, false, true, true, false}));
}

TEST(IdHold, ChangeReadForKFramesSwitchesOnTheKth) {
  const Sent s = Hold(On(), {5, 5, 5, 7, 7, 7, 7, 5});
  // Frames 3 and 4 carry 5 over; frame 5 is the third reading 7 and switches; from then on the
  // track is 7 (read 3 times: stable), so a lone 5 afterwards is held as 7.
  EXPECT_EQ(s.ids, (std::vector<int>{5, 5, 5, 5, 5, 7, 7, 7}));
  EXPECT_EQ(s.held, (std::vector<bool>{false, false, false, true, true, false, false, true}));
}

TEST(IdHold, LongUnknownStretchLosesTheId) {
  const Sent s = Hold(On(), {5, 5, 5, -1, -1, -1, -1, 5});
  EXPECT_EQ(s.ids, (std::vector<int>{5, 5, 5, 5, 5, -1, -1, 5}));
  EXPECT_EQ(s.held, (std::vector<bool>{false, false, false, true, true, false, false, false}));
}

TEST(IdHold, UnstableTrackHoldsNothing) {
  const Sent s = Hold(On(), {5, 5, -1, 5, -1});
  EXPECT_EQ(s.ids, (std::vector<int>{5, 5, -1, 5, 5}));  // stable after the third read
  EXPECT_EQ(s.held, (std::vector<bool>{false, false, false, false, true}));
}

TEST(IdHold, KOfOneCarriesNothingOver) {
  IdHoldOptions o = On();
  o.switch_frames = 1;
  const std::vector<int> ids = {5, 5, 5, -1, 7, 5};
  EXPECT_EQ(Hold(o, ids).ids, ids);
}

TEST(IdHold, FarRobotIsAnotherTrack) {
  IdHolder holder(On());
  for (int f = 0; f < 3; ++f) {
    SslDetection d;
    d.robots_blue.push_back(Robot(5, 0.0, 0.0));
    holder.Apply(&d);
  }
  SslDetection d;
  d.robots_blue.push_back(Robot(-1, 500.0, 0.0));  // 500 mm away: not robot 5
  EXPECT_EQ(holder.Apply(&d), 0);
  EXPECT_EQ(d.robots_blue[0].robot_id, -1);
}

TEST(IdHold, TeamsAreTrackedApart) {
  IdHolder holder(On());
  for (int f = 0; f < 3; ++f) {
    SslDetection d;
    d.robots_blue.push_back(Robot(5, 0.0, 0.0));
    holder.Apply(&d);
  }
  SslDetection d;
  d.robots_yellow.push_back(Robot(-1, 0.0, 0.0));  // a yellow robot where blue 5 was
  EXPECT_EQ(holder.Apply(&d), 0);
  EXPECT_EQ(d.robots_yellow[0].robot_id, -1);
}

TEST(IdHold, HeldIdNeverDuplicatesOneTheFrameReads) {
  IdHolder holder(On());
  for (int f = 0; f < 3; ++f) {
    SslDetection d;
    d.robots_blue = {Robot(5, 0.0, 0.0)};
    holder.Apply(&d);
  }
  SslDetection d;  // the robot at x = 0 unknown while a robot new to the frame reads 5 clearly
  d.robots_blue = {Robot(-1, 10.0, 0.0), Robot(5, 1000.0, 0.0)};
  EXPECT_EQ(holder.Apply(&d), 0);
  EXPECT_EQ(d.robots_blue[0].robot_id, -1);
  EXPECT_EQ(d.robots_blue[1].robot_id, 5);
}

TEST(IdHold, ForgottenAfterKFramesUnseen) {
  IdHolder holder(On());
  for (int f = 0; f < 3; ++f) {
    SslDetection d;
    d.robots_blue.push_back(Robot(5, 0.0, 0.0));
    holder.Apply(&d);
  }
  for (int f = 0; f < 3; ++f) {
    SslDetection empty;
    holder.Apply(&empty);
  }
  SslDetection d;
  d.robots_blue.push_back(Robot(-1, 0.0, 0.0));
  EXPECT_EQ(holder.Apply(&d), 0);
  EXPECT_EQ(d.robots_blue[0].robot_id, -1);
}

TEST(IdHold, HeldRobotIsMarkedInJsonNotInThePacket) {
  IdHolder holder(On());
  SslDetection d;
  for (int f = 0; f < 4; ++f) {
    d = SslDetection{};
    d.robots_yellow.push_back(Robot(f < 3 ? 2 : -1, 0.0, 0.0, 0.25));
    holder.Apply(&d);
  }
  ASSERT_TRUE(d.robots_yellow[0].id_held);
  const std::string json = DetectionJson(d);
  EXPECT_NE(json.find("{\"confidence\":0.25,\"robot_id\":2,\"id_held\":true,\"x\":0"),
            std::string::npos)
      << json;
  const std::optional<SslPacket> packet = ParsePacket(SerializeDetection(d));
  ASSERT_TRUE(packet && packet->detection);
  const SslRobot& sent = packet->detection->robots_yellow[0];
  EXPECT_EQ(sent.robot_id, 2);
  EXPECT_EQ(sent.confidence, 0.25);
  EXPECT_FALSE(sent.id_held);
}

TEST(IdHold, OffIsTheRawDecisionBitForBit) {
  IdHoldOptions off = On();
  off.enabled = false;
  IdHolder holder(off);
  const std::vector<int> ids = {5, 5, 5, -1, 7, 5, -1, -1, -1, 5};
  for (size_t f = 0; f < ids.size(); ++f) {
    SslDetection d;
    d.frame_number = static_cast<uint32_t>(f);
    d.robots_blue = {Robot(ids[f], 10.0 * f, 0.0), Robot(3, 900.0, 0.0)};
    d.robots_yellow = {Robot(ids[ids.size() - 1 - f], -500.0, 20.0 * f)};
    const SslDetection raw = d;
    EXPECT_EQ(holder.Apply(&d), 0);
    EXPECT_EQ(SerializeDetection(d), SerializeDetection(raw));
    EXPECT_EQ(DetectionJson(d), DetectionJson(raw));
  }
  EXPECT_EQ(Hold(off, ids).ids, ids);
}

TEST(IdHold, OptionsAreChecked) {
  IdHoldOptions o = On();
  o.radius_mm = 0.0;
  EXPECT_INPUT_ERROR(IdHolder{o}, "radius_mm is 0; expected a finite number > 0 (mm)");
  o = On();
  o.switch_frames = 0;
  EXPECT_INPUT_ERROR(IdHolder{o}, "switch_frames is 0; expected an integer in [1, 1048576]");
}

}  // namespace
}  // namespace patlab::live
