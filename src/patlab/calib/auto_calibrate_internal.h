// Pieces of the automatic field calibration shared by auto_calibrate.cpp (the search) and
// auto_calibrate_fit.cpp (the assignment, the fit and the held-out error).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "patlab/calib/auto_calibrate.h"
#include "patlab/calib/field_marks.h"

namespace patlab::calib::internal {

// A camera looking straight down, as a map floor -> image: the image-centred point
// q = Rot(psi) s A_k (p - centre_mm), distorted radially q (1 + kd |q|^2 / width^2).
// A_0 = [[1, 0], [0, -1]], A_1 = [[0, 1], [1, 0]], A_2 = -A_0, A_3 = -A_1.
struct NadirView {
  int k = 0;
  double psi = 0.0;
  double scale = 1.0;  // px per mm
  Vec2 centre_mm = Vec2::Zero();
  double kd = 0.0;
};

// The view as a pinhole camera of focal length `width` px.
camera::PinholeCamera PinholeOf(const NadirView& v, int width, int height);

// The same camera turned by 180 deg about the field's vertical axis (x, y -> -x, -y).
camera::PinholeCamera Turned(const camera::PinholeCamera& camera);

// The best nadir views of the line pixels, best first, with their scores (px); throws
// InputError when none explains them.
struct ScoredView {
  NadirView view;
  double score = 0.0;
  camera::PinholeCamera camera;  // the view refined as a pinhole camera (tilt, distortion)
};
std::vector<ScoredView> SearchViews(const std::vector<LinePixel>& pixels, int width, int height,
                                    const FieldMarks& marks, bool symmetric, int* hypotheses);

// The score (px) of a camera: the painted length it explains minus half the length it puts
// where no line pixel is (SearchViews' measure, for comparing the final cameras).
class LineDistance {
 public:
  LineDistance(const std::vector<LinePixel>& pixels, int width, int height);
  double At(const Vec2& q) const;  // px to the nearest line pixel; large outside the image
  int width() const { return w_; }
  int height() const { return h_; }

 private:
  int w_, h_;
  std::vector<float> d_;
};
double CameraScore(const camera::PinholeCamera& camera, const FieldMarks& marks,
                   const LineDistance& distance, double tau_px = 6.0);
// The same through a sampler of the marks, for a run of cameras of nearly one scale.
double CameraScore(const camera::PinholeCamera& camera, MarkSampler& marks,
                   const LineDistance& distance, double tau_px = 6.0);

bool PointSymmetric(const Field& field);

// Steps 1-3 of one field model (the search), and steps 4-5 from them (the fit): AutoCalibrate
// is the two in turn; AutoCalibrateFamily screens every model by its search's best score and
// fits only the best few.
struct Searched {
  FieldMarks marks;
  bool point_symmetric = false;
  int hypotheses = 0;
  std::vector<ScoredView> views;  // best first; views.front().score screens the model
};
Searched SearchField(const std::vector<LinePixel>& pixels, int width_px, int height_px,
                     const std::string& source, const Field& field, const AutoOptions& options);
// A second camera that maps the frame differently yet explains nearly as much line makes the
// frame undecided, unless a piece of line only the first explains decides (OwnLinesDecide): an
// InputError, or, with `undecided` given, that camera's calibration appended to it (the caller
// decides by other evidence). The held-out error is not measured (NaN): MeasureHeldOut does it
// for the cameras the caller keeps (two more fits each; a family fits many it drops).
AutoCalibration FitSearched(const Searched& searched, const std::vector<LinePixel>& pixels,
                            int width_px, int height_px, const std::string& source,
                            const Field& field, const AutoOptions& options,
                            std::vector<AutoCalibration>* undecided = nullptr);

// Step 5: the held-out error of `a`'s camera into its held_out_* fields, each of two folds of
// its observations fitted from that camera and measured on the other.
void MeasureHeldOut(AutoCalibration& a);

// The largest floor distance (mm) between two cameras' maps over a 3 x 3 grid of the frame, the
// second also turned by 180 deg when the field is point-symmetric (equivalents are equal).
double FloorDifferenceMm(const camera::PinholeCamera& first, const camera::PinholeCamera& second,
                         bool point_symmetric, int width_px, int height_px);

// Whether two cameras map the frame alike: FloorDifferenceMm at most 20 px at the first's floor
// scale at the image centre; `differ_mm` receives FloorDifferenceMm.
bool SameMap(const camera::PinholeCamera& first, const camera::PinholeCamera& second,
             bool point_symmetric, int width_px, int height_px, double* differ_mm);

// Whether the lines do not decide between two fitted cameras: the second explains more than
// kUndecidedRatio of the first's line length and maps the frame differently (not SameMap);
// `differ_mm` receives FloorDifferenceMm then.
constexpr double kUndecidedRatio = 0.9;
bool Undecided(const camera::PinholeCamera& best, double best_score,
               const camera::PinholeCamera& second, double second_score, bool point_symmetric,
               int width_px, int height_px, double* differ_mm);

// The line pixels one camera's marks explain and another's leave unexplained: within kOwnPx of
// the first's projected marks and more than kOtherPx from the second's (`first`), and the same
// the other way round (`second`). Two cameras the lines do not decide by length still differ
// when one explains a piece of painted line the other leaves bare and the other explains
// nothing of its own (fresh rendered seed 20: a centre view whose corner shows 30 px of touch
// line, 3.0 m from the mid-line, that a quarter-turned or Division A camera leaves bare).
struct ExclusiveLines {
  int first = 0, second = 0;
};
constexpr double kOwnPx = 2.5, kOtherPx = 6.0;
ExclusiveLines ExclusiveLinePixels(const camera::PinholeCamera& first,
                                   const FieldMarks& first_marks,
                                   const camera::PinholeCamera& second,
                                   const FieldMarks& second_marks,
                                   const std::vector<LinePixel>& pixels, int width_px,
                                   int height_px);
// Whether such pixels decide for the first camera: at least kDecidingPixels of its own and at
// most a quarter as many of the second's.
constexpr int kDecidingPixels = 24;
bool OwnLinesDecide(const ExclusiveLines& e);

// The first pixel on the image's border (every kHorizonStepPx, the corners included) whose ray
// does not meet the floor in front of the camera, or nullopt when every one does. A camera over
// the field sees the floor in every pixel; one whose horizon crosses the image lies near the
// floor looking along it, a fit run off from an overhead start (fresh rendered seed 196: 42 mm
// up, tilted 86 deg, its marks piled near the horizon explained 2161 px of line against the
// true camera's 1666). Inside the image the horizon, a straight line before distortion, crosses
// the border wherever it crosses the image, so the border decides.
constexpr double kHorizonStepPx = 4.0;
std::optional<Vec2> AboveHorizon(const camera::PinholeCamera& camera, int width_px, int height_px);

// The RMS distance (px) of pixels from their best straight line (total least squares): how far
// an arc's pixels bend in the image.
double BendPx(const std::vector<Vec2>& px);

// The calibration input every automatic fit starts from: the frame (`source`, its size) and the
// options' held parameters, Huber scale and camera height; FitCamera's own cross-validation off
// (the automatic calibration measures its held-out error on line pixels).
CalibrationInput BaseInput(const std::string& source, int width_px, int height_px,
                           const AutoOptions& options);

}  // namespace patlab::calib::internal
