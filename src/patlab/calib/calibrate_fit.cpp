// The camera fit of calibrate.h: validation, a closed-form start, and the Ceres solve.
#include <ceres/ceres.h>
#include <glog/logging.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <vector>

#include "patlab/calib/calibrate.h"
#include "patlab/calib/calibrate_internal.h"
#include "patlab/core/format.h"
#include "patlab/core/timeprofile.h"
#include "patlab/estimate/estimators.h"

namespace patlab::calib {

namespace internal {

camera::PinholeCamera CameraOf(const FitState& s) {
  camera::PinholeCamera c;
  c.fx_px = s.intrinsics[0];
  c.fy_px = s.intrinsics[0] * s.intrinsics[1];
  c.cx_px = s.intrinsics[2];
  c.cy_px = s.intrinsics[3];
  c.k1 = s.intrinsics[4];
  c.k2 = s.intrinsics[5];
  c.rotation = camera::RotationFromRodrigues(Eigen::Vector3d(s.pose[0], s.pose[1], s.pose[2]));
  c.translation_mm = Eigen::Vector3d(s.pose[3], s.pose[4], s.pose[5]);
  return c;
}

Vec2 LineTarget(const LineObservation& l, double t) {
  return l.from_mm + t * (l.to_mm - l.from_mm);
}

Vec2 CircleTarget(const CircleObservation& c, double phi) {
  return c.centre_mm + c.radius_mm * Vec2(std::cos(phi), std::sin(phi));
}

Vec2 PatternTarget(const PatternObservation& p, const std::array<double, 3>& pose, int patch) {
  return Pose2{pose[0], pose[1], pose[2]}.Apply(
      p.pattern.patches[static_cast<size_t>(patch)].position_mm);
}

}  // namespace internal

namespace {

using internal::FitState;

// The focal length's lower bound, kMinFocalWidths image widths (calibrate.h): a camera fitted to
// one plane can otherwise shrink towards f -> 0 with its distance.

using internal::CheckPixels;
using internal::CheckStartPoints;
using internal::StartCandidates;

// ---- the solve --------------------------------------------------------------------------------

std::vector<int> FixedIndices(const FitOptions& o) {
  std::vector<int> fixed;
  for (FitParameter p : o.fixed) {
    switch (p) {
      case FitParameter::kFocal:
        fixed.push_back(0);
        break;
      case FitParameter::kAspect:
        fixed.push_back(1);
        break;
      case FitParameter::kPrincipalPoint:
        fixed.insert(fixed.end(), {2, 3});
        break;
      case FitParameter::kK1:
        fixed.push_back(4);
        break;
      case FitParameter::kK2:
        fixed.push_back(5);
        break;
    }
  }
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  return fixed;
}

// One pixel's block on the camera's parameters and, where not null, its nuisance unknowns.
void Add(ceres::Problem& problem, ceres::LossFunction* loss, ceres::CostFunction* cost, FitState& s,
         double* extra) {
  if (extra) {
    problem.AddResidualBlock(cost, loss, s.intrinsics.data(), s.pose.data(), extra);
  } else {
    problem.AddResidualBlock(cost, loss, s.intrinsics.data(), s.pose.data());
  }
}

// Every pixel's residual block; returns the number of pixels.
// `loss` (may be null) is shared by every block and owned by the caller.
int BuildProblem(const CalibrationInput& in, FitState& s, ceres::LossFunction* loss,
                 const std::vector<int>& fixed, ceres::Problem& problem) {
  int pixels = 0;
  for (const PointObservation& p : in.points) {
    Add(problem, loss,
        internal::NewPointCost(p.pixel,
                               Eigen::Vector3d(p.world_mm.x(), p.world_mm.y(), p.height_mm)),
        s, nullptr);
    ++pixels;
  }
  for (size_t i = 0; i < in.lines.size(); ++i) {
    const LineObservation& l = in.lines[i];
    for (size_t j = 0; j < l.pixels.size(); ++j, ++pixels)
      Add(problem, loss, internal::NewLineCost(l.pixels[j], l.from_mm, l.to_mm, l.height_mm), s,
          &s.line_t[i][j]);
  }
  for (size_t i = 0; i < in.circles.size(); ++i) {
    const CircleObservation& c = in.circles[i];
    for (size_t j = 0; j < c.pixels.size(); ++j, ++pixels)
      Add(problem, loss,
          internal::NewCircleCost(c.pixels[j], c.centre_mm, c.radius_mm, c.height_mm), s,
          &s.circle_phi[i][j]);
  }
  for (size_t i = 0; i < in.patterns.size(); ++i) {
    const PatternObservation& p = in.patterns[i];
    for (size_t j = 0; j < p.pixels.size(); ++j) {
      if (!p.pixels[j]) continue;
      Add(problem, loss,
          internal::NewPatternCost(*p.pixels[j], p.pattern.patches[j].position_mm, p.height_mm), s,
          s.pattern_pose[i].data());
      ++pixels;
    }
  }
  if (in.options.camera_height_mm) {
    problem.AddResidualBlock(
        internal::NewHeightPrior(*in.options.camera_height_mm, in.options.camera_height_sd_mm),
        nullptr, s.pose.data());
  }
  if (fixed.size() == 6) {
    problem.SetParameterBlockConstant(s.intrinsics.data());
  } else if (!fixed.empty()) {
    problem.SetManifold(s.intrinsics.data(), new ceres::SubsetManifold(6, fixed));
  }
  return pixels;
}

// The covariance of the camera's numbers (intrinsics then pose, calibrate.h), scaled by the
// residual variance (Ceres assumes unit-variance residuals); all NaN when the data do not
// determine them (a rank-deficient Jacobian). Ceres inverts the whole normal matrix, so the
// nuisance unknowns are marginalised, not held at their fitted values.
std::array<double, kCameraParameters * kCameraParameters> CameraCovariance(
    ceres::Problem& problem, FitState& s, double residual_variance) {
  std::array<double, kCameraParameters * kCameraParameters> out{};
  out.fill(std::numeric_limits<double>::quiet_NaN());
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  // Rank deficiency is declared below a ratio of 1e-10 between J's smallest and largest singular
  // value, not Ceres' default 1e-7: that default is meant for columns of one scale, and these are
  // px per mm (translation, ~0.2), px per radian (rotation, ~1e3), px per unit of k1 (~1e2-1e3)
  // and px per px (focal length, ~0.5). With it, well-determined cameras (the random cameras of
  // tests/calib, seeds 3 and 29) were reported undetermined. JacobiSVD resolves singular values
  // to about 1e-16 of the largest, so 1e-10 leaves about six digits in the covariance.
  co.min_reciprocal_condition_number = 1e-20;
  co.num_threads = 1;
  ceres::Covariance covariance(co);
  const std::array<const double*, 2> blocks = {s.intrinsics.data(), s.pose.data()};
  std::vector<std::pair<const double*, const double*>> pairs;
  for (size_t a = 0; a < 2; ++a)
    for (size_t b = a; b < 2; ++b) pairs.emplace_back(blocks[a], blocks[b]);
  if (!covariance.Compute(pairs, &problem)) return out;
  constexpr int n = kCameraParameters;
  for (size_t a = 0; a < 2; ++a) {
    for (size_t b = a; b < 2; ++b) {
      double c[36];
      if (!covariance.GetCovarianceBlock(blocks[a], blocks[b], c)) {
        out.fill(std::numeric_limits<double>::quiet_NaN());
        return out;
      }
      for (size_t i = 0; i < 6; ++i) {
        for (size_t j = 0; j < 6; ++j) {
          const double v = residual_variance * c[6 * i + j];
          out[(6 * a + i) * n + 6 * b + j] = v;
          out[(6 * b + j) * n + 6 * a + i] = v;
        }
      }
    }
  }
  return out;
}

// Standard errors of fx, fy, cx, cy, k1, k2 from the camera's covariance (fy = f aspect, to first
// order); NaN where it is undetermined.
std::array<double, 6> StandardErrors(
    const std::array<double, kCameraParameters * kCameraParameters>& c, const FitState& s) {
  auto var = [&](size_t i, size_t j) { return c[i * kCameraParameters + j]; };
  const double f = s.intrinsics[0], a = s.intrinsics[1];
  std::array<double, 6> se{};
  se[0] = std::sqrt(var(0, 0));
  se[1] = std::sqrt(std::max(0.0, a * a * var(0, 0) + f * f * var(1, 1) + 2 * a * f * var(0, 1)));
  if (std::isnan(var(0, 0))) se[1] = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 2; i < 6; ++i) se[i] = std::sqrt(var(i, i));
  return se;
}

// A camera looking nearly straight down at one plane sees it the same from any height with the
// focal length scaled alike: such data fix the plane's mapping but not f, and so not the mapping
// of other heights. Say so when f's standard error exceeds 2%.
void WarnIfFocalUndetermined(const std::vector<int>& fixed, CalibrationFit& fit) {
  if (std::find(fixed.begin(), fixed.end(), 0) != fixed.end()) return;
  const double relative = fit.standard_error[0] / fit.camera.fx_px;
  if (relative <= 0.02) return;
  std::string heights;
  for (const PlaneResiduals& p : fit.planes)
    heights += (heights.empty() ? "" : ", ") + FormatNumber(p.height_mm);
  fit.notes.push_back(
      "warning: the focal length is not determined by these data (standard error " +
      (std::isnan(relative) ? std::string("undetermined") : FormatFixed(100 * relative, 1) + "%") +
      "): the mapping of the observed plane heights (" + heights +
      " mm) holds, other heights are extrapolated; give [fit] camera_height_mm (measured), or "
      "focal_px with fix = [\"focal\", ...], or observe patterns at the heights you detect");
}

// An observed pixel the fitted camera cannot map back (NaN mm residual) lies beyond the fold of
// its distortion polynomial: the fit bent the lens to explain it, and is not to be trusted there.
void WarnIfBeyondTheFold(CalibrationFit& fit) {
  const auto n = std::count_if(fit.residuals.begin(), fit.residuals.end(),
                               [](const ObservationResidual& r) { return std::isnan(r.mm); });
  if (n == 0) return;
  fit.notes.push_back("warning: " + std::to_string(n) +
                      " observed pixels lie beyond the fold of the fitted lens distortion (they "
                      "cannot be mapped back): the calibration is not usable there; hold k1 "
                      "(fix = [\"k1\", ...] with [fit] k1) or add observations near the image "
                      "edge");
}

// Minimises over the problem's free parameters (`s` its parameter blocks); Ceres' summary.
ceres::Solver::Summary Solve(const CalibrationInput& in, const FitState& s, ceres::Problem& problem,
                             int max_iterations) {
  ceres::Solver::Options so;
  std::unique_ptr<ceres::IterationCallback> settled;
  if (in.options.settle_px > 0.0) {
    settled = internal::FloorImageSettled(in, s);
    so.callbacks.push_back(settled.get());
    so.update_state_every_iteration = true;
  }
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = 1e-12;
  so.gradient_tolerance = 1e-12;
  so.parameter_tolerance = 1e-12;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return summary;
}

ceres::Problem::Options ProblemOptions() {
  ceres::Problem::Options po;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return po;
}

// The observed pixels and the free parameters (camera and nuisance); refuses data with fewer
// equations than unknowns.
void CountUnknowns(const CalibrationInput& in, const std::vector<int>& fixed, CalibrationFit& fit) {
  int pixels = static_cast<int>(in.points.size()), unknowns = 12 - static_cast<int>(fixed.size());
  for (const LineObservation& l : in.lines) pixels += static_cast<int>(l.pixels.size());
  for (const CircleObservation& c : in.circles) pixels += static_cast<int>(c.pixels.size());
  unknowns += pixels - static_cast<int>(in.points.size());  // one per line or circle pixel
  for (const PatternObservation& p : in.patterns) {
    unknowns += 3;
    for (const auto& px : p.pixels) pixels += px.has_value();
  }
  fit.observations = pixels;
  fit.parameters = unknowns;
  if (2 * pixels + (in.options.camera_height_mm ? 1 : 0) <= unknowns) {
    throw InputError(in.loc, std::to_string(pixels) + " observed pixels give " +
                                 std::to_string(2 * pixels) + " equations for " +
                                 std::to_string(unknowns) +
                                 " unknowns; expected more points, line or circle pixels");
  }
}

// Stage 1 from every start candidate: the pose, the focal length and k1 (principal point, aspect
// and k2 held), which brings the full model near a basin; the candidates by increasing cost.
std::vector<FitState> FirstStage(const CalibrationInput& in, const std::vector<int>& fixed,
                                 ceres::LossFunction* loss) {
  std::vector<int> stage1 = {1, 2, 3, 5};
  for (int i : {0, 4})
    if (std::find(fixed.begin(), fixed.end(), i) != fixed.end()) stage1.push_back(i);
  std::sort(stage1.begin(), stage1.end());
  std::vector<std::pair<double, FitState>> ranked;
  for (FitState& s : StartCandidates(in)) {
    ceres::Problem problem(ProblemOptions());
    BuildProblem(in, s, loss, stage1, problem);
    if (std::find(stage1.begin(), stage1.end(), 0) == stage1.end())
      problem.SetParameterLowerBound(s.intrinsics.data(), 0, kMinFocalWidths * in.image_width_px);
    const ceres::Solver::Summary summary = Solve(in, s, problem, 50);
    if (summary.IsSolutionUsable()) ranked.emplace_back(summary.final_cost, s);
  }
  if (ranked.empty()) {
    throw InputError(in.loc,
                     "no camera in front of the plane explains the known points; "
                     "expected pixels and field coordinates of the same points");
  }
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<FitState> out;
  for (auto& [cost, s] : ranked) out.push_back(std::move(s));
  return out;
}

// Stage 2, the full model, from `s`; the summary.
ceres::Solver::Summary FullStage(const CalibrationInput& in, const std::vector<int>& fixed,
                                 ceres::LossFunction* loss, FitState& s, ceres::Problem& problem) {
  BuildProblem(in, s, loss, fixed, problem);
  if (std::find(fixed.begin(), fixed.end(), 0) == fixed.end())
    problem.SetParameterLowerBound(s.intrinsics.data(), 0, kMinFocalWidths * in.image_width_px);
  return Solve(in, s, problem, in.options.max_iterations);
}

}  // namespace

