// The generic pattern detector of the paper (section III): one frame's unordered blobs in,
// detections {pattern, team colour, ID, pose, fit residual, confidence} out, in a fixed order.
//
// Numbered stages (docs/architecture.md rule 8). Each is counted in DetectStats and, when a
// TimeProfile is passed to Detect, timed under exactly the name given here (kDetectStageNames):
//  1 candidates:    blobs of an enabled team colour whose area is in the key patch's range (with
//                   the bucketing of blobs by x that stage 2 searches);
//  2 neighbours:    blobs of the pattern's ID / fixed colours, area in range, whose distance from
//                   the key is within the ring the model's non-key patches lie on
//                   (+- reach_margin_mm); at most max_neighbours, those nearest the ring;
//  3 radial sort:   the neighbours by angle about the key;
//  4 fit rotations: every choice of as many neighbours as the model has non-key patches, and
//                   every rotation of them against the model's circular order, through the rigid
//                   least-squares fit and the chi-square geometric test
//                   E <= patch_sigma_mm^2 * chi2 quantile (2m - 3 dof) -- this is what fixes the
//                   rotation of a geometrically asymmetric pattern (Butterfly);
//  5 identify:      for the rotations passing geometry, the colour test and ID: fixed-colour
//                   patches must have their colour; the ID-slot colours must be a codebook ID.
//                   Exactly one rotation passing both -> a candidate; two or more rotations that
//                   geometry cannot tell apart and colours do not decide -> kAmbiguous, not
//                   guessed;
//  6 missing patch: (MissingPatchPolicy::kFit) when no full correspondence passes, stages 4 and 5
//                   on one patch fewer, reported kMissingPatch (timed here as a whole);
//  7 conflicts:     candidates ranked (unambiguous first, more blobs explained first, then lower
//                   E / tolerance); each blob goes to the best candidate only (two robots close
//                   together; patterns sharing a key colour);
//  8 pose:          pose with the chosen estimator (estimate/), confidence, and the fixed output
//                   order.
//
// The hot path reuses buffers held by the Detector and does not allocate once they have grown.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "patlab/core/enum_names.h"
#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/core/pattern.h"
#include "patlab/core/timeprofile.h"
#include "patlab/detect/blob.h"
#include "patlab/detect/codebook.h"
#include "patlab/estimate/estimators.h"

