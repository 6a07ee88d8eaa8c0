#include "patlab/estimate/bounds.h"

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <numbers>

#include "patlab/estimate/robust.h"

namespace patlab::estimate {

StdPerSigma CramerRaoBound(const Model& model) {
  // Fisher information of (x, y, theta) for v_i = R p_i + t + e_i, e_i ~ N(0, sigma^2 I):
  // inverting it gives var(theta) = sigma^2 / S with S = sum |p_i - pbar|^2, and the origin
  // covariance sigma^2 (I / n + (dR/dtheta pbar)(dR/dtheta pbar)^T / S), whose per-axis average
  // over heading is sigma^2 (1/n + |pbar|^2 / (2 S)).
  const double n = model.num_patches;
  const double s = model.spread_mm2;
  StdPerSigma bound;
  bound.theta = 1.0 / std::sqrt(s);
  bound.position_per_axis = std::sqrt(1.0 / n + model.centroid_mm.squaredNorm() / (2.0 * s));
  return bound;
}

namespace {

Pose2 Run(const Model& model, Estimator estimator, const Vec2* observed) {
  switch (estimator) {
    case Estimator::kFast:
      return Fast(model, observed);
    case Estimator::kLsq:
      return LeastSquares(model, observed);
    case Estimator::kKey:
      return KeyPatch(model, observed);
    case Estimator::kRobust:  // at these small perturbations every Huber weight is 1
      return Robust(model, observed, RobustModel{}, nullptr);
    case Estimator::kMl: {
      Options options;
      options.max_iterations = 50;
      return MaximumLikelihood(model, observed, Fast(model, observed), options, nullptr);
    }
  }
  return {};
}

}  // namespace

StdPerSigma PredictedStd(const Model& model, Estimator estimator) {
  // C = J J^T with J the estimator's Jacobian at the identity pose (EstimatorJacobian: central
  // differences of the estimator itself), summed column by column in patch-coordinate order.
  const PoseJacobian jacobian = EstimatorJacobian(model, estimator);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int j = 0; j < 2 * model.num_patches; ++j) {
    const Eigen::Vector3d column = jacobian.col(j);
    covariance += column * column.transpose();
  }
  // Isotropic noise is rotation invariant, so at heading phi the world covariance of the origin
  // is R(phi) C R(phi)^T; its per-axis variance averaged over phi is trace(C) / 2.
  StdPerSigma predicted;
  predicted.position_per_axis = std::sqrt((covariance(0, 0) + covariance(1, 1)) / 2.0);
  predicted.theta = std::sqrt(covariance(2, 2));
  return predicted;
}

PoseJacobian EstimatorJacobian(const Model& model, Estimator estimator) {
  constexpr double kStepMm = 1e-3;
  const int n = model.num_patches;
  std::array<Vec2, kMaxPatches> observed = model.model_mm;
  PoseJacobian jacobian = PoseJacobian::Zero();
  for (int j = 0; j < 2 * n; ++j) {
    double& coordinate = observed[j / 2][j % 2];
    const double original = coordinate;
    coordinate = original + kStepMm;
    const Pose2 plus = Run(model, estimator, observed.data());
    coordinate = original - kStepMm;
    const Pose2 minus = Run(model, estimator, observed.data());
    coordinate = original;
    jacobian.col(j) << (plus.x_mm - minus.x_mm) / (2.0 * kStepMm),
        (plus.y_mm - minus.y_mm) / (2.0 * kStepMm),
        WrapAngle(plus.theta_rad - minus.theta_rad) / (2.0 * kStepMm);
  }
  return jacobian;
}

StdPerSigma PredictedStdCorrelated(const Model& model, Estimator estimator, double length_mm) {
  const int n = model.num_patches;
  const PoseJacobian g = EstimatorJacobian(model, estimator);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double d = (model.model_mm[i] - model.model_mm[j]).norm();
      const double c = length_mm > 0.0 ? std::exp(-d / length_mm) : (i == j ? 1.0 : 0.0);
      for (int axis = 0; axis < 2; ++axis) {
        covariance += c * g.col(2 * i + axis) * g.col(2 * j + axis).transpose();
      }
    }
  }
  StdPerSigma predicted;
  predicted.position_per_axis = std::sqrt((covariance(0, 0) + covariance(1, 1)) / 2.0);
  predicted.theta = std::sqrt(covariance(2, 2));
  return predicted;
}

BiasSpread ShiftSpread(const Model& model, Estimator estimator, const double* shift_x_mm) {
  constexpr int kHeadings = 64;
  const int n = model.num_patches;
  const PoseJacobian g = EstimatorJacobian(model, estimator);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum2 = Eigen::Vector3d::Zero();
  for (int h = 0; h < kHeadings; ++h) {
    const double phi = 2.0 * std::numbers::pi * h / kHeadings;
    const double c = std::cos(phi), s = std::sin(phi);
    Eigen::Matrix<double, 2 * kMaxPatches, 1> local =
        Eigen::Matrix<double, 2 * kMaxPatches, 1>::Zero();
    for (int i = 0; i < n; ++i) {  // R(-phi) (b_i, 0)
      local(2 * i) = c * shift_x_mm[i];
      local(2 * i + 1) = -s * shift_x_mm[i];
    }
    const Eigen::Vector3d e = g * local;
    const Eigen::Vector3d world(c * e(0) - s * e(1), s * e(0) + c * e(1), e(2));
    sum += world;
    sum2 += world.cwiseProduct(world);
  }
  const Eigen::Vector3d mean = sum / kHeadings;
  const Eigen::Vector3d variance = (sum2 / kHeadings - mean.cwiseProduct(mean)).cwiseMax(0.0);
  BiasSpread spread;
  spread.std.position_per_axis = std::sqrt((variance(0) + variance(1)) / 2.0);
  spread.std.theta = std::sqrt(variance(2));
  spread.mean_position_mm = Vec2(mean(0), mean(1));
  return spread;
}

}  // namespace patlab::estimate
