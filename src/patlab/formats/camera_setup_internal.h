// What the files of camera_setup*.cpp share (camera_setup.h): the files written
// through one camera and the robots the detector decodes through them.
#pragma once

#include <string>
#include <vector>

#include "patlab/calib/auto_calibrate.h"
#include "patlab/calib/calibrate.h"
#include "patlab/camera/camera.h"
#include "patlab/camera/image.h"
#include "patlab/detect/detector.h"
#include "patlab/formats/camera_setup.h"
#include "patlab/vision/color_lut.h"

namespace patlab::formats::internal {

// Everything after the calibration: the tolerances of r's camera, the colour classes (fitted and
// chosen by the robots they decode when `fit_colours`; else r's kept), the files.
void FinishSetup(const std::vector<const camera::Image*>& frames,
                 const std::vector<std::string>& names, const detect::DetectorConfig& config,
                 const SetupOptions& options, SetupResult& r, bool fit_colours = true);

// The colour classes (camera_setup_colours.cpp): FitColours fits the blobs' classes at the
// settings' segment_k and standout_delta_e into r->thresholds and r->colour_clusters
// (vision::FitThresholdsFromBlobs; the blob area range from r's floor scale, SetupBlobAreas, when
// r->mm_per_px > 0, else the options' own: no camera yet); ChooseColourFit, once r's calibration
// and settings are written, keeps of those, the blobs' fits at the neighbouring segmentation
// scales and the lower stand-out threshold, and the pixel clustering the one that decodes the
// most robots (SetupResult::colour_fit).
void FitColours(const std::vector<const camera::Image*>& frames,
                const detect::DetectorConfig& config, const SetupOptions& o, SetupResult* r);
void ChooseColourFit(const std::vector<const camera::Image*>& frames,
                     const detect::DetectorConfig& config, const SetupOptions& o,
                     const std::string& calibration_text, const std::string& settings_text,
                     SetupResult* r);

// The report's "colour fit:" line: the fit kept, and the robots each fit tried decoded.
std::string ColourFitText(const SetupResult& r);

// The robots the detector decodes through r's files: DecodedRobots' count (per frame the distinct
// pattern, team and ID, less one for every further detection of one), the decoded robots' mean
// pattern residual E (mm^2; NaN when none) and, per decoded robot, its patches' pixel centroids
// as a pattern observation at `robot_height_mm` (for a fit of the camera to them).
struct Decoded {
  int robots = 0;
  double residual_mm2 = 0.0;
  std::vector<calib::PatternObservation> patterns;
};
// The count alone through given thresholds, calibration and settings text; with `decoded`, the rest
// too (`config` gives the patterns).
int DecodedRobots(const std::vector<const camera::Image*>& frames,
                  const vision::Thresholds& thresholds, const camera::Calibration& calibration,
                  const std::string& settings_text, const detect::DetectorConfig* config = nullptr,
                  double robot_height_mm = 0.0, Decoded* decoded = nullptr);
Decoded DecodeThroughFiles(const std::vector<const camera::Image*>& frames,
                           const detect::DetectorConfig& config, const SetupResult& r,
                           double robot_height_mm);

// The camera's height (SetupHeight): given, or, from the lines' camera in r, chosen by the robots
// where the lines leave it open; r's calibration, tolerances, colours and files follow it.
void ChooseHeight(const std::vector<const camera::Image*>& frames,
                  const std::vector<std::string>& names, const detect::DetectorConfig& config,
                  const SetupOptions& options, SetupResult& r);

// The robots a camera of several the lines leave open (SetupRival) is credited with, once its
// height is chosen (ChooseHeight): those decoded at its height where something measures that
// height -- it was given and its lines measure f / h (so the focal length); the fit of its lines
// and robots together measures it; or, that fit not kept, its lines measure it (the robots through
// the lines' camera); or, nothing measuring it, no height of the scan decodes more than the lines'
// camera (the count then tells the floor's scale, not the height) -- and none otherwise, or where
// its lines and that fit (kept or not) each measure it and disagree by more than kHeightAgreement
// combined standard errors. A wrong model's camera at a height that makes its floor's scale the
// robots' decodes every robot too (fresh seed 15: ssl-2018's lines measure 5.95 +- 0.44 m, its
// robots choose 1.01 m; seed 1: ssl-2014's lines 5.02 +- 0.23 m, the fit with the robots 3.34 +-
// 0.25 m), as does one at a height nothing measures (seed 58: 11 m, the fit with the robots
// unphysical): the robots decide between cameras only where a height is measured.
int CreditedRobots(const SetupHeight& h);
inline constexpr double kHeightAgreement = 3.0;

// The most robots decoded through a camera ChooseHeight scaled: the lines' (at a given height too)
// and the scan's.
int MostRobotsTried(const SetupHeight& h);

// A height in metres for the report: "3.43 m".
std::string Metres(double mm);

// The camera's height above the floor.
inline double HeightOf(const camera::PinholeCamera& c) {
  return (-c.rotation.transpose() * c.translation_mm).z();
}

// r's calibration fitted again from `start` to r's lines and `patterns` (decoded robots' patches,
// each pose free) together, the focal length free, with the covariance. InputError when it fails.
calib::CalibrationFit FitWithRobots(const SetupResult& r, const camera::PinholeCamera& start,
                                    const std::vector<calib::PatternObservation>& patterns);

// The fit's own uncertainty of the floor it shows inside the field's lines (calib::MappingSdOver
// over r's model, every 10th pixel of a frame width x height): NaN where the fit has no covariance.
double FloorSd(const SetupResult& r, int width_px, int height_px);

// The height's standard error of a fit with the robots' patches, scaled from the fit's residual
// variance to the patches' own (they measure the height); NaN when the fit does not determine it.
double RobotsHeightSd(const calib::CalibrationFit& fit, double robot_height_mm);

// Where the lines fit one camera only (no rival), only with its focal length at the fit's lower
// bound (calib::kMinFocalWidths image widths: they pushed it as short as it goes), and no robot
// decodes through it at any height (`height`, ChooseHeight's), the text saying so, for
// SetupFromRobots; "" otherwise. Few-lines view 5: ssl-2015's lines camera at 156 px decoded no
// robot from 1.55 to 8.31 m, and setup wrote it. At the bound alone the lines still fix f / h:
// rendered seeds 16, 46, 63 and 104 have their lines' camera there, and the robots choose its
// height.
std::string FocalAtItsBound(const calib::FamilyCalibration& family,
                            const std::vector<calib::Field>& fields, const std::string& name,
                            int width_px, const SetupHeight& height);

// Where the lines fit one camera only (no rival), nothing measures its height (CreditedRobots 0)
// and the robots decode the most only through the height scan's highest camera, more than through
// the lines' own: the text saying so, for SetupFromRobots; "" otherwise. There the robots' plane
// is nearly at the floor's scale, and robots decoding ever more the higher the camera ask for a
// plane no higher than the floor: the lines' map of the floor is larger than the robots' patterns
// allow at any camera's height. Fresh rendered seed 481 (ssl-2018 named): one touch line, and the
// rims of the robots' patches taken for a defence area's corner; the lines' camera, 2.79 m up, 3 m
// off, decoded 2 robots, the scan's 11.33 m camera 10, and setup wrote it: 10 false IDs.
std::string RobotsOnlyAtTheHighest(const calib::FamilyCalibration& family,
                                   const std::vector<calib::Field>& fields, const std::string& name,
                                   const SetupHeight& height);

// One camera of the lines (the kept one, a rival or a runner-up) as r's calibration.
void UseCalibration(const calib::AutoCalibration& a, const calib::Field& field, SetupResult* r);

// The camera setup keeps of the lines' (camera_setup_rivals.cpp): each of the kept camera and its
// rivals gets its files and height (ChooseHeight) and is credited with robots (CreditedRobots).
// Where no robot decodes through any of them at any height tried, the runners-up are weighed too
// (family's, their held-out error measured then), and kept only when one is credited with robots
// (SetupResult::lines_overruled). One camera left: it is returned, unless its focal length is at
// its bound with no robot decoding (FocalAtItsBound) or the robots decode the most only through
// the height scan's highest camera (RobotsOnlyAtTheHighest): its text in *at_bound, and an empty
// result.
// Several: the one credited with the most robots, all of them in SetupResult::undecided; a tie is
// refused (InputError naming each).
SetupResult WeighCameras(const std::vector<const camera::Image*>& frames,
                         const std::vector<std::string>& names,
                         const detect::DetectorConfig& config, const SetupOptions& options,
                         calib::FamilyCalibration& family, std::string* at_bound);

// The report's lines on the cameras weighed by their robots (SetupResult::undecided).
std::string UndecidedText(const SetupResult& r);

// Where the line pixels match too few marks to fix a camera (calib::AutoCalibrateFamily's
// InputError `lines_failure`): the robots' patterns measure the floor's scale and the lines'
// crossing is placed on the field's (camera_setup_place.cpp, SetupFewLines). InputError naming
// the numbers when the robots do not fix the camera either.
SetupResult SetupFromRobots(const std::vector<const camera::Image*>& frames,
                            const std::vector<std::string>& names,
                            const detect::DetectorConfig& config, const SetupOptions& options,
                            const std::vector<calib::LinePixel>& pixels,
                            const std::string& lines_failure);

// The report's lines on what decided where the lines did not fix the camera (SetupFewLines).
std::string FewLinesText(const SetupFewLines& f);

// The report's line on the camera's height where the robots placed the field: given, or the fit
// of the lines and the robots' patches together.
std::string FewLinesHeightText(const SetupHeight& h);

// Whether an automatic calibration's failure says its lines matched too few marks.
bool MatchedTooFewMarks(const std::string& failure);

// The report's lines on the camera's height: the height kept, what decided it, with the numbers.
std::string HeightText(const SetupHeight& h);

}  // namespace patlab::formats::internal