bool internal::RefitFrom(const CalibrationInput& in, const std::vector<int>& fixed,
                         ceres::LossFunction* loss, FitState& s) {
  ceres::Problem problem(ProblemOptions());
  return FullStage(in, fixed, loss, s, problem).IsSolutionUsable();
}

CalibrationFit FitCamera(const CalibrationInput& input) {
  const auto t0 = std::chrono::steady_clock::now();
  CheckPixels(input);
  CheckStartPoints(input);
  // Ceres reports through glog; what matters reaches the user in the fit's termination message.
  FLAGS_minloglevel = google::GLOG_FATAL;
  const std::unique_ptr<ceres::LossFunction> loss(
      input.options.huber_px > 0.0 ? new ceres::HuberLoss(input.options.huber_px) : nullptr);
  CalibrationFit fit;
  const std::vector<int> fixed = FixedIndices(input.options);
  CountUnknowns(input, fixed, fit);
  // The full model from the three best first stages (a camera seen nearly head-on has shallow
  // valleys with more than one basin); the least final cost wins.
  std::vector<FitState> starts = FirstStage(input, fixed, loss.get());
  starts.resize(std::min<size_t>(starts.size(), 3));
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Summary summary;
  FitState* best = nullptr;  // the problem's parameter blocks live in it
  for (FitState& start : starts) {
    auto candidate = std::make_unique<ceres::Problem>(ProblemOptions());
    const ceres::Solver::Summary result = FullStage(input, fixed, loss.get(), start, *candidate);
    if (!problem || (result.IsSolutionUsable() && result.final_cost < summary.final_cost) ||
        !summary.IsSolutionUsable()) {
      problem = std::move(candidate);
      summary = result;
      best = &start;
    }
  }
  const FitState& s = *best;
  fit.notes.push_back("start: " + std::to_string(starts.size()) +
                      " first stages refined; the best has focal " +
                      FormatSignificant(s.intrinsics[0], 5) + " px");
  fit.iterations = static_cast<int>(summary.iterations.size()) - 1;
  fit.termination = summary.termination_type == ceres::USER_SUCCESS  // only the settle's stop
                        ? internal::SettledTermination(input.options)
                        : ceres::TerminationTypeToString(summary.termination_type) +
                              std::string(": ") + summary.message;
  if (!summary.IsSolutionUsable()) {
    throw InputError(input.loc, "the camera fit failed (" + fit.termination +
                                    "); expected observations a pinhole camera can explain");
  }
  fit.camera = internal::CameraOf(s);
  fit.rotation_rodrigues = Eigen::Vector3d(s.pose[0], s.pose[1], s.pose[2]);
  const double dof = 2.0 * fit.observations - fit.parameters;
  if (input.options.covariance) {
    fit.covariance = CameraCovariance(*problem, *best, 2.0 * summary.final_cost / dof);
  } else {
    fit.covariance.fill(std::numeric_limits<double>::quiet_NaN());
  }
  fit.standard_error = StandardErrors(fit.covariance, s);
  for (int i : fixed) {
    if (i == 0) fit.standard_error[0] = fit.standard_error[1] = 0.0;
    if (i >= 2) fit.standard_error[static_cast<size_t>(i)] = 0.0;
  }
  fit.camera_centre_mm = -fit.camera.rotation.transpose() * fit.camera.translation_mm;
  internal::FillResiduals(input, s, fit);
  if (input.options.covariance) {
    internal::FillMappingUncertainty(fit);
    WarnIfFocalUndetermined(fixed, fit);
  } else {
    for (PlaneResiduals& plane : fit.planes)
      plane.mapping_sd_rms_mm = plane.mapping_sd_worst_mm =
          std::numeric_limits<double>::quiet_NaN();
  }
  WarnIfBeyondTheFold(fit);
  // A folded or unphysical camera is refused before anyone spends time on its held-out error.
  const std::string unphysical =
      UnphysicalFitReason(fit, input.image_width_px, input.image_height_px);
  if (!unphysical.empty()) throw InputError(input.loc, unphysical);
  internal::FillHeldOut(input, fixed, loss.get(), s, fit);
  fit.seconds = SecondsSince(t0);
  return fit;
}

}  // namespace patlab::calib
