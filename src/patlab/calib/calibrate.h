// `patlab calibrate`: fits the pinhole camera of camera/camera.h (fx, fy, cx, cy, radial k1, k2,
// and the pose R, t with X_camera = R X_world + t) to what a user can measure in one image:
//  - points: a pixel and the world point it shows (x, y on the floor, at a plane height);
//  - lines: pixels anywhere on a known straight field line (one free position per pixel);
//  - circles: pixels anywhere on a known circle or arc (one free angle per pixel);
//  - patterns: the patch centres of a pattern of known layout lying at a known height (a robot
//    top, a pattern sheet), whose pose on its plane is unknown (three free numbers per pattern).
// Every residual is a reprojection error in pixels, minimised by Ceres Solver (Levenberg-
// Marquardt, dense Schur; optionally a Huber loss). The start comes from the known points
// (a plane homography, Zhang's focal-length constraints, docs/calibrate.md), so at least four of
// them on one plane, not all on a line, are needed. The report gives the RMS and worst residual in
// px and, back-projected with the fitted camera, in mm on each plane height, and each fitted
// parameter's standard error from the fit's covariance.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "patlab/calib/field.h"
#include "patlab/camera/camera.h"
#include "patlab/core/error.h"
#include "patlab/core/geometry.h"
#include "patlab/core/pattern.h"

