// The detect-mode runner (correspondence = "detect"): every pattern x false-blob rate x patch
// sigma is a data point of `frames` whole frames. A frame is k robots wearing the pattern and a
// ball (detect::GenerateScene), every patch measured with the experiment's NoiseModel, plus the
// [detect] table's missing patches, false blobs and colour-label errors; the blobs go through
// detect::Detector and detect::ScoreFrame matches detections to robots. Per point: detection,
// wrong-ID and ambiguous rates and false positives per frame, each with a 95% interval, and the
// pose error statistics of the correct detections.
//
// Frame f of point p draws every random number from RandomStream(seed, p, f): first the common
// offset (NoiseModel::CommonOffset, once per frame), then the scene, each patch's error from
// NoiseModel::PatchError through detect::PatchNoise::perturb. Frames run in parallel into slots
// indexed by frame number and are reduced in frame order, so results are identical for any
// thread count (DESIGN.md rules 1-2), and any frame can be replayed alone (GenerateDetectFrame).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "detect/scene.h"
#include "sim/experiment.h"
#include "sim/runner.h"

namespace patlab::sim {

// A proportion k / n with its 95% Wilson score interval (Wilson 1927, JASA 22:209):
//   centre = (p + z^2 / 2n) / (1 + z^2 / n),
//   half   = z / (1 + z^2 / n) * sqrt(p (1 - p) / n + z^2 / 4n^2),   p = k / n, z = 1.959964.
// Unlike the normal interval it stays inside [0, 1] and is not empty at k = 0 or k = n.
// n = 0: rate and interval NaN.
struct Proportion {
  int64_t count = 0;
  int64_t total = 0;
  double rate = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};
Proportion WilsonInterval(int64_t count, int64_t total);

// A Poisson mean per unit (events per frame) with its exact 95% interval (Garwood 1936):
//   lower = chi2_{2K}^-1(0.025) / 2F, upper = chi2_{2K+2}^-1(0.975) / 2F, K events in F frames
// (lower = 0 when K = 0).
struct PoissonRate {
  int64_t count = 0;
  int64_t frames = 0;
  double rate = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};
PoissonRate GarwoodInterval(int64_t count, int64_t frames);

struct DetectPointResult {
  int pattern_index = 0;
  std::string pattern;
  double sigma_mm = 0.0;
  double false_blob_rate_per_m2 = 0.0;
  uint32_t point = 0;  // stream id: (pattern_index * num_rates + rate_index) * num_sigmas + sigma
  int64_t frames = 0;
  double detector_sigma_mm = 0.0;  // the detector's patch_sigma_mm at this point
  double tolerance_mm2 = 0.0;      // its geometric tolerance on E (all patches)

  // Robots over all frames, split by how they were detected (detect::FrameScore).
  int64_t robots = 0, correct = 0, wrong_id = 0, unknown_id = 0, ambiguous = 0, missed = 0;
  int64_t false_positives = 0;  // detections matching no robot
  Proportion detection;         // correct / robots
  Proportion wrong_id_rate;     // wrong_id / (correct + wrong_id): a reported ID is wrong
  Proportion ambiguous_rate;    // ambiguous / robots: geometry and colours leave the rotation open
  PoissonRate false_positives_per_frame;

  // Errors of the correct detections (detected minus true; theta wrapped), with the chi-square
  // interval of each std (stats::StdWithConfidence); NaN with fewer than 2 correct detections.
  AxisSummary x, y, theta;
  double crlb_position_mm = 0.0;  // the pattern's Cramer-Rao bound at sigma (isotropic only)
  double crlb_theta_rad = 0.0;

  // Scene and detector counters, summed over frames.
  int64_t false_blobs = 0, missing_patches = 0, colour_errors = 0;
  detect::DetectStats stats;
};

struct DetectRunResult {
  std::vector<DetectPointResult> points;  // pattern-major, then false-blob rate, then sigma
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
  uint32_t point = 0;
  double sigma_mm = 0.0;
  detect::DetectorConfig config;
  detect::SceneOptions scene;
};
int NumDetectPoints(const Experiment& experiment);
DetectPoint MakeDetectPoint(const Experiment& experiment, uint32_t point);

// Frame `frame` of a point, exactly as the runner draws it (for replaying one frame). `detector`
// must have been built from point.config.
detect::Scene GenerateDetectFrame(const Experiment& experiment, const DetectPoint& point,
                                  const detect::Detector& detector, uint64_t frame);

}  // namespace patlab::sim
