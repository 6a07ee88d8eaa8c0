#include "patlab/estimate/robust.h"

#include <array>
#include <cmath>

#include "patlab/core/portable_math.h"

namespace patlab::estimate {

namespace {

constexpr int kMaxSteps = 200;
constexpr double kStepMm = 1e-9, kStepRad = 1e-11;

// Squared residual of patch i at the pose, in units of sigma^2.
double Residual2(const Model& model, const Vec2* observed, const Pose2& pose, int i,
                 double inv_sigma2) {
  return (pose.Apply(model.model_mm[i]) - observed[i]).squaredNorm() * inv_sigma2;
}

// The posterior inlier probability's odds factor: gamma = 1 / (1 + odds exp(d (1 - 1/k^2)))
// with d = |e|^2 / (2 sigma^2) and odds = p / ((1 - p) k^2).
double InlierProbability(const RobustModel& r, double d) {
  const double k2 = r.outlier_sigma_ratio * r.outlier_sigma_ratio;
  const double odds = r.outlier_probability / ((1.0 - r.outlier_probability) * k2);
  return 1.0 / (1.0 + odds * pmath::Exp(d * (1.0 - 1.0 / k2)));
}

// The IRLS weight of a patch at squared residual e2 (units of sigma^2).
double Weight(const RobustModel& r, double e2) {
  if (!r.IsMixture()) {
    const double norm = std::sqrt(e2);
    return norm <= RobustModel::kHuberTuning ? 1.0 : RobustModel::kHuberTuning / norm;
  }
  const double gamma = InlierProbability(r, e2 / 2.0);
  const double k2 = r.outlier_sigma_ratio * r.outlier_sigma_ratio;
  return gamma + (1.0 - gamma) / k2;
}

// The most likely of the least-squares fit and the leave-one-out fits (n >= 3).
Pose2 RobustStart(const Model& model, const Vec2* observed, const RobustModel& robust) {
  Pose2 best = LeastSquares(model, observed);
  if (model.num_patches < 3) return best;
  double best_objective = RobustObjective(model, observed, robust, best);
  std::array<double, kMaxPatches> weights{};
  for (int out = 0; out < model.num_patches; ++out) {
    for (int i = 0; i < model.num_patches; ++i) weights[i] = i == out ? 0.0 : 1.0;
    const Pose2 candidate = WeightedLeastSquares(model, observed, weights.data());
    const double objective = RobustObjective(model, observed, robust, candidate);
    if (objective > best_objective) best = candidate, best_objective = objective;
  }
  return best;
}

}  // namespace

Pose2 WeightedLeastSquares(const Model& model, const Vec2* observed, const double* weights) {
  double total = 0.0;
  Vec2 model_mean = Vec2::Zero(), data_mean = Vec2::Zero();
  for (int i = 0; i < model.num_patches; ++i) {
    total += weights[i];
    model_mean += weights[i] * model.model_mm[i];
    data_mean += weights[i] * observed[i];
  }
  model_mean /= total;
  data_mean /= total;
  double dot = 0.0, cross = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const Vec2 q = model.model_mm[i] - model_mean;
    const Vec2 u = observed[i] - data_mean;
    dot += weights[i] * (q.x() * u.x() + q.y() * u.y());
    cross += weights[i] * (q.x() * u.y() - q.y() * u.x());
  }
  const double theta = WrapAngle(pmath::Atan2(cross, dot));
  double s, c;
  pmath::SinCos(theta, &s, &c);
  return {data_mean.x() - (c * model_mean.x() - s * model_mean.y()),
          data_mean.y() - (s * model_mean.x() + c * model_mean.y()), theta};
}

double RobustObjective(const Model& model, const Vec2* observed, const RobustModel& robust,
                       const Pose2& pose) {
  const double inv_sigma2 = 1.0 / (robust.sigma_mm * robust.sigma_mm);
  const double p = robust.outlier_probability, k = robust.outlier_sigma_ratio;
  double objective = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const double e2 = Residual2(model, observed, pose, i, inv_sigma2);
    if (robust.IsMixture()) {
      // log((1 - p) exp(-d) + p / k^2 exp(-d / k^2)), d = e2 / 2, the larger term factored out.
      const double d = e2 / 2.0;
      const double a = pmath::Log(1.0 - p) - d, b = pmath::Log(p / (k * k)) - d / (k * k);
      const double hi = a > b ? a : b, lo = a > b ? b : a;
      objective += hi + pmath::Log(1.0 + pmath::Exp(lo - hi));
    } else {
      const double r = std::sqrt(e2), c = RobustModel::kHuberTuning;
      objective -= r <= c ? e2 / 2.0 : c * r - c * c / 2.0;
    }
  }
  return objective;
}

Pose2 Robust(const Model& model, const Vec2* observed, const RobustModel& robust,
             Summary* summary) {
  Summary local;
  Summary& sum = summary != nullptr ? *summary : local;
  sum = Summary{};
  sum.termination = Termination::kMaxIterations;
  if (!(robust.sigma_mm > 0.0)) {  // noise-free: every patch is exact, least squares is the pose
    sum.termination = Termination::kConverged;
    return LeastSquares(model, observed);
  }
  Pose2 pose = RobustStart(model, observed, robust);
  sum.initial_cost = -RobustObjective(model, observed, robust, pose);
  const double inv_sigma2 = 1.0 / (robust.sigma_mm * robust.sigma_mm);
  std::array<double, kMaxPatches> weights{};
  for (int step = 0; step < kMaxSteps; ++step) {
    for (int i = 0; i < model.num_patches; ++i) {
      weights[i] = Weight(robust, Residual2(model, observed, pose, i, inv_sigma2));
    }
    const Pose2 next = WeightedLeastSquares(model, observed, weights.data());
    ++sum.iterations;
    const bool small = std::abs(next.x_mm - pose.x_mm) <= kStepMm &&
                       std::abs(next.y_mm - pose.y_mm) <= kStepMm &&
                       std::abs(WrapAngle(next.theta_rad - pose.theta_rad)) <= kStepRad;
    pose = next;
    if (small) {
      sum.termination = Termination::kConverged;
      break;
    }
  }
  sum.final_cost = -RobustObjective(model, observed, robust, pose);
  if (!std::isfinite(sum.final_cost) || !std::isfinite(pose.x_mm)) {
    sum.termination = Termination::kNumericalFailure;
  }
  return pose;
}

}  // namespace patlab::estimate