namespace patlab::detect {

enum class MissingPatchPolicy {
  kReject,  // a pattern with a patch missing is not detected
  kFit,     // fit on the remaining patches and report kMissingPatch
};
inline constexpr EnumNames<MissingPatchPolicy, 2> kMissingPatchPolicyNames{
    {{{MissingPatchPolicy::kReject, "reject"}, {MissingPatchPolicy::kFit, "fit"}}}};
// NameOf(policy, kMissingPatchPolicyNames), for the callers outside detect/.
std::string_view MissingPatchPolicyName(MissingPatchPolicy policy);

// Detector settings. Defaults are the values documented in experiments/detector.toml.
struct DetectorOptions {
  // Expected standard deviation of one blob centre per axis (mm). Sets the geometric tolerance:
  // E <= patch_sigma_mm^2 * chi2_{2m-3}^-1(geometry_confidence), m = patches fitted. Larger
  // accepts worse blobs but lets wrong rotations of a nearly symmetric pattern pass: the
  // Butterfly's wrong rotations have E >= 932 mm^2, so keep the tolerance well below that.
  double patch_sigma_mm = 2.0;
  // The calibration's measured RMS position error (mm) on the plane the patterns lie on (a
  // camera frame: the calibration file's [[residual]] row, set by vision::FrameDetector; 0 for
  // simulated blobs and old calibration files). It adds to the blob noise: the geometric test
  // and the confidence use the effective sigma^2 = patch_sigma_mm^2 + calibration_residual_mm^2
  // (EffectiveSigma2Mm2), so that settings tuned on good blobs also work through an imperfect
  // camera model (docs/detect.md, "Settings that travel"). >= 0.
  double calibration_residual_mm = 0.0;
  // Probability that a correct correspondence with Gaussian noise of patch_sigma_mm passes the
  // geometric test, in (0, 1). Higher: fewer misses, looser tolerance.
  double geometry_confidence = 0.9999;
  // How far (mm) a neighbour's distance from the key may lie outside the range of the model's
  // non-key patch distances. Larger tolerates more noise but draws in more foreign blobs.
  double reach_margin_mm = 20.0;
  // Accepted blob area as a fraction of the model patch area pi r^2, for keys and neighbours.
  double area_ratio_min = 0.4;
  double area_ratio_max = 2.5;
  MissingPatchPolicy missing_patch = MissingPatchPolicy::kReject;
  // Most neighbours considered around one key (those nearest the model's ring are kept);
  // the number of correspondences grows as C(max_neighbours, m - 1). In [1, 16].
  int max_neighbours = 8;
  estimate::Estimator estimator = estimate::Estimator::kFast;
  estimate::Options ml;  // for Estimator::kMl
};

// The variance per axis (mm^2) the geometric test assumes for one blob centre: the segmentation
// noise patch_sigma_mm^2 plus the calibration's calibration_residual_mm^2 (independent errors add
// in variance).
double EffectiveSigma2Mm2(const DetectorOptions& options);

// The one place DetectorOptions are checked (core/options.h): every broken constraint, field names
// as the settings file spells them (the ML options with prefix "ml_", estimate::Check).
std::vector<OptionsProblem> Check(const DetectorOptions& options);
// Throws InputError with the first problem of Check, if any.
void Validate(const DetectorOptions& options);

// One pattern the detector looks for.
struct DetectorPattern {
  Pattern pattern;
  Codebook codebook;                     // its IDs (GenerateCodebook or a codebook file)
  std::vector<std::string> key_colours;  // team colours (palette names) of its key patch
  double symmetry_tolerance_mm = 10.0;   // see FindSymmetry; paper section III rule of thumb
};

struct DetectorConfig {
  // Colour names; a blob's colour label is an index into this (at most 64 colours).
  std::vector<std::string> palette;
  DetectorOptions options;
  std::vector<DetectorPattern> patterns;
};

enum class DetectionStatus {
  kOk,            // every patch found; ID from the colours
  kMissingPatch,  // fitted on one patch fewer (MissingPatchPolicy::kFit); id may be -1
  kAmbiguous,     // geometry fits but neither it nor the colours fix the rotation: id = -1 and
                  // theta is one of the symmetric candidates
};
inline constexpr EnumNames<DetectionStatus, 3> kDetectionStatusNames{
    {{{DetectionStatus::kOk, "ok"},
      {DetectionStatus::kMissingPatch, "missing_patch"},
      {DetectionStatus::kAmbiguous, "ambiguous"}}}};
// NameOf(status, kDetectionStatusNames), for the callers outside detect/.
std::string_view DetectionStatusName(DetectionStatus status);

struct Detection {
  int pattern = 0;       // index into DetectorConfig::patterns
  int team_colour = -1;  // palette label of the key blob
  int id = -1;           // codebook ID, or -1 when unknown
  DetectionStatus status = DetectionStatus::kOk;
  Pose2 pose;                 // of the model origin, with DetectorOptions::estimator
  double residual_mm2 = 0.0;  // E: sum-squared error of the rigid least-squares fit
  double confidence = 0.0;    // P(chi2_{2m-3} >= E / EffectiveSigma2Mm2): 1 perfect, ~0 poor
  int missing_patch = -1;     // kMissingPatch: the pattern patch index not found
  std::array<int, kMaxPatches> blob{};  // blob index per pattern patch (-1: missing)
};

// The stage names of the header comment, in order: what Detect stamps into a TimeProfile.
inline constexpr std::array<std::string_view, 8> kDetectStageNames = {
    "1 candidates", "2 neighbours",    "3 radial sort", "4 fit rotations",
    "5 identify",   "6 missing patch", "7 conflicts",   "8 pose"};

// Per-frame counters of the stages (summed over frames by operator+=).
struct DetectStats {
  long key_candidates = 0;   // stage 1: (key blob, pattern) pairs
  long neighbours = 0;       // stage 2: neighbour blobs found, summed over key candidates
  long neighbours_cut = 0;   // stage 2: dropped beyond max_neighbours
  long correspondences = 0;  // stage 4: rotations tried (stage 6's included)
  long geometry_passed = 0;  // stage 4: rotations passing the geometric test
  long colour_rejected = 0;  // stage 5: a single geometric fit whose colours are no ID
  long ambiguous = 0;        // stage 5: reported kAmbiguous
  long missing_fits = 0;     // stage 6: reported kMissingPatch
  long conflicts = 0;        // stage 7: candidates dropped for sharing a blob
  long detections = 0;       // stage 8: detections returned

