// Holding a robot's ID through short ambiguities (`patlab live --hold-ids`; off by default).
//
// A frame's detector may read a robot's ID as unknown (a missing patch, robot_id -1) or, for a
// frame, as another ID (a patch misread under a light change). An AI that sees the ID flicker
// loses the robot for that frame. IdHolder follows each team's robots of one camera from frame to
// frame and, for such a frame, sends the ID the robot had before, marked as carried over:
//
//   - A track is a robot seen in the last frames: an observation matches the nearest track of its
//     team within `radius_mm` of where that track was last seen (pairs taken nearest first, each
//     track and observation once); an observation with no track starts one; a track not matched
//     for `switch_frames` consecutive frames is forgotten.
//   - A track's ID is stable when it was read (robot_id >= 0, the same ID) in at least
//     `stable_frames` frames since it was last taken up.
//   - A matched observation read as the track's ID is sent as is. Otherwise (unknown, or another
//     ID) and when the track's ID is stable, fewer than `switch_frames` consecutive frames have
//     missed it, and no other robot of the team reads that ID in this frame, the robot is sent
//     with the track's ID (carried over: SslRobot::id_held); its confidence stays the frame's
//     own.
//   - A real change is never hidden: the `switch_frames`-th consecutive frame that does not read
//     the track's ID is sent as the frame reads it, and from then on the track has that ID (a
//     robot read as another ID for switch_frames frames switches to it on the last of them; an
//     unknown one loses its ID until it is read again).
//
// With `enabled` false, Apply changes nothing: the packets are the frame's own decision, bit for
// bit.
#pragma once

#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/live/packet.h"

namespace patlab::live {

struct IdHoldOptions {
  bool enabled = false;
  // How far a robot may be from where its track was last seen and still be that robot, mm, > 0.
  // Larger follows faster robots (a robot at 3 m/s moves 50 mm between frames at 60 Hz) but may
  // swap two robots that pass close to each other (robots are 180 mm wide).
  double radius_mm = 90.0;
  // Frames a track must have been read with its ID before that ID is carried over, >= 1.
  int stable_frames = 3;
  // k: consecutive frames not reading a track's ID after which the frame's own reading is sent
  // (at most k - 1 frames are carried over); also the frames an unmatched track is remembered.
  // >= 1; 1 carries nothing over.
  int switch_frames = 3;
};
std::vector<OptionsProblem> Check(const IdHoldOptions& options);
void Validate(const IdHoldOptions& options);

// One camera's holder: Apply each of its detection frames in order.
class IdHolder {
 public:
  explicit IdHolder(const IdHoldOptions& options);  // validates

  // Sets the held IDs in `detection` (robot_id and id_held of the robots carried over) and
  // returns how many robots were carried over. Nothing when the options are not enabled.
  int Apply(SslDetection* detection);

 private:
  struct Track {
    Vec2 position_mm = Vec2::Zero();
    int id = -1;        // the ID the track carries; -1: none
    int reads = 0;      // frames read as `id` since the track took it up
    int missed = 0;     // consecutive frames (matched) not read as `id`
    int other_id = -1;  // the other ID read in those frames, and in how many of them
    int other_reads = 0;
    int unmatched = 0;  // consecutive frames without an observation
  };
  int ApplyTeam(std::vector<SslRobot>* robots, std::vector<Track>* tracks) const;

  IdHoldOptions options_;
  std::vector<Track> yellow_, blue_;
};

}  // namespace patlab::live
