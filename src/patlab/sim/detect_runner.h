// The detect-mode runner (correspondence = "detect"): every pattern x false-blob rate x patch
// sigma is a data point of `frames` whole frames. A frame is k robots wearing the pattern and a
// ball (GenerateScene), every patch measured with the experiment's NoiseModel, plus the
// [detect] table's missing patches, false blobs and colour-label errors; the blobs go through
// detect::Detector and ScoreFrame matches detections to robots. Per point: detection,
// wrong-ID and ambiguous rates and false positives per frame, each with a 95% interval, and the
// pose error statistics of the correct detections.
//
// Frame f of a point draws every random number from RandomStream(key, kDetectStream, f), key =
// DetectPointKey (experiment seed, pattern content, noise, sigma, false-blob rate, codebook
// content, key colours, palette: point_key.h),
// so a point draws the same frames in any grid (docs/architecture.md rule 1): first the common
// offset (NoiseModel::CommonOffset, once per frame), then the scene, each patch's error from
// NoiseModel::PatchError through PatchNoise::perturb. Frames run in parallel into slots
// indexed by frame number and are reduced in frame order, so results are identical for any
// thread count (docs/architecture.md rules 1-2), and any frame can be replayed alone
// (GenerateDetectFrame).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "patlab/sim/experiment.h"
#include "patlab/sim/runner.h"
#include "patlab/sim/scene.h"
#include "patlab/stats/intervals.h"

namespace patlab::sim {

struct DetectPointResult {
  int pattern_index = 0;
  std::string pattern;
  double sigma_mm = 0.0;
  double false_blob_rate_per_m2 = 0.0;
  uint32_t point = 0;  // grid index (pattern_index * num_rates + rate_index) * num_sigmas + sigma
                       // of this run, for --replay; frames are keyed by DetectPointKey
  int64_t frames = 0;
  double detector_sigma_mm = 0.0;  // the detector's patch_sigma_mm at this point
  double tolerance_mm2 = 0.0;      // its geometric tolerance on E (all patches)

  // Robots over all frames, split by how they were detected (FrameScore).
  int64_t robots = 0, correct = 0, wrong_id = 0, unknown_id = 0, ambiguous = 0, missed = 0;
  int64_t false_positives = 0;      // detections matching no robot
  stats::Proportion detection;      // correct / robots
  stats::Proportion wrong_id_rate;  // wrong_id / (correct + wrong_id): a reported ID is wrong
  stats::Proportion
      ambiguous_rate;  // ambiguous / robots: geometry and colours leave the rotation open
  stats::PoissonRate false_positives_per_frame;

  // Errors of the correct detections (detected minus true; theta wrapped), with the chi-square
  // interval of each std (stats::StdWithConfidence); NaN with fewer than 2 correct detections.
  AxisSummary x, y, theta;
  double crlb_position_mm = 0.0;  // the pattern's Cramer-Rao bound at sigma (isotropic only)
  double crlb_theta_rad = 0.0;

  // Scene and detector counters, summed over frames.
  int64_t false_blobs = 0, missing_patches = 0, colour_errors = 0;
  detect::DetectStats stats;
};

// What one block of a point's frames (runner.h, kStatisticsBlockFrames) leaves: its counters,
// summed over its frames in frame order, and the moments of its correct detections' pose errors.
// A point's blocks fold in frame order into its DetectPointResult (FinishDetectPoint): counters
// add, moments combine (stats::CombineMoments), so a point of any number of blocks has the same
// bits whether one process ran it or the blocks came from trial-range shares (shard.h).
struct DetectBlock {
  WorkBlock work;
  int64_t robots = 0, correct = 0, wrong_id = 0, unknown_id = 0, ambiguous = 0, missed = 0;
  int64_t false_positives = 0, false_blobs = 0, missing_patches = 0, colour_errors = 0;
  detect::DetectStats stats;
  stats::Moments x, y, theta;  // pose errors of the correct detections (mm, mm, rad)
  double tolerance_mm2 = 0.0;  // the detectors' geometric tolerance (the same in every block)
};

// The point's result from all its blocks (block 0, 1, ... in order). `header` holds the point's
// identity (pattern, sigma, rate, point, frames), the detector sigma and the bounds, which are
// copied; the counters, rates, intervals and error statistics come from the blocks. The runner
// and `patlab merge` both finish detect points here.
DetectPointResult FinishDetectPoint(const DetectPointResult& header,
                                    std::span<const DetectBlock> blocks);

struct DetectRunResult {
  std::vector<DetectPointResult> points;  // pattern-major, then false-blob rate, then sigma
  // A sharded run whose points have more than one block of frames: the share's blocks, in item
  // order, and the header (for FinishDetectPoint) of each point they belong to, in point order.
  std::vector<DetectBlock> blocks;
  std::vector<DetectPointResult> block_headers;
  int threads = 0;
  int64_t total_frames = 0;
  double simulate_seconds = 0.0;    // scenes, detection and scoring
  double statistics_seconds = 0.0;  // per-point reduction and intervals
  double wall_seconds = 0.0;
};

// Requires experiment.correspondence == kDetect. Throws InputError if a scene cannot be drawn.
DetectRunResult RunDetectExperiment(const Experiment& experiment, const RunOptions& options);

// One data point's set-up: the detector configuration (only the point's pattern enabled, its
// patch_sigma_mm possibly matched to sigma) and the scene options.
struct DetectPoint {
  int pattern_index = 0, rate_index = 0, sigma_index = 0;
  uint32_t point = 0;  // grid index (for --replay)
  uint64_t key = 0;    // DetectPointKey: what the frames are drawn from
  double sigma_mm = 0.0;
  detect::DetectorConfig config;
  SceneOptions scene;
};
int NumDetectPoints(const Experiment& experiment);
DetectPoint MakeDetectPoint(const Experiment& experiment, uint32_t point);

// Frame `frame` of a point, exactly as the runner draws it (for replaying one frame). `detector`
// must have been built from point.config.
Scene GenerateDetectFrame(const Experiment& experiment, const DetectPoint& point,
                          const detect::Detector& detector, uint64_t frame);

}  // namespace patlab::sim
