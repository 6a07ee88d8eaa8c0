// The section-II track through the colour camera: one pattern rides the paper's
// platform path across the view of a camera 3 m up while render/camera_render.h renders each
// frame (only a window around the pattern) and the real-frame low-level vision (colour lookup
// table, runs, regions, pixel -> mm through the calibration) measures every patch. Truth is
// known, so each patch's error and the pattern's pose error (the paper's fast estimator on the
// measured patches, known correspondence) are exact. It answers: how noisy is each colour class
// (key, ID dots, white) through a Bayer 4:2:2 camera, and what share of that comes from the pixel
// grid, the colour processing, the sensor noise and the camera's jitter (switch each on alone).
//
// Path (section II, docs/track.md): run r of `runs`, frames f = 0 .. frames - 1 at 30 frames/s,
// the pattern origin at x = -travel/2 + speed f / 30, y = offset_r, heading theta_r, with
// offset_r uniform in +-100 mm and theta_r uniform in [-pi, pi) from RandomStream(seed,
// kCameraTrackStream, r). Frame identity for the camera's noise and jitter: r * frames + f.
// Statistics per run about the run's own mean (the paper's smoothing removes a constant offset
// too), pooled over runs: dof = samples - runs per axis. Consecutive frames are correlated, so
// the 95% intervals use dof / tau (stats/effective_n.h: tau from the lag-k autocorrelations of
// each patch's or the pose's per-run series); tau is reported.
//
// With `detect`, each frame's regions (every class of the thresholds) also go as blobs through
// the generic detector (detect/detector.h, default settings, the scene's codebook, key colour
// `team`) and the detected pose of the robot (status ok, the right ID) is scored as the group
// "detect", beside "pose" (the same estimator on known correspondence).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "patlab/core/options.h"
#include "patlab/render/camera_render.h"
#include "patlab/render/scene_render.h"
#include "patlab/vision/color_lut.h"

namespace patlab::analysis {

inline constexpr uint32_t kCameraTrackStream = 0x63747263;  // "ctrc"

struct CameraTrackOptions {
  int runs = 5;               // runs, in [1, 1000]
  int frames = 2570;          // frames per run, in [2, 100000] (the paper: ~2570)
  double speed_mm_s = 23.0;   // platform speed, (0, 1000] mm/s, 30 frames/s
  double travel_mm = 2000.0;  // centred on the camera axis, for the path's start; (0, 10000]
  uint64_t seed = 14;
  // Every ID-slot and key colour drawn as "white" (the scene's colour of that name): the
  // section-II white patches on the same geometry, measured with the threshold class "white".
  bool all_white = false;
  // Also measure the pattern through the detector (group "detect").
  bool detect = false;
  // Called after each frame (frames done, runs x frames); empty = no reports.
  std::function<void(int, int)> progress;
};
std::vector<OptionsProblem> Check(const CameraTrackOptions& options);
void Validate(const CameraTrackOptions& options);

// Std of one group's errors (mm or rad) per axis, with 95% chi-square intervals.
struct GroupError {
  std::string group;                    // "key", "id", "all" (every patch), "pose" or "detect"
  long samples = 0;                     // per axis
  double sx = 0, sx_lo = 0, sx_hi = 0;  // world x (along the travel)
  double sy = 0, sy_lo = 0, sy_hi = 0;  // world y (across)
  double stheta = 0, stheta_lo = 0, stheta_hi = 0;  // pose only (rad)
  // Variance inflation of each std from the frames' autocorrelation (stats::EffectiveSize):
  // the intervals above hold with (samples - runs) / tau degrees of freedom.
  double tau_x = 1, tau_y = 1, tau_theta = 1;
};

struct CameraTrackResult {
  std::vector<GroupError> groups;  // key, id, all, pose
  long missed_patches = 0;         // true patches without a region of their class nearby
  long frames = 0;                 // frames with every patch found (the pose's samples)
  long detected_frames = 0;        // with `detect`: frames where the robot was detected (ok)
  long wrong_id_frames = 0;        // with `detect`: detections at the robot of another ID
  double seconds = 0.0;
};

// `scene` gives the pattern, codebook, colours and render options (its robots are ignored: one
// robot of team `team`, ID `id` rides the path); `calibration` the camera (pinhole, heights per
// class); `thresholds` the colour classes, which must name the team colour, the codebook's ID
// colours (or "white" when all_white).
CameraTrackResult RunCameraTrack(const render::FieldScene& scene,
                                 const camera::Calibration& calibration,
                                 const vision::Thresholds& thresholds, const std::string& team,
                                 int id, const render::CameraSensorOptions& sensor,
                                 const render::CameraJitter& jitter,
                                 const CameraTrackOptions& options);

}  // namespace patlab::analysis
