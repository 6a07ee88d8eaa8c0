// Experiment files (experiments/*.toml; format documented in docs/file-formats.md).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/enum_names.h"
#include "patlab/core/options.h"
#include "patlab/core/pattern.h"
#include "patlab/detect/detector.h"
#include "patlab/estimate/estimators.h"
#include "patlab/sim/noise.h"
#include "patlab/sim/scene.h"

namespace patlab::sim {

// How patches reach the estimator.
enum class Correspondence {
  kKnown,   // patches already matched to the model (the estimator engine: runner.h)
  kDetect,  // whole frames of blobs through detect::Detector (detect_runner.h)
};
// As experiment files spell them (key `correspondence`).
inline constexpr EnumNames<Correspondence, 2> kCorrespondenceNames{
    {{{Correspondence::kKnown, "known"}, {Correspondence::kDetect, "detect"}}}};

// The detector's patch sigma in detect mode (key `detector_sigma`; DetectSettings::matched_sigma).
inline constexpr EnumNames<bool, 2> kDetectorSigmaNames{{{{false, "settings"}, {true, "matched"}}}};

// What the detector sees in every frame of a detect-mode data point, and how detections are
// scored (the [detect] table; docs/file-formats.md lists every key and default).
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

// The sizes of an experiment, each limit stated once for files, flags and EvaluatePattern.
// Trials per known-correspondence point: >= 2 for a sample std; at most 1e9 (hours of work).
inline constexpr int64_t kMinTrials = 2;
inline constexpr int64_t kMaxTrials = 1'000'000'000;
// Frames per detect-mode point: at most 1e8 (every frame keeps a slot in memory).
inline constexpr int64_t kMaxFrames = 100'000'000;

// Add the problems of one size to `check`; `field` is the name messages use ("trials",
// "--trials"). A sigma grid must be non-empty, finite, >= 0 and strictly increasing: the
// report's rows are in sigma order and a repeated sigma would repeat a data point.
void CheckTrials(int64_t trials, std::string_view field, OptionsChecker* check);
void CheckFrames(int64_t frames, std::string_view field, OptionsChecker* check);
void CheckSigmas(std::span<const double> sigmas_mm, std::string_view field, OptionsChecker* check);
// The field the poses are drawn on: each side in [0, 100000] mm (a 100 m field is far beyond
// any robot league; 1e308 would make every pose error vanish in rounding).
inline constexpr double kMaxFieldSideMm = 1e5;
void CheckFieldSides(double length_mm, double width_mm, std::string_view length_field,
                     std::string_view width_field, OptionsChecker* check);

// The detect-mode settings, fields named as the [detect] keys: frames, match_radius_mm and every
// scene option (Check(SceneOptions)), the scene's false-blob rate included.
std::vector<OptionsProblem> Check(const DetectSettings& settings);

struct Experiment {
  std::string name;
  std::string description;
  std::string source_file;                      // the experiment file, for the manifest
  std::vector<Pattern> patterns;                // in file order
  std::vector<std::string> pattern_files;       // resolved paths, same order
  std::vector<estimate::Estimator> estimators;  // in file order, no duplicates
  std::vector<double> sigmas_mm;                // the patch sigma grid, >= 0, increasing
  int64_t trials = 100000;                      // per data point, >= 2
  uint64_t seed = 1;                            // experiment seed
  double field_length_mm = 2800.0;              // random pose x range: +-length/2
  double field_width_mm = 2300.0;               // random pose y range: +-width/2
  NoiseModel noise;
  estimate::Options ml_options;
  Correspondence correspondence = Correspondence::kKnown;
  DetectSettings detect;  // correspondence = "detect" only
};

// Every broken constraint of an experiment, however it was made (a file, the flags, a program):
// trials, sigmas_mm, the noise model, the ML options and, in detect mode, the DetectSettings.
std::vector<OptionsProblem> Check(const Experiment& experiment);
void Validate(const Experiment& experiment);

// Command-line overrides, applied after loading and checked with the file's limits; messages name
// the flag ("--trials is 1; expected an integer in [2, 1000000000]").
struct Overrides {
  std::optional<int64_t> trials;  // in detect mode the frames per point
  std::optional<uint64_t> seed;
  std::vector<double> sigmas_mm;  // empty: keep
};
void ApplyOverrides(const Overrides& overrides, Experiment* experiment);

}  // namespace patlab::sim
