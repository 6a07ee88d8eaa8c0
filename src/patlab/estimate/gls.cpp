#include "patlab/estimate/gls.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <numbers>

#include "patlab/core/error.h"
#include "patlab/core/portable_math.h"
#include "patlab/estimate/newton_internal.h"

namespace patlab::estimate {

namespace {

constexpr int kMax = GaussianWeights::kMax;

// Lower Cholesky factor of the 2n x 2n covariance A (gls.h), row-major in `l`.
void FactorCovariance(const Model& model, const GaussianNoise& noise,
                      std::array<double, kMax * kMax>& l) {
  const int n = model.num_patches, size = 2 * n;
  const double g2 = noise.common_sigma_ratio * noise.common_sigma_ratio;
  const double r2 = noise.sigma_y_ratio * noise.sigma_y_ratio;
  const auto a = [&](int row, int col) {
    const int i = row / 2, j = col / 2;
    if (row % 2 != col % 2) return 0.0;
    double c = i == j ? 1.0 : 0.0;
    if (noise.correlation_length_mm > 0.0 && i != j) {
      c = pmath::Exp(-(model.model_mm[i] - model.model_mm[j]).norm() / noise.correlation_length_mm);
    }
    return c * (row % 2 == 0 ? 1.0 : r2) + g2;
  };
  l.fill(0.0);
  for (int i = 0; i < size; ++i) {
    for (int j = 0; j <= i; ++j) {
      double v = a(i, j);
      for (int k = 0; k < j; ++k) v -= l[i * kMax + k] * l[j * kMax + k];
      if (i == j) {
        PATLAB_CHECK(v > 0.0);  // A is positive definite for distinct patches
        l[i * kMax + i] = std::sqrt(v);
      } else {
        l[i * kMax + j] = v / l[j * kMax + j];
      }
    }
  }
}

// Gradient and Hessian of the Mahalanobis cost at `pose` (order x, y, theta); returns the cost.
double CostDerivatives(const Model& model, const GaussianWeights& w, const Vec2* observed,
                       const Pose2& pose, Eigen::Vector3d* gradient, Eigen::Matrix3d* hessian) {
  const int n = model.num_patches, size = 2 * n;
  double s, c;
  pmath::SinCos(pose.theta_rad, &s, &c);
  std::array<double, kMax> e{}, jt{}, second{};  // residual, d/dtheta, d2/dtheta2 of the model
  for (int i = 0; i < n; ++i) {
    const Vec2& p = model.model_mm[i];
    const double a = c * p.x() - s * p.y(), b = s * p.x() + c * p.y();
    e[2 * i] = pose.x_mm + a - observed[i].x();
    e[2 * i + 1] = pose.y_mm + b - observed[i].y();
    jt[2 * i] = -b;
    jt[2 * i + 1] = a;
    second[2 * i] = -a;
    second[2 * i + 1] = -b;
  }
  double cost = 0.0;
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (int k = 0; k < size; ++k) {
    double we = 0.0, wx = 0.0, wy = 0.0, wt = 0.0;  // row k of W times e, jx, jy, jt
    for (int l = 0; l < size; ++l) {
      const double wkl = w(k, l);
      we += wkl * e[l];
      wt += wkl * jt[l];
      if (l % 2 == 0) {
        wx += wkl;
      } else {
        wy += wkl;
      }
    }
    cost += e[k] * we;
    const double jx = k % 2 == 0 ? 1.0 : 0.0, jy = 1.0 - jx;
    g += 2.0 * we * Eigen::Vector3d(jx, jy, jt[k]);
    h.row(0) += 2.0 * jx * Eigen::RowVector3d(wx, wy, wt);
    h.row(1) += 2.0 * jy * Eigen::RowVector3d(wx, wy, wt);
    h.row(2) += 2.0 * jt[k] * Eigen::RowVector3d(wx, wy, wt);
    h(2, 2) += 2.0 * we * second[k];
  }
  *gradient = g;
  *hessian = h;
  return cost;
}

// The Newton step -H^-1 g, with H damped (Levenberg 1944) until positive definite; false if
// no damping helps.
bool NewtonStep(const Eigen::Matrix3d& h, const Eigen::Vector3d& g, Eigen::Vector3d* step) {
  double lambda = 0.0;
  for (int tries = 0; tries < 60; ++tries) {
    const Eigen::LLT<Eigen::Matrix3d> llt(h + lambda * Eigen::Matrix3d::Identity());
    if (llt.info() == Eigen::Success) {
      *step = -llt.solve(g);
      return step->allFinite();
    }
    lambda = lambda == 0.0 ? 1e-6 * (std::abs(h.trace()) + 1.0) : 10.0 * lambda;
  }
  return false;
}

}  // namespace

GaussianWeights GaussianWeights::Make(const Model& model, const GaussianNoise& noise) {
  std::array<double, kMax * kMax> l;
  FactorCovariance(model, noise, l);
  GaussianWeights w;
  w.size = 2 * model.num_patches;
  // Column j of A^-1: solve L y = e_j, then L^T x = y.
  for (int j = 0; j < w.size; ++j) {
    std::array<double, kMax> y{};
    for (int i = 0; i < w.size; ++i) {
      double v = i == j ? 1.0 : 0.0;
      for (int k = 0; k < i; ++k) v -= l[i * kMax + k] * y[k];
      y[i] = v / l[i * kMax + i];
    }
    for (int i = w.size - 1; i >= 0; --i) {
      double v = y[i];
      for (int k = i + 1; k < w.size; ++k) v -= l[k * kMax + i] * w.inverse[k * kMax + j];
      w.inverse[i * kMax + j] = v / l[i * kMax + i];
    }
  }
  return w;
}

double MahalanobisCost(const Model& model, const GaussianWeights& weights, const Vec2* observed,
                       const Pose2& pose) {
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  return CostDerivatives(model, weights, observed, pose, &g, &h);
}

Pose2 GeneralisedLeastSquares(const Model& model, const GaussianWeights& weights,
                              const Vec2* observed, const Pose2& start, const Options& options,
                              Summary* summary) {
  Summary local;
  Summary& sum = summary != nullptr ? *summary : local;
  sum = Summary{};
  sum.termination = Termination::kMaxIterations;
  Pose2 r = start;
  Eigen::Vector3d g, step;
  Eigen::Matrix3d h;
  sum.initial_cost = CostDerivatives(model, weights, observed, r, &g, &h);
  for (int it = 0; it < options.max_iterations; ++it) {
    if (it > 0) CostDerivatives(model, weights, observed, r, &g, &h);
    if (!g.allFinite() || !h.allFinite()) {
      sum.termination = Termination::kNumericalFailure;
      break;
    }
    if (g.norm() <= options.gradient_tolerance) {
      sum.termination = Termination::kConverged;
      break;
    }
    if (!NewtonStep(h, g, &step)) {
      sum.termination = Termination::kNumericalFailure;
      break;
    }
    if (internal::TakeNewtonStep(step, options, &r, &sum)) break;
  }
  r.theta_rad = WrapAngle(r.theta_rad);
  sum.final_cost = MahalanobisCost(model, weights, observed, r);
  if (!std::isfinite(sum.final_cost)) sum.termination = Termination::kNumericalFailure;
  return r;
}

Eigen::Matrix3d GaussianInformation(const Model& model, const GaussianWeights& weights,
                                    double theta_rad) {
  // The information is the Gauss-Newton half of the Hessian at zero residual: observe the exact
  // patches of the pose and take CostDerivatives' Hessian / 2.
  const Pose2 pose{0.0, 0.0, theta_rad};
  std::array<Vec2, kMaxPatches> exact{};
  for (int i = 0; i < model.num_patches; ++i) exact[i] = pose.Apply(model.model_mm[i]);
  Eigen::Vector3d g;
  Eigen::Matrix3d h;
  CostDerivatives(model, weights, exact.data(), pose, &g, &h);
  return h / 2.0;
}

StdPerSigma GaussianCramerRaoBound(const Model& model, const GaussianWeights& weights) {
  constexpr int kHeadings = 256;
  double position = 0.0, theta = 0.0;
  for (int k = 0; k < kHeadings; ++k) {
    const double heading = 2.0 * std::numbers::pi * k / kHeadings;
    const Eigen::Matrix3d covariance = GaussianInformation(model, weights, heading).inverse();
    position += (covariance(0, 0) + covariance(1, 1)) / 2.0;
    theta += covariance(2, 2);
  }
  return {std::sqrt(position / kHeadings), std::sqrt(theta / kHeadings)};
}

}  // namespace patlab::estimate
