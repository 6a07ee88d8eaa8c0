// The run of the track experiment (track.h gives the whole picture): every frame of every run
// rendered, segmented and measured, then each subject's errors in the track frame, both the
// paper's estimate (sample minus the Gaussian-smoothed track) and the true error.
//
// Randomness (docs/architecture.md rule 1): everything is a pure function of (seed, run, frame,
// pixel):
//   run setup (heading, start)   RandomStream(seed, kRunStream, run)
//   camera jitter of a frame     RandomStream(seed, kJitterStream, run << 32 | frame)
//   intensity noise of a pixel   Philox block (frame, run, kPixelStream, y * width + x)
// so the subjects of a run see the same frames (paired samples, as on the paper's single
// platform) and results do not depend on the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "patlab/analysis/track_options.h"
#include "patlab/core/geometry.h"

namespace patlab::analysis {

inline constexpr uint32_t kRunStream = 0x7472756e;     // "trun"
inline constexpr uint32_t kJitterStream = 0x746a6974;  // "tjit"
inline constexpr uint32_t kPixelStream = 0x7470786c;   // "tpxl"

// One subject over one run: per kept sample (after trimming), errors in the track frame (mm;
// theta in rad, patterns only). est_* = sample - Gaussian-smoothed track (the paper's estimate);
// true_* = sample - truth. Missing samples (no region found) are interpolated for the smoothing
// and left out here; missed_frames counts them.
struct SubjectRun {
  std::vector<int> sample;  // frame index of each kept sample
  std::vector<double> est_x_mm, est_y_mm, true_x_mm, true_y_mm;
  std::vector<double> est_theta_rad, true_theta_rad;  // patterns only
  int missed_frames = 0;
};

struct RunSetup {
  double heading_rad = 0.0;
  Vec2 start_mm = Vec2::Zero();  // platform centre at frame 0
};
RunSetup MakeRunSetup(const TrackOptions& options, int run);

// True pose of subject `subject` in frame `frame` of a run (theta = the run's heading).
Pose2 TruthPose(const TrackOptions& options, const RunSetup& setup, int frame, int subject);
// A world-frame error in the track frame of a run: x along the travel, y across it.
Vec2 ToTrackFrame(const Vec2& world_error_mm, double heading_rad);

// Re-measures one subject in one frame exactly as RunTrack does (docs/architecture.md rule 3:
// any sample can be replayed alone): a disc's centroid (theta 0), or the pattern's
// fast-estimator pose. False when a region was not found.
bool MeasureSubject(const TrackOptions& options, int run, int frame, int subject, Pose2* measured);

// The measured world position (mm) of a single disc of diameter_mm at truth position world_mm in
// frame `frame` of run `run` (jitter and noise included), or false when no region was found.
// Exposed for tests and replays.
bool MeasureDisc(const TrackOptions& options, int run, int frame, const Vec2& world_mm,
                 double diameter_mm, Vec2* measured_mm);

// One subject of one frame, replayed alone (MeasureSubject), with its truth and its true error
// in the track frame.
struct ReplayedSubject {
  std::string name;  // as SubjectNames() names it
  Pose2 truth;
  bool found = false;  // false: no region was found, the rest is unset
  Pose2 measured;
  Vec2 true_error_mm = Vec2::Zero();  // x along the travel, y across it
  bool has_theta = false;             // the pattern subject
  double true_theta_error_rad = 0.0;
};
// Every subject of frame `frame` of run `run` (0 <= run < runs, 0 <= frame < samples_per_run).
std::vector<ReplayedSubject> ReplayFrame(const TrackOptions& options, int run, int frame);

struct TrackResult {
  std::vector<std::string> subjects;          // SubjectNames(): "40mm", ..., the pattern name
  std::vector<std::vector<SubjectRun>> data;  // [subject][run]
  std::vector<RunSetup> setups;               // per run
  int smoothing_radius = 0;  // radius (samples) of the kernel behind the estimated errors
  double wall_seconds = 0.0;
  double measure_seconds = 0.0;   // stage 1: render, segment, camera (and fast estimator)
  double analysis_seconds = 0.0;  // stage 2: smoothing residuals, track-frame errors
  int threads = 0;
};

struct TrackRunOptions {
  int threads = 0;  // 0 = all cores; results do not depend on it
  // Called after each block of frames is measured: (blocks done, blocks in all). Called from the
  // worker threads one at a time (under a lock), with the count increasing by one each call.
  std::function<void(int, int)> progress = {};
};

// Runs the whole experiment (TBB over blocks of frames, results in fixed slots). Validates first.
TrackResult RunTrack(const TrackOptions& options, const TrackRunOptions& run_options = {});

}  // namespace patlab::analysis
