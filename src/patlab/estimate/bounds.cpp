#include "patlab/estimate/bounds.h"

#include <Eigen/Core>
#include <cmath>

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
  // Jacobian of (x, y, theta) with respect to the 2n patch coordinates at the identity pose,
  // by central differences of the estimator itself (its error is O(h^2) relative).
  constexpr double kStepMm = 1e-3;
  const int n = model.num_patches;
  std::array<Vec2, kMaxPatches> observed = model.model_mm;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (int j = 0; j < 2 * n; ++j) {
    double& coordinate = observed[j / 2][j % 2];
    const double original = coordinate;
    coordinate = original + kStepMm;
    const Pose2 plus = Run(model, estimator, observed.data());
    coordinate = original - kStepMm;
    const Pose2 minus = Run(model, estimator, observed.data());
    coordinate = original;
    const Eigen::Vector3d column((plus.x_mm - minus.x_mm) / (2.0 * kStepMm),
                                 (plus.y_mm - minus.y_mm) / (2.0 * kStepMm),
                                 WrapAngle(plus.theta_rad - minus.theta_rad) / (2.0 * kStepMm));
    covariance += column * column.transpose();
  }
  // Isotropic noise is rotation invariant, so at heading phi the world covariance of the origin
  // is R(phi) C R(phi)^T; its per-axis variance averaged over phi is trace(C) / 2.
  StdPerSigma predicted;
  predicted.position_per_axis = std::sqrt((covariance(0, 0) + covariance(1, 1)) / 2.0);
  predicted.theta = std::sqrt(covariance(2, 2));
  return predicted;
}

}  // namespace patlab::estimate
