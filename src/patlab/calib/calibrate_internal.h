// Pieces of the camera fit shared by calibrate_fit.cpp, calibrate_start.cpp and
// calibrate_report.cpp (and the automatic calibration's fit, for a camera's tilt).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "patlab/calib/calibrate.h"

namespace ceres {
class CostFunction;
class IterationCallback;
class LossFunction;
}  // namespace ceres

namespace patlab::calib::internal {

// The fit's parameter blocks. intrinsics = {f, aspect, cx, cy, k1, k2} (fx = f, fy = f aspect);
// pose = {Rodrigues r (3), t (3) mm} with X_camera = R(r) X_world + t; one position along its
// line (fraction of from -> to) per line pixel; one angle (rad) per circle pixel; one planar pose
// {x, y, theta} per pattern.
struct FitState {
  std::array<double, 6> intrinsics{};
  std::array<double, 6> pose{};
  std::vector<std::vector<double>> line_t;
  std::vector<std::vector<double>> circle_phi;
  std::vector<std::array<double, 3>> pattern_pose;
};

camera::PinholeCamera CameraOf(const FitState& s);

// The camera of camera/camera.h as the fit parametrises it (FitState): the pixel of the world
// point `world` (x, y, z mm) and, where the pointers are not null, its derivatives by the
// intrinsics (2 x 6), the pose (2 x 6) and the world point (2 x 3), each row-major. False for a
// point not in front of the camera (calibrate_costs.cpp).
bool ProjectWithDerivatives(const double* intrinsics, const double* pose, const double* world,
                            double* pixel, double* d_intrinsics, double* d_pose, double* d_world);

// The fit's residual blocks, projection minus observed pixel, on the parameter blocks
// (intrinsics, pose) and the observation's nuisance unknowns: none for a known point, t for a
// line pixel, phi for a circle pixel, the planar pose for a pattern (calibrate_costs.cpp). And a
// measured camera height's prior on the pose. The caller owns what they return.
ceres::CostFunction* NewPointCost(const Vec2& pixel, const Eigen::Vector3d& world);
ceres::CostFunction* NewLineCost(const Vec2& pixel, const Vec2& from, const Vec2& to,
                                 double height_mm);
ceres::CostFunction* NewCircleCost(const Vec2& pixel, const Vec2& centre, double radius_mm,
                                   double height_mm);
ceres::CostFunction* NewPatternCost(const Vec2& pixel, const Vec2& model, double height_mm);
ceres::CostFunction* NewHeightPrior(double height_mm, double sd_mm);

// The world point (x, y, height) that an observation's pixel `index` is fitted to.
Vec2 LineTarget(const LineObservation& l, double t);
Vec2 CircleTarget(const CircleObservation& c, double phi);
Vec2 PatternTarget(const PatternObservation& p, const std::array<double, 3>& pose, int patch);

// The input's checks before the fit (calibrate_start.cpp): every observed pixel inside the image,
// and at least four known points on one plane, no three of them on a line, so that the plane
// homography of the start is determined (InputError at the observation's file:line otherwise).
void CheckPixels(const CalibrationInput& in);
void CheckStartPoints(const CalibrationInput& in);

// Start cameras: the plane homography of the known points on the best-covered plane, decomposed
// with each candidate focal length (calibrate_start.cpp says which). The fit's first stage starts
// from each and keeps the best.
std::vector<FitState> StartCandidates(const CalibrationInput& in);

// Residuals of every pixel, per-plane summaries and totals into `fit`.
void FillResiduals(const CalibrationInput& input, const FitState& s, CalibrationFit& fit);

// FitOptions::settle_px's stop (calibrate_settle.cpp): a solver callback that ends the solve
// once the image of the floor through `s`'s camera has settled, kSettleIterations successful
// iterations moving no point of it by more than in.options.settle_px. The points: the floor seen
// at a 5 x 5 grid of the start camera's image. `s` must hold the problem's parameter blocks, and
// the solver must update them every iteration.
std::unique_ptr<ceres::IterationCallback> FloorImageSettled(const CalibrationInput& in,
                                                            const FitState& s);

// CalibrationFit::termination of a solve FloorImageSettled ended: "SETTLED" and the rule it met.
std::string SettledTermination(const FitOptions& options);

// The full model refitted from `s` (its parameters and nuisance unknowns as they stand) to `in`,
// with `fixed` intrinsics held: false when Ceres finds no usable solution (calibrate_fit.cpp).
bool RefitFrom(const CalibrationInput& in, const std::vector<int>& fixed, ceres::LossFunction* loss,
               FitState& s);

// fit.heldout_* and each plane's heldout_*: the cross-validated mapping error
// (calibrate_holdout.cpp), refitting from the fitted state `s`.
void FillHeldOut(const CalibrationInput& in, const std::vector<int>& fixed,
                 ceres::LossFunction* loss, const FitState& s, CalibrationFit& fit);

// Each plane's mapping_sd_* from fit.covariance (calibrate_uncertainty.cpp).
void FillMappingUncertainty(CalibrationFit& fit);
double WorstAxisSd(const std::array<double, 4>& covariance);

// The angle (deg) between a camera's optical axis and straight down (calibrate_report.cpp).
double TiltDeg(const camera::PinholeCamera& c);

}  // namespace patlab::calib::internal