namespace patlab::calib {

struct PointObservation {
  std::string name;  // the field point's name, or "" for a point given by coordinates
  Vec2 pixel = Vec2::Zero();
  Vec2 world_mm = Vec2::Zero();
  double height_mm = 0.0;
  FileLoc loc;
};

struct LineObservation {
  std::string name;
  Vec2 from_mm = Vec2::Zero(), to_mm = Vec2::Zero();
  double height_mm = 0.0;
  std::vector<Vec2> pixels;
  FileLoc loc;
};

struct CircleObservation {
  std::string name;
  Vec2 centre_mm = Vec2::Zero();
  double radius_mm = 0.0;
  double height_mm = 0.0;
  std::vector<Vec2> pixels;
  FileLoc loc;
};

struct PatternObservation {
  std::string name;  // the pattern's name
  Pattern pattern;
  double height_mm = 0.0;
  std::vector<std::optional<Vec2>> pixels;  // one per patch, in pattern order; nullopt = unseen
  FileLoc loc;
};

// The parameters a fit may hold fixed at their starting values.
enum class FitParameter { kFocal, kAspect, kPrincipalPoint, kK1, kK2 };
inline constexpr EnumNames<FitParameter, 5> kFitParameterNames{{{
    {FitParameter::kFocal, "focal"},
    {FitParameter::kAspect, "aspect"},
    {FitParameter::kPrincipalPoint, "principal_point"},
    {FitParameter::kK1, "k1"},
    {FitParameter::kK2, "k2"},
}}};

inline constexpr int kSettleIterations = 10;  // FitOptions::settle_px's window

struct FitOptions {
  // Held fixed (at the start value): by default the pixel aspect (fy = fx) and k2, which one
  // view of a nearly planar scene rarely determines; the principal point is fitted.
  std::vector<FitParameter> fixed = {FitParameter::kAspect, FitParameter::kK2};
  // Start values; unset ones come from the data (focal) or the image centre (principal point).
  std::optional<double> focal_px;
  std::optional<Vec2> principal_point_px;
  double k1 = 0.0, k2 = 0.0;
  double huber_px = 0.0;  // > 0: Huber loss with this scale (px); 0: plain least squares
  // The camera's measured height above the floor (mm) and its uncertainty: a prior that
  // separates the focal length from the distance when every observation is on one plane.
  std::optional<double> camera_height_mm;
  double camera_height_sd_mm = 10.0;
  int max_iterations = 200;
  // > 0: the fit also stops once the camera's image of the floor (z = 0) has settled: over
  // kSettleIterations successful iterations no floor point seen at a 5 x 5 grid of the start
  // camera's image moved by more than settle_px. Lines on the floor alone leave a valley of focal
  // length against height along which that image hardly changes, and the solver crawls along
  // it, each step lowering the cost by a few parts in 10^7, to max_iterations. 0: Ceres' own
  // tolerances alone.
  double settle_px = 0.0;
  // Folds of the cross-validated mapping error (CalibrationFit::heldout_rms_mm): every k-th
  // point, line pixel and circle pixel is held out in turn, the camera refitted without it (from
  // the full fit) and its back-projection measured against its target. More folds: each refit
  // closer to the full fit's data, more time (one refit each). 0: not computed.
  int holdout_folds = 5;
  // A start camera of the caller's own (the automatic field calibration's, auto_calibrate.h):
  // when set, the fit starts from it alone and needs no known points.
  std::optional<camera::PinholeCamera> start_camera;
  // Whether the fit's covariance (and so the standard errors and the mapping uncertainty) is
  // computed: a dense SVD of the whole Jacobian, most of a line fit's time. Off for fits whose
  // camera alone is used (the automatic calibration's intermediate gates and held-out folds):
  // their covariance, standard errors and mapping uncertainty are NaN.
  bool covariance = true;
};

struct CalibrationInput {
  std::string source;
  int image_width_px = 0, image_height_px = 0;
  std::vector<PointObservation> points;
  std::vector<LineObservation> lines;
  std::vector<CircleObservation> circles;
  std::vector<PatternObservation> patterns;
  FitOptions options;
  // Written to the calibration file's [heights] table: default_mm and class name -> mm.
  double default_height_mm = 0.0;
  std::map<std::string, double> class_height_mm;
  FileLoc loc;  // the file, for whole-file messages
};

// One observation's residual after the fit.
struct ObservationResidual {
  std::string kind;  // "point", "line", "circle", "pattern"
  std::string name;
  int index = 0;  // pixel index within the observation (0 for points)
  FileLoc loc;
  double height_mm = 0.0;
  Vec2 pixel = Vec2::Zero();  // the observed pixel
  double px = 0.0;            // reprojection error (px)
  double mm = 0.0;  // back-projected distance to the target on its plane (mm); NaN if off-image
};

struct PlaneResiduals {
  double height_mm = 0.0;
  int count = 0;
  double rms_px = 0.0, worst_px = 0.0;
  double rms_mm = 0.0, worst_mm = 0.0;
  // The fit's own uncertainty of where it puts the plane's observed pixels (mm, one standard
  // deviation along each pixel's worst axis, MappingCovariance): RMS and worst over them; NaN
  // when the data do not determine the camera.
  double mapping_sd_rms_mm = 0.0, mapping_sd_worst_mm = 0.0;
  // The cross-validated mapping error (FitOptions::holdout_folds), RMS in mm: each held-out
  // pixel back-projected onto this plane through the camera fitted without it and measured to its
  // target -- a point's distance, or a line's or circle's distance across it counted for both axes
  // (times sqrt 2: to first order the error is isotropic). Unlike rms_mm, which the fit itself has
  // minimised, it is the error of a point the fit never saw, as a measured point has it: the
  // observations' own noise included. NaN when not computed (no folds, or no fold of this plane
  // refitted); heldout_count pixels.
  double heldout_rms_mm = std::numeric_limits<double>::quiet_NaN();
  int heldout_count = 0;
};

// The camera's 12 fitted numbers in the fit's order: f, aspect (fy / fx), cx, cy, k1, k2,
// Rodrigues rotation (3), translation (3 mm).
inline constexpr int kCameraParameters = 12;

struct CalibrationFit {
  camera::PinholeCamera camera;
  Eigen::Vector3d rotation_rodrigues = Eigen::Vector3d::Zero();  // camera.rotation, as fitted
  std::array<double, 6> standard_error{};  // fx, fy, cx, cy, k1, k2 (0 when held fixed)
  // The covariance of the kCameraParameters camera numbers (row-major; rows and columns of held
  // parameters 0), the nuisance unknowns (line, circle and pattern positions) marginalised, scaled
  // by the residual variance; all NaN when the data do not determine them. A plain array, not an
  // Eigen fixed-size matrix: calib/ is compiled for another instruction set than its users
  // (calib/CMakeLists.txt), and a vectorisable Eigen member would change the struct's layout.
  std::array<double, kCameraParameters * kCameraParameters> covariance{};
  Eigen::Vector3d camera_centre_mm = Eigen::Vector3d::Zero();
  double rms_px = 0.0, worst_px = 0.0;
  // The cross-validated mapping error over every held-out pixel of every plane (mm, see
  // PlaneResiduals::heldout_rms_mm); NaN when not computed. heldout_folds: the folds refitted.
  double heldout_rms_mm = std::numeric_limits<double>::quiet_NaN();
  int heldout_folds = 0;
  std::vector<PlaneResiduals> planes;  // by increasing height
  // The calibration file's [[residual]] rows, which patlab detect adds to its blob noise: every
  // plane with observations (its measured rms_mm, worst_mm) and every height of [heights] without
  // (each pixel's reprojection error times the plane's mm per px at that pixel, measured = false).
  std::vector<camera::PlaneResidual> file_residuals;  // by increasing height
  std::vector<ObservationResidual> residuals;
  int iterations = 0;
  double seconds = 0.0;
  std::string termination;         // Ceres' termination type and message
  int observations = 0;            // pixels used
  int parameters = 0;              // free parameters, nuisance ones included
  std::vector<std::string> notes;  // how the start was found, warnings
};

// Validates the input (enough points, not all on a line, ...) and fits. Bad input -> InputError;
// so is a fit UnphysicalFitReason refuses (the message is its reason).
CalibrationFit FitCamera(const CalibrationInput& input);

// The bounds a fitted camera must keep (docs/calibrate.md "Refused fits"): a focal length of at
// least kMinFocalWidths image widths (the fit's own lower bound: a 136 deg field of view) and at
// most kMaxFocalWidths (a 2.9 deg field of view, which sees less than a robot from a field
// camera's height), and a pixel aspect fy / fx within [1 / kMaxAspect, kMaxAspect].
inline constexpr double kMinFocalWidths = 0.2;
inline constexpr double kMaxFocalWidths = 20.0;
inline constexpr double kMaxAspect = 2.0;

// The normalised image radius |(pixel - principal point) / f| at which the radial distortion
// x_d = x (1 + k1 r^2 + k2 r^4) stops increasing with r (its derivative 1 + 3 k1 r^2 + 5 k2 r^4
// first reaches 0): pixels beyond it are shown twice or not at all. nullopt when it increases
// for every r (k1, k2 >= 0, or k2 large enough).
std::optional<double> DistortionFoldRadius(double k1, double k2);

// Why a fitted camera must not be used, with its numbers, or "" when it may: a number of the
// camera or of its residuals that is not finite; radial distortion that folds inside the image
// (DistortionFoldRadius below the largest normalised radius of the image's corners); the
// principal point outside the image; the focal length or the pixel aspect outside the bounds
// above. FitCamera throws it as an InputError, so `patlab calibrate` writes no file.
std::string UnphysicalFitReason(const CalibrationFit& fit, int image_width_px, int image_height_px);

// The covariance (mm^2, row-major 2x2) of where the fitted camera puts `pixel` on the plane at
// `height_mm`: the camera's covariance propagated to first order (central differences of the
// back-projection over each free parameter, steps of 1e-3 of its standard deviation). nullopt
// when the pixel does not map onto the plane or the covariance is undetermined. For a fit whose
// noise is Gaussian, the error e at every pixel at once obeys e' C^-1 e <= chi-square with as many
// degrees of freedom as free camera parameters (Cauchy-Schwarz), to first order.
std::optional<std::array<double, 4>> MappingCovariance(const CalibrationFit& fit, const Vec2& pixel,
                                                       double height_mm);

// The fitted camera's uncertainty over the floor it shows: the RMS, over the pixels of a grid
// `step_px` apart (from step_px / 2) whose point on the plane at `height_mm` `inside` accepts, of
// the standard deviation of the distance between that point and the true one (the square root of
// MappingCovariance's trace). Pixels that do not map onto the plane are skipped. NaN when the
// covariance is undetermined or no pixel is inside.
double MappingSdOver(const CalibrationFit& fit, int width_px, int height_px, double height_mm,
                     const std::function<bool(const Vec2&)>& inside, int step_px);

// The calibration TOML file `patlab detect` reads, with the fit's summary as comments.
std::string CalibrationFileText(const CalibrationInput& input, const CalibrationFit& fit);
// The human-readable report: parameters with standard errors, residuals per plane, worst pixels.
std::string FitReportText(const CalibrationInput& input, const CalibrationFit& fit);

}  // namespace patlab::calib
