// Maximum likelihood under Gaussian patch noise of known covariance (generalised least squares)
// and its Cramer-Rao bound.
//
// The observed patches v_i = R(theta) p_i + t + e_i have errors e, stacked (x_0, y_0, x_1, y_1,
// ...), that are jointly Gaussian with covariance sigma^2 A, A known up to the scale sigma:
//
//   A = C (x) diag(1, r^2) + g^2 (1 1^T) (x) I_2
//
// with r = sigma_y_ratio (world-frame anisotropy), C_ij = exp(-|p_i - p_j| / L) the correlation
// between patches (L = correlation_length_mm; C = I when L = 0) and g = common_sigma_ratio (an
// offset shared by every patch): the Gaussian part of sim/noise.h. The likelihood is maximal
// where the Mahalanobis cost e^T A^-1 e is least, whatever sigma; A does not depend on the pose
// (anisotropy is in the world frame, C on model distances only), so its inverse is computed once
// per pattern and noise model (GaussianWeights) and every trial only runs Newton's method.
#pragma once

#include <Eigen/Core>
#include <array>

#include "patlab/core/geometry.h"
#include "patlab/estimate/bounds.h"
#include "patlab/estimate/estimators.h"

namespace patlab::estimate {

// The Gaussian part of a noise model, per unit sigma (names as sim::NoiseModel's fields).
struct GaussianNoise {
  double sigma_y_ratio = 1.0;          // > 0
  double correlation_length_mm = 0.0;  // >= 0; 0: independent patches
  double common_sigma_ratio = 0.0;     // >= 0
  // True when least squares is already the maximum-likelihood estimator: r = 1 and no
  // correlation. (A common offset alone lies in the span of the translation columns of the
  // Jacobian, so GLS and OLS coincide: Kruskal 1968, "When are Gauss-Markov and least squares
  // estimators identical?".)
  bool IsLeastSquares() const { return sigma_y_ratio == 1.0 && correlation_length_mm == 0.0; }
};

// A^-1 for a pattern and noise model, row-major 2n x 2n in a fixed array (no allocation per
// trial). Built by a Cholesky factorisation of A and two triangular solves per column.
struct GaussianWeights {
  static constexpr int kMax = 2 * kMaxPatches;
  int size = 0;                               // 2n
  std::array<double, kMax * kMax> inverse{};  // A^-1 (symmetric)
  static GaussianWeights Make(const Model& model, const GaussianNoise& noise);
  double operator()(int i, int j) const { return inverse[i * kMax + j]; }
};

// The Mahalanobis cost e^T A^-1 e of `pose` (mm^2 per unit sigma^2; with A = I it is E).
double MahalanobisCost(const Model& model, const GaussianWeights& weights, const Vec2* observed,
                       const Pose2& pose);

// The pose that minimises the Mahalanobis cost, by Newton's method with the exact Hessian (and
// Levenberg damping where it is indefinite) from `start` (normally LeastSquares()), the step and
// gradient tolerances of `options` as estimate::MaximumLikelihood. `summary` may be null; its
// costs are Mahalanobis costs.
Pose2 GeneralisedLeastSquares(const Model& model, const GaussianWeights& weights,
                              const Vec2* observed, const Pose2& start, const Options& options,
                              Summary* summary);

// Fisher information of (x, y, theta) at heading theta per unit 1/sigma^2: J^T A^-1 J with J the
// Jacobian of the stacked patch positions (translation-independent).
Eigen::Matrix3d GaussianInformation(const Model& model, const GaussianWeights& weights,
                                    double theta_rad);

// The Cramer-Rao bound per unit sigma for poses of uniformly random heading: sigma^2 times the
// inverse information, its per-axis position variance ((x + y) / 2) and theta variance averaged
// over 256 equally spaced headings (the integrand is smooth and periodic, so this trapezoid rule
// is exact to rounding), square-rooted. With A = I it is CramerRaoBound(model).
StdPerSigma GaussianCramerRaoBound(const Model& model, const GaussianWeights& weights);

}  // namespace patlab::estimate
