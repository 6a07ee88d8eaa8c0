#include "patlab/estimate/estimators.h"

#include <cmath>

#include "patlab/core/error.h"
#include "patlab/core/portable_math.h"
#include "patlab/estimate/newton_internal.h"

namespace patlab::estimate {

Model Model::FromPattern(const Pattern& pattern) {
  PATLAB_CHECK_OP(pattern.size(), <=, kMaxPatches);
  PATLAB_CHECK_OP(pattern.size(), >=, 2);
  Model m;
  m.num_patches = pattern.size();
  m.key_index = pattern.key_index;
  for (int i = 0; i < m.num_patches; ++i) m.model_mm[i] = pattern.patches[i].position_mm;
  m.centroid_mm = pattern.Centroid();
  m.spread_mm2 = pattern.Spread();
  PATLAB_CHECK_OP(static_cast<int>(pattern.orientation_pairs.size()), <=, kMaxPairs);
  m.num_pairs = static_cast<int>(pattern.orientation_pairs.size());
  for (int k = 0; k < m.num_pairs; ++k) {
    const OrientationPair& pair = pattern.orientation_pairs[k];
    const Vec2 d = m.model_mm[pair.to] - m.model_mm[pair.from];
    PATLAB_CHECK(d.norm() > 0.0);
    m.pair_from[k] = pair.from;
    m.pair_to[k] = pair.to;
    m.pair_cos[k] = d.x() / d.norm();
    m.pair_sin[k] = d.y() / d.norm();
  }
  return m;
}

namespace {

Vec2 Mean(const Model& model, const Vec2* observed) {
  Vec2 sum = Vec2::Zero();
  for (int i = 0; i < model.num_patches; ++i) sum += observed[i];
  return sum / static_cast<double>(model.num_patches);
}

// The paper's orientation estimate: each pair's observed displacement rotated by minus its model
// angle (so that all point "forward"), summed, atan2.
double FastAngle(const Model& model, const Vec2* observed) {
  double sx = 0.0, sy = 0.0;
  for (int k = 0; k < model.num_pairs; ++k) {
    const Vec2 d = observed[model.pair_to[k]] - observed[model.pair_from[k]];
    const double c = model.pair_cos[k], s = model.pair_sin[k];
    sx += c * d.x() + s * d.y();
    sy += -s * d.x() + c * d.y();
  }
  return pmath::Atan2(sy, sx);
}

// The origin whose pose maps `model_point` to `world_point` at heading theta.
Pose2 OriginFrom(const Vec2& world_point, const Vec2& model_point, double theta) {
  double s, c;
  pmath::SinCos(theta, &s, &c);
  return {world_point.x() - (c * model_point.x() - s * model_point.y()),
          world_point.y() - (s * model_point.x() + c * model_point.y()), WrapAngle(theta)};
}

}  // namespace

Pose2 Fast(const Model& model, const Vec2* observed) {
  return OriginFrom(Mean(model, observed), model.centroid_mm, FastAngle(model, observed));
}

Pose2 KeyPatch(const Model& model, const Vec2* observed) {
  return OriginFrom(observed[model.key_index], model.model_mm[model.key_index],
                    FastAngle(model, observed));
}

Pose2 LeastSquares(const Model& model, const Vec2* observed) {
  const Vec2 mean = Mean(model, observed);
  double dot = 0.0, cross = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const Vec2 q = model.model_mm[i] - model.centroid_mm;
    const Vec2 w = observed[i] - mean;
    dot += q.x() * w.x() + q.y() * w.y();
    cross += q.x() * w.y() - q.y() * w.x();
  }
  return OriginFrom(mean, model.centroid_mm, pmath::Atan2(cross, dot));
}

double SumSquaredError(const Model& model, const Vec2* observed, const Pose2& pose) {
  double s, c;
  pmath::SinCos(pose.theta_rad, &s, &c);
  double e = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const Vec2& p = model.model_mm[i];
    const double xi = pose.x_mm + c * p.x() - s * p.y() - observed[i].x();
    const double yi = pose.y_mm + s * p.x() + c * p.y() - observed[i].y();
    e += xi * xi + yi * yi;
  }
  return e;
}

