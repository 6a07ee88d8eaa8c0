// Every failure can be replayed (docs/architecture.md rule 3): one trial of a known-correspondence
// experiment, or one frame of a detect-mode experiment, recomputed alone from its identity
// (point, trial or frame) exactly as the runners draw it, with a text report for a person.
// `patlab simulate --replay POINT,TRIAL` prints these.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/core/pattern.h"
#include "patlab/detect/detector.h"
#include "patlab/estimate/estimators.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/scene.h"

namespace patlab::sim {

// A replay request "POINT,TRIAL" (or "POINT,FRAME"): two integers >= 0. Throws InputError
// "--replay is '<spec>'; expected POINT,<what> (two integers >= 0)" otherwise.
struct ReplayIndex {
  int64_t point = 0;
  int64_t index = 0;  // the trial or the frame
  std::string spec;   // as the user wrote it, for messages
};
ReplayIndex ParseReplayIndex(std::string_view spec, std::string_view what);

// One trial of a known-correspondence experiment: its true pose, the observed patches, and the
// estimate and error of each of the experiment's estimators exactly as the run computed them
// (the kernel's own outputs for that trial, sim/batch.h RunTrialAsInBatch: the same bits), with
// the ML summary (its Newton steps and termination as the run counted them, the costs at the
// fast start and at the estimate).
struct TrialReplay {
  int64_t point = 0, trial = 0;
  const Pattern* pattern = nullptr;  // into the experiment
  double sigma_mm = 0.0;
  uint64_t seed = 0;
  Pose2 truth;
  std::vector<Vec2> observed;                             // per pattern patch
  std::vector<estimate::Estimator> estimators;            // the experiment's, in its order
  std::array<Pose2, estimate::kNumEstimators> estimates;  // per estimate::Estimator
  std::array<Pose2, estimate::kNumEstimators>
      errors;  // estimate - truth, theta wrapped, as the run
  estimate::Summary ml_summary;
};
// Throws InputError when the point or trial is out of the experiment's range.
TrialReplay ReplayTrial(const Experiment& experiment, const ReplayIndex& index);
std::string ReplayText(const TrialReplay& replay);

// One frame of a detect-mode experiment: the scene, the detections and their score.
struct FrameReplay {
  int64_t point = 0, frame = 0;
  std::string pattern;
  double sigma_mm = 0.0;
  double false_blob_rate_per_m2 = 0.0;
  uint64_t seed = 0;
  std::vector<std::string> palette;
  Scene scene;
  std::vector<detect::Detection> detections;
  FrameScore score;
};
// Requires experiment.correspondence == kDetect. Throws InputError when out of range.
FrameReplay ReplayDetectFrame(const Experiment& experiment, const ReplayIndex& index);
std::string ReplayText(const FrameReplay& replay);

}  // namespace patlab::sim
