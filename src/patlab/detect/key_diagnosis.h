// Why a robot was not detected, with numbers (patlab detect --explain): for every key blob and
// pattern of Detect's explain records (detector.h KeyExplanation), the stage that rejected it
// with the measured value against its bound, the nearest rotation tried, the nearest pattern of
// that key blob, and the cheapest single setting change that would accept it -- found from the
// measured values and then checked by detecting the same blobs again with the change, so a
// change is only ever named when it does accept the robot ("never a wrong cause").
//
// The settings changed are the detector's tolerances, each candidate value computed from what
// was measured: area_ratio_min / area_ratio_max (the key's or a would-be neighbour's area ratio),
// reach_margin_mm (a would-be neighbour's distance outside the ring), max_neighbours (the
// neighbours found within reach), patch_sigma_mm and geometry_confidence (the nearest rotation's
// E against the tolerance). "Cheapest" is the smallest factor of change, |ln(to / from)| (for
// geometry_confidence, of the miss probability 1 - p), over the candidates that accept the
// robot. Colours, conflicts and a missing patch of another colour have no tolerance to change:
// their diagnosis names the colours or the winner instead.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "patlab/detect/detector.h"

namespace patlab::detect {

// A measured value against the bound it failed (or met): "area ratio 0.19 < 0.23".
struct StageMeasure {
  std::string quantity;  // what was measured, e.g. "key area ratio", "E"
  double value = 0.0;
  std::string relation;  // "<", ">", "<=", ">=": value relation bound
  double bound = 0.0;
  std::string unit;  // "", "mm", "mm^2"
  std::string note;  // where the bound comes from, when it is not a setting as written
};

// A blob that stage 2 did not count as a neighbour of the key, with each of its tests.
struct WouldBeNeighbour {
  int blob = -1;
  double distance_mm = 0.0;                           // from the key
  double reach_min_mm = 0.0, reach_max_mm = 0.0;      // the ring +- reach_margin_mm
  double area_ratio = 0.0;                            // its area / the pattern's non-key patch area
  double area_ratio_min = 0.0, area_ratio_max = 0.0;  // the bounds stage 2 applied to it
  bool colour_ok = false;  // a colour of the pattern's ID slots or fixed patches
  bool reach_ok = false, area_ok = false;
};

// One setting of the detector settings file's [detector] table, from its value to a new one.
struct SettingChange {
  std::string key;  // e.g. "reach_margin_mm"
  double from = 0.0, to = 0.0;
};

struct KeyDiagnosis {
  KeyExplanation explanation;  // the detector's record (outcome = the rejecting stage)
  // The rejecting stage's measures, the deciding one first.
  std::vector<StageMeasure> measures;
  // kFewNeighbours: the blobs nearest the ring that were not counted (at most 3), nearest first.
  std::vector<WouldBeNeighbour> would_be;
  // kColours: the nearest rotation's colour per pattern patch (palette name, "" for none), what
  // is wrong with them, and the nearest codebook ID (-1: none) with the patches it differs in.
  std::vector<std::string> patch_colours;
  std::string colour_problem;
  int nearest_id = -1;
  std::vector<int> nearest_id_differs;
  // Of the records of this key blob, the one whose pattern came nearest to a detection (furthest
  // stage reached, then the smallest E / tolerance).
  bool nearest_pattern = false;
  // The cheapest single setting change that accepts the robot (checked), or none, and why none.
  std::optional<SettingChange> change;
  std::string no_change;
  // With `change`: the detection it gives on this key -- its ID and status. The ID is what the
  // colours of the rotation that then fits say: a patch moved so far that a wrong rotation fits
  // better than the right one is accepted with another ID, and the text says which.
  Detection accepted;
};

struct DiagnosisOptions {
  // The settings file's area_ratio_min times this is the detector's (vision::AdaptToCamera's
  // edge-loss factor; 1 for blobs without a camera). Changes are stated in the file's terms.
  double area_ratio_min_scale = 1.0;
  // At most this many candidate changes are checked per record (each is one Detect).
  int max_checks = 16;
};

// One KeyDiagnosis per record of `explanations` (Detect's explain output for `blobs` with a
// Detector of `config`), in the same order. Only records that are not kDetected get a change.
std::vector<KeyDiagnosis> DiagnoseKeys(const DetectorConfig& config, std::span<const Blob> blobs,
                                       const std::vector<KeyExplanation>& explanations,
                                       const DiagnosisOptions& options = {});

// Whether Detect with `config` changed by `change` (file terms, see DiagnosisOptions) detects
// pattern `pattern` on key blob `key_blob` of `blobs`. False when the change makes the settings
// invalid.
bool ChangeAccepts(const DetectorConfig& config, std::span<const Blob> blobs, int pattern,
                   int key_blob, const SettingChange& change, const DiagnosisOptions& options = {});
// The detection of pattern `pattern` on key blob `key_blob` with the change, or nullopt.
std::optional<Detection> DetectWithChange(const DetectorConfig& config, std::span<const Blob> blobs,
                                          int pattern, int key_blob, const SettingChange& change,
                                          const DiagnosisOptions& options = {});

// "reach_margin_mm 20 -> 27.4"
std::string SettingChangeText(const SettingChange& change);
// "area ratio 0.19 < 0.23"
std::string StageMeasureText(const StageMeasure& measure);
// The diagnosis for people, one line without the key's position (vision::ExplanationText puts
// the frame, the key and its position before it): "few_neighbours: neighbours within reach 1 < 2;
// ...; change reach_margin_mm 20 -> 27.4".
// `blobs` are the ones diagnosed (for the colours of the blobs named).
std::string DiagnosisText(const KeyDiagnosis& diagnosis, const DetectorConfig& config,
                          std::span<const Blob> blobs);

}  // namespace patlab::detect
