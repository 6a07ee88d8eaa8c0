// The automatic field calibration: the camera of a frame from the centre points of its white
// field lines (vision/field_lines.h finds them) and the field's model (field.h), with nobody
// clicking. Image-free: pixels in, calibration out.
//
//  1. Hypotheses. The field's lines are parallel to two axes; the frame's dominant line
//     direction (modulo 90 deg) gives the image's rotation against them. Line pixels running
//     along either image axis are histogrammed across it; the histograms' peaks are lines. A
//     camera looking nearly straight down maps the floor to the image by a similarity (scale s
//     px/mm, one of the four quarter-turns with the image's mirror, the floor point under the
//     image centre); a pair of peaks matched to a pair of field lines along one axis gives s and
//     one coordinate, one peak matched to one field line along the other axis the second (and
//     a log-spaced sweep of s when an axis shows fewer than two lines). Views centred on the
//     field's middle along an axis whose peaks matched lines are scored apart and replace the
//     others when the best of them, refined, explains 1.5 times more (a narrow view between the
//     touch lines: its arcs' tangent peaks match only the touch lines, out of view).
//  2. Scoring. Each hypothesis projects points along the field's painted marks (field_marks.h)
//     into the image and is scored by the line length it explains (marks within a few px of a
//     line pixel, by a distance transform of the line pixels) minus half the length it puts
//     where there is no line. The six best distinct ones are refined by coordinate descent on
//     the same score: first as similarities (scale, rotation, position, a radial distortion),
//     then as pinhole cameras (tilts orbiting the floor point at the image centre, position,
//     height, k1).
//  3. Symmetry. A field that is the same rotated by 180 deg about its centre (mirrored about
//     both axes) gives two equivalent cameras for every view; the one whose image centre looks
//     at x >= 0 (at the pos half; on the halfway line, at y >= 0) is kept, and the report says
//     whether the search's camera was turned to it.
//  4. Fit. From the best cameras in turn, while they score at least 80% of the first, until two
//     have fitted (one whose pixels match too few marks to fix a camera fails at once and takes
//     no place: a T of two lines fits many places of a field), each line pixel is given to the
//     painted mark nearest its back-projection on the floor (within a gate of 12, then 5, then 3
//     px, and within 25 deg of its direction), and calib::FitCamera fits every free parameter to
//     the line and circle observations with a Huber loss, three rounds; a fit that leaves the
//     camera model's range (the floor alone hardly separates focal length from height) is redone
//     with the focal length held. A fitted camera whose horizon crosses the image is no fit
//     (a camera over the field sees the floor in every pixel). The better final score wins; a
//     different camera (not the equivalent one) scoring 90% of it makes the frame ambiguous.
//  5. Held-out error. The pixels of every observation, in runs of 8 along it, are split into
//     two folds; the camera fitted to one fold back-projects the other's pixels, and their
//     distance on the floor to their mark, in mm, is the held-out mapping error.
// A frame whose lines do not decide the camera (too few line pixels, no hypothesis that
// explains them, a second, non-equivalent camera explaining them nearly as well, observations
// along one direction only) is an InputError naming what was found.
#pragma once

#include <string>
#include <vector>

#include "patlab/calib/calibrate.h"
#include "patlab/calib/field.h"
#include "patlab/core/geometry.h"

