// Experiment files (experiments/*.toml; format documented in README.md, "Experiment files").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "patlab/core/pattern.h"
#include "patlab/detect/detector.h"
#include "patlab/sim/scene.h"
#include "patlab/estimate/estimators.h"
#include "patlab/sim/noise.h"

namespace patlab::sim {

// How patches reach the estimator.
enum class Correspondence {
  kKnown,   // patches already matched to the model (the estimator engine: runner.h)
  kDetect,  // whole frames of blobs through detect::Detector (detect_runner.h)
};

// What the detector sees in every frame of a detect-mode data point, and how detections are
// scored (the [detect] table; README "Detect-mode experiments" lists every key and default).
struct DetectSettings {
  std::string settings_file;          // the detector settings file, resolved
  detect::DetectorConfig detector;    // as loaded; a data point enables one of its patterns
  std::vector<int> detector_pattern;  // per experiment pattern: its index in detector.patterns
  int64_t frames = 1000;              // frames per data point, 1..100000000
  // robots_per_team, the probabilities, false-blob radii, ball, robot radius and separation;
  // the field comes from [field]; false_blob_rate_per_m2 is set per point from the grid below.
  SceneOptions scene;
  // The false-blob rates (per m^2 of field), a second grid axis; one value = no sweep.
  std::vector<double> false_blob_rates_per_m2 = {0.0};
  // A detection of the right pattern and team within this distance of a robot's true centre
  // is matched to it (ScoreFrame; nearest first). Larger forgives worse positions but
  // may pair a detection with a neighbouring robot.
  double match_radius_mm = 45.0;
  // false: the detector's patch_sigma_mm is the settings' value. true (detector_sigma =
  // "matched"): per point max(settings value, sigma * noise.EffectiveSigmaRatio()), a detector
  // told the true noise level, so its geometric tolerance grows with the sweep.
  bool matched_sigma = false;
};

struct Experiment {
  std::string name;
  std::string description;
  std::string source_file;                          // the experiment file, for the manifest
  std::vector<Pattern> patterns;                    // in file order
  std::vector<std::string> pattern_files;           // resolved paths, same order
  std::vector<estimate::Estimator> estimators;      // in file order, no duplicates
  std::vector<double> sigmas_mm;                    // the patch sigma grid, >= 0, increasing
  int64_t trials = 100000;                          // per data point, >= 2
  uint64_t seed = 1;                                // experiment seed
  double field_length_mm = 2800.0;                  // random pose x range: +-length/2
  double field_width_mm = 2300.0;                   // random pose y range: +-width/2
  NoiseModel noise;
  estimate::Options ml_options;
  Correspondence correspondence = Correspondence::kKnown;
  DetectSettings detect;  // correspondence = "detect" only
};

// Reads an experiment file. Pattern names resolve to <patterns_dir>/<name>.toml, where
// patterns_dir defaults to ../patterns relative to the experiment file (key `patterns_dir`).
// With correspondence = "detect" they name [[pattern]]s of the [detect] settings file instead,
// and trials, estimators, ml and patterns_dir are rejected (the detector settings hold them).
Experiment LoadExperimentFile(const std::string& path);

// Command-line overrides, applied after loading and validated like the file.
struct Overrides {
  int64_t trials = 0;  // 0: keep; in detect mode the frames per point
  bool has_seed = false;
  uint64_t seed = 0;
  std::vector<double> sigmas_mm;  // empty: keep
};
void ApplyOverrides(const Overrides& overrides, Experiment* experiment);

}  // namespace patlab::sim
