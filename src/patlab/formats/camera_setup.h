// A new camera set up from its frames, behind `patlab setup` (docs/setup.md): the field's lines
// give the calibration (vision/field_lines.h FindLinePixels once, then
// calib::AutoCalibrateFamily: every model screened by its search, the best few fitted, the one
// whose camera explains the most line length kept; where a second camera explains nearly as
// much yet maps the frame differently, the one through which the most robots decode), or, as a
// fallback, landmarks the user clicked; the camera's height, which a view of the floor leaves
// nearly open, given (--camera-height) or measured by the robots' patterns (SetupHeight,
// camera_setup_height.cpp); the colour classes the settings' palette names give the
// thresholds (vision/thresholds_auto.h); and the detector's tolerances are chosen from what was
// measured. The result is four files in one folder -- calibration.toml, thresholds.toml,
// settings.toml (the given settings with a [detector] table of the chosen tolerances and the
// settings' own missing_patch, max_neighbours and estimator) and
// setup.toml naming them -- which `patlab detect --setup DIR` reads.
//
// Tolerances (SetupTolerances): with s the floor's mm per pixel at the image centre on the
// robots' plane and e the calibration's mapping error (mm, mapping_error_mm; at least its
// resolution),
//   patch_sigma_mm  = max(2, 0.4 s)  -- a thresholded patch's centroid is good to ~0.4 px;
//   reach_margin_mm = max(20, 3 e + 2 s)  -- a patch may be found 3 mapping errors and 2 pixels
//                     beyond the pattern's reach;
//   area_ratio_min  = clamp(0.5 ((r - 1.06) / r)^2, 0.1, 0.4), r the smallest patch's radius in
//                     px -- the thresholds keep a patch's core, about a pixel inside its edge
//                     (settings/ssl-frame.detector.toml explains the 1.06 px); half of that
//                     admits every patch;
//   area_ratio_max  = 2.5.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "patlab/calib/auto_calibrate.h"
#include "patlab/calib/field.h"
#include "patlab/camera/image.h"
#include "patlab/detect/detector.h"
#include "patlab/vision/thresholds_auto.h"
#include "patlab/vision/thresholds_blobs.h"

