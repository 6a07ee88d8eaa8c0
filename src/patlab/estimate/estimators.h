// Pose of a pattern from patches already matched to its model (paper section III).
//
// Every estimator takes the observed world positions v[i] of the pattern's patches, in the
// pattern's patch order, and returns the pose (origin position in mm, heading in rad wrapped to
// (-pi, pi]) that maps model positions to world positions. All are pure functions on small
// fixed-size data and never allocate.
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include "patlab/core/enum_names.h"
#include "patlab/core/geometry.h"
#include "patlab/core/options.h"
#include "patlab/core/pattern.h"

namespace patlab::estimate {

// Everything the estimators need from a Pattern, precomputed once: model positions, the
// orientation pairs with the unit direction of each model displacement, and the centroid.
struct Model {
  int num_patches = 0;
  int key_index = 0;
  std::array<Vec2, kMaxPatches> model_mm{};  // p_i
  Vec2 centroid_mm = Vec2::Zero();           // mean of p_i
  double spread_mm2 = 0.0;                   // sum |p_i - centroid|^2

  int num_pairs = 0;
  static constexpr int kMaxPairs = kMaxPatches * (kMaxPatches - 1) / 2;
  std::array<int, kMaxPairs> pair_from{};
  std::array<int, kMaxPairs> pair_to{};
  std::array<double, kMaxPairs> pair_cos{};  // cos of the model angle of p_to - p_from
  std::array<double, kMaxPairs> pair_sin{};  // sin of the model angle of p_to - p_from

  static Model FromPattern(const Pattern& pattern);
};

// The paper's fast estimator (section III): the mean of the patches; each orientation pair's
// displacement rotated back by its model angle, summed, atan2; the mean projected back to the
// model origin with that angle.
Pose2 Fast(const Model& model, const Vec2* observed);

// The closed-form minimiser of the sum-squared error (2-D Procrustes / Umeyama 1991 without
// scale): theta = atan2(sum q_i x w_i, sum q_i . w_i) on centred model q and centred data w.
Pose2 LeastSquares(const Model& model, const Vec2* observed);

// What SSL-Vision publishes: the position of the key patch alone (mapped to the model origin
// with the fast angle), and the fast estimator's angle.
Pose2 KeyPatch(const Model& model, const Vec2* observed);

// Sum-squared error E(r) = sum_i |R(r_theta) p_i + r_xy - v_i|^2 (paper section III).
double SumSquaredError(const Model& model, const Vec2* observed, const Pose2& pose);

// E's gradient (the paper's analytic formulas, section III) and its exact Hessian at `pose`, in
// the order (x, y, theta): gradient[3], hessian[3][3] (symmetric; hessian[0][1] = 0).
void SumSquaredErrorDerivatives(const Model& model, const Vec2* observed, const Pose2& pose,
                                double gradient[3], double hessian[3][3]);

// Newton's method on E with the paper's analytic gradient and the exact Hessian.
struct Options {
  int max_iterations = 20;  // Newton steps before giving up (>= 1)
  // Converged when the last Newton step was below both step tolerances. Newton converges
  // quadratically here, so the error left after such a step is of the order of its square:
  // tighter values only add a step that changes nothing measurable.
  double step_tolerance_mm = 1e-7;    // |d x|, |d y| (mm)
  double step_tolerance_rad = 1e-9;   // |d theta| (rad)
  double gradient_tolerance = 1e-12;  // or when |grad E| (mm, mm, mm^2 units) is below this
};
// The one place these options are checked (core/options.h): max_iterations in [1, 1000] (more
// never helps a method that converges in 2-4 steps, and bounds the work of a diverging trial),
// each tolerance a finite number >= 0. Experiment files ([ml]) and detector settings
// (ml_max_iterations, with field prefix "ml_") report these problems at their key's line.
std::vector<OptionsProblem> Check(const Options& options, std::string_view field_prefix = "");
void Validate(const Options& options);

enum class Termination {
  kConverged,         // a step or gradient tolerance was met
  kMaxIterations,     // Options::max_iterations steps without meeting a tolerance
  kNumericalFailure,  // a non-finite cost or an indefinite Hessian that damping could not fix
};
inline constexpr EnumNames<Termination, 3> kTerminationNames{{{
    {Termination::kConverged, "converged"},
    {Termination::kMaxIterations, "max_iterations"},
    {Termination::kNumericalFailure, "numerical_failure"},
}}};
inline std::string_view TerminationName(Termination termination) {
  return NameOf(termination, kTerminationNames);
}

struct Summary {
  Termination termination = Termination::kConverged;
  int iterations = 0;         // Newton steps taken
  double initial_cost = 0.0;  // E at the starting pose (mm^2)
  double final_cost = 0.0;    // E at the returned pose (mm^2)
};

// The maximum-likelihood pose under iid isotropic Gaussian patch noise, by Newton's method from
// `start` (normally Fast()). `summary` may be null.
Pose2 MaximumLikelihood(const Model& model, const Vec2* observed, const Pose2& start,
                        const Options& options, Summary* summary);

// Estimator names as they appear in experiment files and results. kRobust (robust.h) needs the
// noise model (its sigma and outlier mixture) besides the pattern; kAllEstimators are the four
// that need the pattern alone (what `patlab evaluate` and the detector's estimator choice run).
enum class Estimator { kFast, kMl, kLsq, kKey, kRobust };
inline constexpr int kNumEstimators = 5;  // arrays indexed by Estimator
inline constexpr std::array<Estimator, 4> kAllEstimators = {Estimator::kFast, Estimator::kMl,
                                                            Estimator::kLsq, Estimator::kKey};
inline constexpr std::array<Estimator, kNumEstimators> kEveryEstimator = {
    Estimator::kFast, Estimator::kMl, Estimator::kLsq, Estimator::kKey, Estimator::kRobust};
inline constexpr EnumNames<Estimator, kNumEstimators> kEstimatorNames{{{
    {Estimator::kFast, "fast"},
    {Estimator::kMl, "ml"},
    {Estimator::kLsq, "lsq"},
    {Estimator::kKey, "key"},
    {Estimator::kRobust, "robust"},
}}};
inline std::string_view EstimatorName(Estimator estimator) {
  return NameOf(estimator, kEstimatorNames);
}
// Returns false if `name` is not an estimator name. (FindName(name, kEstimatorNames) is the same;
// this form serves the file readers of formats/ and the shard merge of sim/.)
inline bool ParseEstimator(std::string_view name, Estimator* estimator) {
  const std::optional<Estimator> found = FindName(name, kEstimatorNames);
  if (found) *estimator = *found;
  return found.has_value();
}

}  // namespace patlab::estimate