  DetectStats& operator+=(const DetectStats& other);
};

// Why a key candidate became a detection or not: Detect's optional `explain` output, one record
// per blob of a pattern's key colour (patlab detect --explain).
enum class KeyOutcome {
  kDetected,       // a detection (its status: ok, missing_patch or ambiguous)
  kKeyArea,        // stage 1: the blob's area is outside the key patch's range; not a candidate
  kFewNeighbours,  // stage 2: fewer neighbours within reach than the pattern's non-key patches
                   // (one fewer with MissingPatchPolicy::kFit)
  kGeometry,       // stage 4: no rotation of any choice of neighbours has E within tolerance
  kColours,        // stage 5: rotations passed geometry, but their colours are no codebook ID (or
                   // a fixed patch has the wrong colour)
  kConflict,       // stage 7: a candidate, but a better-ranked one took one of its blobs
};
inline constexpr EnumNames<KeyOutcome, 6> kKeyOutcomeNames{
    {{{KeyOutcome::kDetected, "detected"},
      {KeyOutcome::kKeyArea, "key_area"},
      {KeyOutcome::kFewNeighbours, "few_neighbours"},
      {KeyOutcome::kGeometry, "geometry"},
      {KeyOutcome::kColours, "colours"},
      {KeyOutcome::kConflict, "conflict"}}}};

struct KeyExplanation {
  int pattern = 0;   // index into DetectorConfig::patterns
  int key_blob = 0;  // index into the blobs
  KeyOutcome outcome = KeyOutcome::kDetected;
  // Stage 2: neighbours within reach (after the max_neighbours cut) and how many a full fit needs.
  int neighbours = 0;
  int needed = 0;
  // Stage 4: rotations tried and passing geometry (full and missing-patch fits), the smallest E
  // of the full fits (inf when none was tried) and its tolerance.
  long rotations = 0;
  long geometry_passed = 0;
  double best_e_mm2 = 0.0;
  double tolerance_mm2 = 0.0;
  int detection = -1;        // kDetected: index into the detections
  int lost_to_key = -1;      // kConflict: the key blob of the candidate that won ...
  int lost_to_pattern = -1;  // ... and its pattern
  int lost_blob = -1;        // ... and the blob it took
  // The nearest rotation tried: the full fit with the smallest E (best_e_mm2), as the rotation
  // (0 .. non-key patches - 1: the shift of the pattern's circular order against the neighbours
  // in angular order) and the blob given to each pattern patch (-1: none); -1 when none was tried.
  int nearest_rotation = -1;
  std::array<int, kMaxPatches> nearest_blob{};
};

// P(chi-square with `dof` degrees of freedom >= e), dof >= 1: the detections' confidence.
double ChiSquaredSurvival(int dof, double e);

class Detector {
 public:
  // Validates the configuration (colour names, codebooks against the patterns, options) and
  // precomputes the models. Throws InputError.
  explicit Detector(DetectorConfig config);
  ~Detector();
  Detector(Detector&&) noexcept;
  Detector& operator=(Detector&&) noexcept;

  // Detects every enabled pattern in one frame. `detections` is cleared and filled, ordered by
  // (pattern, team colour, status, id, x, y). `stats` (optional) is overwritten. When `profile`
  // is given and enabled, the wall time of each stage of kDetectStageNames is added to it (one
  // entry per stage, count 1 per call; the stages partition the call). The clock reads cost
  // ~20-30 ns each, charged to the stage they end (about 5 per key candidate, 2 per choice of
  // neighbours with a rotation passing geometry, 2 per detection); without an enabled profile no
  // clock is read. Blob colours outside the palette and positions beyond 1e9 mm or not finite
  // are ignored. `explain` (optional) is cleared and filled with one KeyExplanation per blob of
  // a key colour and pattern, in blob order; without it nothing is recorded (no allocation, one
  // branch per key candidate). Not thread-safe: use one Detector per thread.
  void Detect(std::span<const Blob> blobs, std::vector<Detection>* detections,
              DetectStats* stats = nullptr, TimeProfile* profile = nullptr,
              std::vector<KeyExplanation>* explain = nullptr);

  const DetectorConfig& config() const;
  // The palette label of a colour name, or -1.
  int ColourLabel(std::string_view name) const;
  // The geometric tolerance on E (mm^2) of pattern p with all patches / one patch missing.
  double ResidualTolerance(int pattern, bool missing_patch = false) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace patlab::detect