namespace patlab::formats {

// A landmark of the field model clicked in the first frame (`--landmark NAME=X,Y`).
struct SetupLandmark {
  std::string name;
  Vec2 pixel = Vec2::Zero();
};

struct SetupOptions {
  // The field models to try (one model, or every model of a family); at least one.
  std::vector<calib::Field> fields;
  // Models searched only for views to lend to `fields` (calib::AutoCalibrateFamily's lenders):
  // with one model named, the rest of its family (formats::SetupFieldModels).
  std::vector<calib::Field> lenders;
  std::string settings_path;  // detector settings: palette and patterns (required)
  // The robots' pattern plane above the floor (mm), written as the calibration's default height;
  // in [0, 1000].
  double robot_height_mm = 140.0;
  double line_width_px = 4.0;  // the field lines' width in the frames, in [1, 30]
  // The camera's measured height above the floor (mm; `--camera-height`, as calibrate --auto's):
  // the calibration is fitted with it (calib::FitOptions::camera_height_mm) and the robots do not
  // choose the height. Unset: the lines' camera, or the robots' where the lines leave it open
  // (SetupHeight). In (robot_height_mm, 100000].
  std::optional<double> camera_height_mm;
  // When not empty (at least 4): the calibration is fitted to these in the first frame instead
  // of the lines, with the first field model.
  std::vector<SetupLandmark> landmarks;
  // The pixel clustering's options (vision/thresholds_auto.h), the colour fit setup weighs
  // against the blobs' (SetupResult::colour_fit).
  vision::AutoThresholdsOptions thresholds;
  // The colour fit (vision/thresholds_blobs.h); its blob area range is set from the calibration
  // and the patterns' patch sizes (SetupBlobAreas).
  vision::BlobThresholdsOptions colours;
  // The frames binned k x k (camera::BinImage) before setup works on them; 0: chosen from their
  // size (SetupBinning). In [0, detect::kMaxBinning]. line_width_px is in the binned frames'
  // pixels, landmarks in the frames' own.
  int binning = 0;
};

// Setup works on frames of at most about this many pixels along their longer side: the line
// finder, the colour fit's segmentation and the tolerances were developed on frames of 580-780
// px (the SSL cameras of 2008-2015, the VSS webcams), and its CPU time grows with the pixels.
inline constexpr int kSetupWorkingPx = 1024;
// The binning SetupOptions::binning = 0 chooses for frames of this size: the least k that
// brings the longer side to kSetupWorkingPx or below (1 for frames that small already).
int SetupBinning(int width_px, int height_px);

// One field model tried: its search's score (the screen), its fitted camera's score (px of line
// explained), or why it failed or was not fitted (calib::AutoCalibrateFamily).
struct SetupFieldTry {
  std::string field;
  double score_px = 0.0;
  double held_out_mapping_mm = 0.0;
  std::string failure;         // "" when it fitted
  double screen_px = 0.0;      // the search's best score (NaN: the search failed; landmarks: 0)
  bool fitted = true;          // given the full fit (false: screened out, or the search failed)
  std::string same_as;         // the earlier model of the same lines whose result it shares
  std::string screen_view_of;  // the model whose search found its best view ("": its own)
};

// A camera the lines do not decide from another (calib::FamilyOptions::keep_rivals): setup
// writes the files through each, chooses each one's height (SetupHeight), and keeps the one that
// decodes the most robots there, counting only heights something measures (the patterns' sizes in
// mm judge the scale; docs/setup.md); a tie is refused.
struct SetupRival {
  std::string field;                 // its model
  double score_px = 0.0;             // the line length its camera explains
  double floor_difference_mm = 0.0;  // how far its map of the frame is from the kept camera's
  int robots = 0;  // credited: decoded where its height is measured (internal::CreditedRobots)
};

// The camera's height above the floor and what set it. A view of the floor fixes the focal length
// over the height (f / h), not each: the robots' patterns, at the robots' height and of a known
// size in mm, measure the rest. setup scans heights with the focal length scaled with them (the
// floor's map kept), detects through each, keeps the one decoding the most robots (a tie: the
// lines' own height if it is among them, else the lowest mean pattern residual), then fits the
// camera to the lines and the decoded robots' patches together and takes that fit's height.
struct SetupHeightTry {
  double height_mm = 0.0;
  double focal_px = 0.0;
  int robots = 0;             // decoded through it (DecodedRobots' count)
  double residual_mm2 = 0.0;  // their mean pattern residual E (NaN: none decoded)
};
struct SetupHeight {
  // "given" (--camera-height), "lines" (the robots agree with the lines' height and add little),
  // "robots" (they moved it, or measure it better than the lines), "undetermined" (no robots
  // decoded, or the robots are on the floor: the lines' height kept, whatever it is worth).
  std::string decided_by = "lines";
  double height_mm = 0.0, focal_px = 0.0;
  double sd_mm = 0.0;  // its standard error (NaN: the fit does not determine it)
  int robots = 0;      // decoded through the kept camera
  double lines_height_mm = 0.0, lines_focal_px = 0.0;
  double lines_sd_mm = 0.0;  // the lines' fit's standard error of the height (NaN: undetermined)
  int lines_robots = 0;      // decoded through the lines' camera
  // The fit of the lines and the decoded robots' patches together (patterns: the robots in it; 0:
  // none made): its height and standard error, and whether it was kept ("kept", or why not).
  int patterns = 0;
  double fitted_height_mm = NAN, fitted_sd_mm = NAN;
  std::string fitted;
  std::vector<SetupHeightTry> scan;  // by increasing height
};

// Where the lines match too few marks to fix a camera (a corner and a line): the robots' patterns
// of known size measure the floor's scale -- a camera looking straight down is tried at
// kFloorScales floor scales, log-spaced over [kLeastMmPerPx, kMostMmPerPx], the one decoding the
// most robots kept (colours fitted from the blobs alone first) -- each pair of crossing field lines
// of each model is placed on the line pixels through it (calib::PlaceCrossings), placements that
// put a decoded robot off the field and its run-off (the model's boundary, else 1000 mm) are
// dropped, the best of the rest by line length is fitted to the lines and the decoded robots'
// patches together (principal point at the image centre). Kept only when every decoded robot's
// position is known within a pattern's radius at one standard error (position_sd_mm: the worst
// robot's, along its worst axis, the fit's covariance scaled to the patches' residuals).
struct SetupFewLines {
  bool used = false;
  std::string lines_failure;     // what the lines alone matched
  double floor_mm_per_px = 0.0;  // the scan's kept floor scale
  int robots = 0;                // decoded through it
  // The scan's colours were fitted for patches down to kSmallPatchPx radius, not with the given
  // blob bounds: they decoded more robots (a tie keeps the given).
  bool small_patches = false;
  int placements = 0;         // crossings placed (scoring at least half the best)
  int on_field = 0;           // of them, keeping every decoded robot on the field
  std::string crossing;       // the placement kept: "LINE x LINE" of its model
  double score_px = 0.0;      // its line length explained (CameraScore)
  double runner_up_px = 0.0;  // the best other placement on the field mapping differently (0: none)
  double position_sd_mm = 0.0;  // the stated error of a robot's position
  double limit_mm = 0.0;        // a pattern's radius: the most accepted
};

struct SetupResult {
  // The frames were binned binning x binning (SetupOptions::binning) from frame_size_px: every
  // pixel figure of this result (the calibration fit, mm_per_px, patch sizes, the colour fit's
  // counts) is the binned frames'. The files written are the frames' own: calibration.toml maps
  // their pixels, settings.toml's [frame] binning makes detect bin them alike.
  int binning = 1;
  std::array<int, 2> frame_size_px{};
  calib::Field field;                // the model kept
  std::vector<SetupFieldTry> tried;  // every model tried, best first
  // The cameras the lines did not decide between, the kept one first (empty when the lines
  // decided); robots_decided: the kept one decoded more robots than every other (always, where
  // there are such cameras: a tie is refused, SetupCamera throws).
  std::vector<SetupRival> undecided;
  bool robots_decided = false;
  // No robot decoded through any camera the lines left (the kept one and its rivals, at any
  // height tried), and one of the cameras they decided against narrowly (their runners-up,
  // calib::FamilyCalibration::runners_up, at least 80% of the line) was credited with robots:
  // the robots chose among them all (listed in `undecided`, the lines' best among them).
  bool lines_overruled = false;
  SetupHeight height;
  SetupFewLines few_lines;
  bool from_landmarks = false;
  calib::CalibrationInput calibration_input;
  calib::CalibrationFit calibration_fit;
  std::string calibration_report;  // the automatic calibration's (or the fit's) report
  double mapping_error_mm = 0.0;   // held-out (lines) or cross-validated (landmarks)
  // What mapping_error_mm is, where not the held-out or cross-validated error: "the fit's spread
  // over the field" where the robots set the camera's height (floor_sd_mm, when larger).
  std::string mapping_error_source;
  // The fit with the robots' own uncertainty of the floor it shows inside the field's lines (RMS
  // mm, calib::MappingSdOver; SetupHeight): NaN where that fit was not kept.
  double floor_sd_mm = std::numeric_limits<double>::quiet_NaN();
  // What the held-out estimate resolves (calib::AutoCalibration::held_out_resolution_mm; 0 for
  // landmarks): an error below it is reported as "below" it, and the tolerances take it as the
  // error's bound.
  double mapping_resolution_mm = 0.0;
  double mm_per_px = 0.0;          // on the robots' plane at the image centre
  double smallest_patch_px = 0.0;  // the smallest patch's radius in px there
  vision::AutoThresholdsFit thresholds;
  std::vector<vision::BlobCluster> colour_clusters;  // the blobs' clusters, named or clutter
  // The colour fit kept: "blobs" (vision::FitThresholdsFromBlobs) or "pixels"
  // (vision::FitThresholdsAuto), whichever decodes more robots through the files setup writes:
  // per frame the distinct (pattern, team, ID), a further detection of one counted against it;
  // a tie keeps the blobs. The detector's geometry and codebook judge the colours, not a truth.
  // The blobs' fit is made at the settings' segment_k (vision::BlobThresholdsOptions) and at 2/3
  // and 3/2 of it, each at the settings' standout_delta_e and at 0.7 times it, and the fit
  // decoding the most robots kept (a tie keeps the earlier: the given threshold before the lower,
  // the given scale first): how readily the segmentation joins pixels depends on the patches' size
  // in px, their blur and the colours beside them, and how far a dull patch stands out from the
  // carpet on the light (seed 89: dim green ID patches on a green carpet, Delta E 14-20 from it),
  // which the frame shows and no constant knows. blob_fits: each fit tried and the robots it
  // decoded; robots_by_blobs: the kept one's.
  std::string colour_fit = "blobs";
  double segment_k = 0.0;
  double standout_delta_e = 0.0;
  struct BlobFitTry {
    double standout_delta_e = 0.0, segment_k = 0.0;
    int robots = 0;
  };
  std::vector<BlobFitTry> blob_fits;
  int robots_by_blobs = 0;
  int robots_by_pixels = 0;
  // The frames normalised for the blobs' fits (vision::NormaliseFrame) and the options they were
  // normalised with: made by the first fit and shared by every later fit of one setup and every
  // copy of this result -- a rival's, a height's -- since they depend on the frames and two
  // colour options, never on the camera. Written to no file; SetupCamera's result drops them.
  struct NormalisedFrames {
    std::vector<const camera::Image*> frames;
    int light_cell_px = 0;
    double max_light_gain = 0.0;
    std::vector<vision::NormalisedFrame> normalised;
  };
  std::shared_ptr<const NormalisedFrames> normalised_frames;
  detect::DetectorOptions tolerances;  // the settings' options with the chosen tolerances
  // The files to write into the output folder (name, text): calibration.toml, thresholds.toml,
  // settings.toml, setup.toml.
  std::vector<std::pair<std::string, std::string>> files;
  double seconds = 0.0;
};

// Sets up a camera from its frames (names for messages). InputError for bad input or frames
// that do not decide the camera, naming the frame, the numbers and what is expected.
SetupResult SetupCamera(const std::vector<const camera::Image*>& frames,
                        const std::vector<std::string>& names, const SetupOptions& options);

// The tolerances for a floor scale (mm per px), a mapping error (mm) and the smallest patch's
// radius (px), starting from `base` (header comment).
detect::DetectorOptions SetupTolerances(const detect::DetectorOptions& base, double mm_per_px,
                                        double mapping_error_mm, double smallest_patch_px);

// The blob area range (px) the colour fit looks for, from the smallest and largest patch radius in
// px on the robots' plane: [max(3, 0.2 pi r_min^2), 3 pi r_max^2] -- a blob may be a patch's
// core eaten by blur or a third of it hidden, and not three times its size -- and its narrowest
// spread at least 0.3 r_min (a patch's core has about 0.5 r).
void SetupBlobAreas(double smallest_patch_px, double largest_patch_px,
                    vision::BlobThresholdsOptions* options);

// The report for people: the model kept (and by how much), the mapping error, the colour
// classes with pixel counts and separability, the tolerances.
std::string SetupReportText(const SetupResult& result);

// The files a setup folder's setup.toml names, as paths (relative ones resolved against the
// folder). InputError "file:line: ...; expected ..." for a missing file or key.
struct SetupFiles {
  std::string calibration, thresholds, settings;
};
SetupFiles LoadSetupFiles(const std::string& dir);

// "name x y" lines of a field model's landmarks, for `patlab setup --list-landmarks`.
std::string LandmarkListText(const calib::Field& field);

// Parses "NAME=X,Y" (`--landmark`); InputError naming the flag.
SetupLandmark ParseLandmark(const std::string& text);

// Sets one colour fit option from "NAME=VALUE" (`--colour-option`, vision::
// SetBlobThresholdsOption) and checks the options' ranges; InputError naming the flag.
void ParseColourOption(const std::string& text, vision::BlobThresholdsOptions* options);

}  // namespace patlab::formats