namespace patlab::calib {

// A point on the centre of a painted line, in pixels, with the line's direction there.
struct LinePixel {
  Vec2 pixel = Vec2::Zero();
  Vec2 direction = Vec2(1, 0);  // unit
  double strength = 0.0;        // the ridge's contrast (8-bit levels), for ranking
};

struct AutoOptions {
  double huber_px = 1.0;     // the fit's Huber scale, > 0
  int max_fit_pixels = 300;  // the line pixels the fit uses at most (evenly along each mark)
  // Each fit stops once the camera's image of the floor has settled to a hundredth of a pixel
  // over 10 iterations (FitOptions::settle_px; 0: off): it would crawl along the valley of focal
  // length against height to its last iteration otherwise.
  double settle_px = 0.01;
  // Held fixed in the fit (calibrate.h FitOptions::fixed).
  std::vector<FitParameter> fixed = {FitParameter::kAspect, FitParameter::kK2};
  // The camera's height above the floor, if measured: separates focal length from height,
  // which a view of the floor alone barely does (calibrate.h FitOptions::camera_height_mm).
  std::optional<double> camera_height_mm;
};

struct AutoCalibration {
  CalibrationInput input;        // the observations found (lines and circles), for the file
  CalibrationFit fit;            // the fit on every observation
  int line_pixels = 0;           // found
  int assigned_pixels = 0;       // within the final gate of a mark
  int hypotheses = 0;            // scored
  double score_px = 0.0;         // the best hypothesis' explained length minus penalty (px)
  double runner_up_px = 0.0;     // the best non-equivalent other one's
  bool point_symmetric = false;  // the field is the same rotated by 180 deg
  bool turned = false;           // the search's camera was turned by 180 deg to the kept one
  // The held-out pixels' floor distances to their marks (mm): RMS and worst; they hold the line
  // finder's noise as well as the camera's error. Their means over each run of 8 along a mark
  // average the noise away: held_out_mapping_mm = sqrt(mean of the squared run means - the
  // noise's share of them), the estimated RMS floor error of the camera. (The runs measure one
  // axis of the error, across the line: 1 / sqrt 2 of the 2-D error; a fold's camera is fitted to
  // half the pixels: sqrt 2 times the whole fit's error; the two cancel.) held_out_noise_mm is
  // the within-run spread (the finder's noise).
  // held_out_resolution_mm: what the estimate can resolve, twice the RMS noise of a run's mean
  // (held_out_noise_mm / sqrt 8 for full runs): an estimate below it says only that the camera's
  // error is below it too (the report says so).
  double held_out_rms_mm = 0.0, held_out_worst_mm = 0.0;
  double held_out_mapping_mm = 0.0, held_out_noise_mm = 0.0, held_out_resolution_mm = 0.0;
  int held_out_count = 0;
  double seconds = 0.0;
  std::vector<std::string> notes;
};

// The calibration of a width x height frame from its line pixels. `source` names the frame in
// the input and messages. InputError when the lines do not decide the camera.
AutoCalibration AutoCalibrate(const std::vector<LinePixel>& pixels, int width_px, int height_px,
                              const std::string& source, const Field& field,
                              const AutoOptions& options = {});

// A family of field models (`patlab setup --field ssl`): every model's search (steps 1-3) is a
// cheap screen, its best camera's score ranking the models; the full fit (steps 4-5) is given
// in that order to the first min_fitted models that search found a camera for, then to every
// model whose screen reaches screen_ratio of the best fitted score. (A fitted camera explains
// about as much line as its search's or more: a model screened below that cannot win.) Models
// whose painted marks are the same as an earlier one's share its result. The fitted model of
// the highest score is kept. Before the screen, each view one model's search found is scored
// against every other model's marks; one that explains a model's marks better than the best its
// own search found becomes that model's best view (screen_view_of names its search): models whose
// lines in view are alike find their common camera from different hypotheses.
//
// `lenders` are searched only to lend their views to `fields`, never fitted as themselves, kept
// or reported in `tries`: a model named alone (`patlab setup --field ssl-2015`) borrows from the
// rest of its family. Besides the best view lent as above, each lender's views, scored against
// each model's marks, are one more search of that model, screened and fitted with the models'
// own; a camera fitted from them is that model's (its try, the kept camera, the rivals).
//
// Where the lines do not decide -- a second camera, of the same model or another, explains more
// than 90% of the kept one's line length yet maps the frame differently (a view of a T of two
// lines and a parallel one fits every model whose lines are alike there, each at its own scale)
// -- AutoCalibrate refuses the frame. With keep_rivals those cameras are returned instead, best
// first, for the caller to decide by evidence the lines do not hold (the robots, setup).
//
// With runner_up_ratio > 0 the cameras the lines decide against but not by much are returned too
// (runners_up): fitted cameras mapping the frame differently from the kept one and from every
// rival, explaining at least runner_up_ratio of the kept one's line, best first, at most
// max_rivals, their held-out error not measured (MeasureHeldOut). A caller whose own evidence
// contradicts the kept camera outright (setup: no robot decodes through it) weighs them.
struct FamilyOptions {
  double screen_ratio = 0.8;  // in (0, 1]
  int min_fitted = 2;         // >= 1: a runner-up to compare with
  bool keep_rivals = false;
  int max_rivals = 3;            // >= 0: the best this many rivals kept
  double runner_up_ratio = 0.0;  // in [0, 1]: 0 keeps no runner-up
};
// held_out_mapping_mm is measured for the cameras kept only, the kept one and its rivals (two
// more fits each): the other models' tries report NaN.
struct FamilyTry {
  std::string field;                 // the model's name
  double screen_px = 0.0;            // its search's best score (NaN: the search failed)
  std::string screen_view_of;        // the model whose search found that view ("": its own)
  bool fitted = false;               // given the full fit
  double score_px = 0.0;             // the full fit's score (NaN: not fitted or failed)
  double held_out_mapping_mm = 0.0;  // the kept model's full fit's (NaN for the others)
  std::string same_as;               // the earlier model of the same marks whose result it shares
  std::string failure;               // why it failed or was not fitted ("" when fitted)
};
struct FamilyRival {
  int model = -1;                    // index in `fields`
  double floor_difference_mm = 0.0;  // from the kept camera's map (FloorDifferenceMm)
  AutoCalibration calibration;
};
struct FamilyCalibration {
  int kept = -1;                        // index of the kept model in `fields`
  AutoCalibration calibration;          // the kept model's
  std::vector<FamilyTry> tries;         // one per model, in the order of `fields`
  std::vector<FamilyRival> rivals;      // keep_rivals: the cameras the lines do not decide from it
  std::vector<FamilyRival> runners_up;  // runner_up_ratio > 0: those they decide against narrowly
  double seconds = 0.0;
};
// InputError (the best-screened model's failure) when no model fits.
FamilyCalibration AutoCalibrateFamily(const std::vector<LinePixel>& pixels, int width_px,
                                      int height_px, const std::string& source,
                                      const std::vector<Field>& fields,
                                      const AutoOptions& options = {},
                                      const FamilyOptions& family = {},
                                      const std::vector<Field>& lenders = {});

// The held-out error (held_out_*) of a camera returned without it (FamilyCalibration's
// runners_up): each of two folds of its observations fitted from that camera, measured on the
// other. Two fits.
void MeasureHeldOut(AutoCalibration& a);

// Where the lines match too few marks to fix a camera (a corner and a line: every corner of a
// field fits them, at any scale) but the floor's scale is known otherwise -- `floor_camera`, a
// camera looking straight down whose map of the floor has the right scale, its position and
// turn about the vertical free (setup measures it by the robots' patterns, of known size) --
// each pair of crossing field lines of each model is placed on the line pixels
// (auto_calibrate_place.cpp): the pixels put on the floor through floor_camera, their dominant
// direction (modulo 90 deg) turned onto the field's axes, the strongest line along each axis
// found by a histogram across it, their crossing put on the model's crossing in each of the four
// quarter turns. Each placement is floor_camera moved there, scored like the search's cameras
// (CameraScore), with the line pixels assigned to its model's marks (within gate_px). Best first;
// empty when the pixels show no two crossing lines.
struct Placement {
  int model = -1;                // index in `fields`
  std::string crossing;          // "LINE x LINE"
  camera::PinholeCamera camera;  // floor_camera moved onto the crossing
  double score_px = 0.0;         // CameraScore's
  CalibrationInput input;        // the line pixels assigned to the model's marks through it
};
std::vector<Placement> PlaceCrossings(const std::vector<LinePixel>& pixels, int width_px,
                                      int height_px, const std::string& source,
                                      const std::vector<Field>& fields,
                                      const camera::PinholeCamera& floor_camera,
                                      double gate_px = 12.0, const AutoOptions& options = {});

// The line pixels assigned through `camera` to the nearest painted mark of `field` within gate_px
// and of their direction (the automatic calibration's assignment), as observations of `base`
// (its lines and circles replaced). Marks with too few pixels are left out.
CalibrationInput AssignToMarks(const camera::PinholeCamera& camera,
                               const std::vector<LinePixel>& pixels, const Field& field,
                               double gate_px, int max_pixels, const CalibrationInput& base);

// The distance (mm) from the back-projection of `pixel` through `camera` on the floor to the
// observation's line or circle; NaN when the pixel does not map onto the floor.
double FloorDistanceMm(const camera::PinholeCamera& camera, const Vec2& pixel,
                       const LineObservation* line, const CircleObservation* circle);

// The held-out mapping error for people: "0.83 mm", or, below its resolution, "below 0.42 mm
// (the line finder's resolution; estimate 0 mm)".
std::string HeldOutText(const AutoCalibration& a);

// The report: what was found, the symmetry, the held-out error, then FitReportText.
std::string AutoReportText(const AutoCalibration& a);

}  // namespace patlab::calib