void SumSquaredErrorDerivatives(const Model& model, const Vec2* observed, const Pose2& pose,
                                double gradient[3], double hessian[3][3]) {
  double s, c;
  pmath::SinCos(pose.theta_rad, &s, &c);
  double gx = 0.0, gy = 0.0, gt = 0.0, hxt = 0.0, hyt = 0.0, htt = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const Vec2& p = model.model_mm[i];
    const double xi = pose.x_mm + c * p.x() - s * p.y() - observed[i].x();
    const double yi = pose.y_mm + s * p.x() + c * p.y() - observed[i].y();
    const double dx = -s * p.x() - c * p.y();  // d(x_i)/d(theta)
    const double dy = c * p.x() - s * p.y();   // d(y_i)/d(theta)
    gx += 2.0 * xi;
    gy += 2.0 * yi;
    gt += 2.0 * (xi * dx + yi * dy);
    hxt += 2.0 * dx;
    hyt += 2.0 * dy;
    // d2E/dtheta2 = 2 sum (dx^2 + dy^2) + 2 sum (x_i d(dx)/dtheta + y_i d(dy)/dtheta),
    // with d(dx)/dtheta = -dy and d(dy)/dtheta = dx.
    htt += 2.0 * (dx * dx + dy * dy) - 2.0 * (xi * dy - yi * dx);
  }
  const double two_n = 2.0 * model.num_patches;
  gradient[0] = gx;
  gradient[1] = gy;
  gradient[2] = gt;
  hessian[0][0] = two_n;
  hessian[0][1] = hessian[1][0] = 0.0;
  hessian[1][1] = two_n;
  hessian[0][2] = hessian[2][0] = hxt;
  hessian[1][2] = hessian[2][1] = hyt;
  hessian[2][2] = htt;
}

Pose2 MaximumLikelihood(const Model& model, const Vec2* observed, const Pose2& start,
                        const Options& options, Summary* summary) {
  Summary local;
  Summary& sum = summary != nullptr ? *summary : local;
  sum = Summary{};
  Pose2 r = start;
  const double n = model.num_patches;
  sum.initial_cost = SumSquaredError(model, observed, r);
  sum.termination = Termination::kMaxIterations;
  if (!std::isfinite(sum.initial_cost)) {
    sum.termination = Termination::kNumericalFailure;
    sum.final_cost = sum.initial_cost;
    return r;
  }
  for (int it = 0; it < options.max_iterations; ++it) {
    double g[3], h[3][3];
    SumSquaredErrorDerivatives(model, observed, r, g, h);
    const double gx = g[0], gy = g[1], gt = g[2];
    const double hxt = h[0][2], hyt = h[1][2], htt = h[2][2];
    const double grad_norm = std::sqrt(gx * gx + gy * gy + gt * gt);
    if (grad_norm <= options.gradient_tolerance) {
      sum.termination = Termination::kConverged;
      break;
    }
    // Solve H step = -g. H = [[2n, 0, a], [0, 2n, b], [a, b, c]] has the Schur complement
    // c - (a^2 + b^2) / 2n in theta. Far from the optimum it can be <= 0 (H indefinite): then
    // damp the diagonal (Levenberg 1944) until H + lambda I is positive definite, which makes the
    // step a descent direction.
    double lambda = 0.0;
    double schur = htt - (hxt * hxt + hyt * hyt) / (2.0 * n);
    for (int tries = 0; !(schur > 0.0) && tries < 60; ++tries) {
      lambda = lambda == 0.0 ? 1e-6 * (2.0 * n + std::abs(htt)) : 10.0 * lambda;
      schur = htt + lambda - (hxt * hxt + hyt * hyt) / (2.0 * n + lambda);
    }
    if (!(schur > 0.0)) {
      sum.termination = Termination::kNumericalFailure;
      break;
    }
    const double dxy = 2.0 * n + lambda;
    const double step_t = -(gt - (hxt * gx + hyt * gy) / dxy) / schur;
    const Eigen::Vector3d step(-(gx + hxt * step_t) / dxy, -(gy + hyt * step_t) / dxy, step_t);
    if (!step.allFinite()) {
      sum.termination = Termination::kNumericalFailure;
      break;
    }
    if (internal::TakeNewtonStep(step, options, &r, &sum)) break;
  }
  r.theta_rad = WrapAngle(r.theta_rad);
  sum.final_cost = SumSquaredError(model, observed, r);
  if (!std::isfinite(sum.final_cost)) sum.termination = Termination::kNumericalFailure;
  return r;
}

std::vector<OptionsProblem> Check(const Options& options, std::string_view field_prefix) {
  const std::string p(field_prefix);
  OptionsChecker check;
  check.IntegerInRange(p + "max_iterations", options.max_iterations, 1, 1000)
      .NonNegative(p + "step_tolerance_mm", options.step_tolerance_mm, "mm")
      .NonNegative(p + "step_tolerance_rad", options.step_tolerance_rad, "rad")
      .NonNegative(p + "gradient_tolerance", options.gradient_tolerance);
  return check.Take();
}

void Validate(const Options& options) { ThrowFirstProblem(Check(options)); }

}  // namespace patlab::estimate
