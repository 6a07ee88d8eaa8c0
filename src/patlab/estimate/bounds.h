// Accuracy predictions from the geometry alone: the Cramer-Rao bound and each estimator's
// first-order (small sigma) standard deviation.
#pragma once

#include <Eigen/Core>

#include "patlab/core/pattern.h"
#include "patlab/estimate/estimators.h"

namespace patlab::estimate {

// Standard deviations per unit patch sigma (multiply by sigma in mm). Position is the per-axis
// world std of the reported origin, averaged over a uniformly random heading.
struct StdPerSigma {
  double position_per_axis = 0.0;  // mm per mm of patch sigma
  double theta = 0.0;              // rad per mm of patch sigma
};

// Cramer-Rao bound for iid isotropic Gaussian patch noise sigma on n patches (Fisher information
// of (x, y, theta)): sigma_theta >= sigma / sqrt(sum |p_i - pbar|^2); the origin's per-axis std
// >= sigma * sqrt(1/n + |pbar|^2 / (2 sum |p_i - pbar|^2)) averaged over heading.
StdPerSigma CramerRaoBound(const Model& model);

// First-order predicted std of an estimator: the estimator is linearised about the noise-free
// patches (central differences of the real code, so the prediction describes what runs), and
// the covariance G G^T is averaged over heading. Exact as sigma -> 0 for any patch noise with
// per-axis variance sigma^2 that is independent between patches.
StdPerSigma PredictedStd(const Model& model, Estimator estimator);

// The estimator's Jacobian at the identity pose: d(x, y, theta) / d(patch coordinates), column
// 2i the patch i's x, column 2i + 1 its y (central differences of the real code, as above); the
// columns beyond 2n are zero. The first-order error of any small patch perturbation d is G d.
using PoseJacobian = Eigen::Matrix<double, 3, 2 * kMaxPatches>;
PoseJacobian EstimatorJacobian(const Model& model, Estimator estimator);

// First-order std per unit sigma for patch errors correlated between patches, independent
// between the axes, per-axis covariance sigma^2 C with C_ij = exp(-|p_i - p_j| / length_mm)
// (sim/noise.h): cov = G_x C G_x^T + G_y C G_y^T, averaged over heading as above (C (x) I is
// rotation invariant). length_mm -> 0 gives PredictedStd.
StdPerSigma PredictedStdCorrelated(const Model& model, Estimator estimator, double length_mm);

// The spread over a uniformly random heading of the error that fixed world-frame patch shifts
// cause (shift_x_mm[i] along x for patch i): at heading phi the error is R(phi) G R(-phi) b to
// first order; returned are its std over phi (position pooled per axis) and its mean position
// error. Evaluated on 64 equally spaced headings, exact for these trigonometric polynomials.
struct BiasSpread {
  StdPerSigma std;  // here in mm and rad, not per sigma
  Vec2 mean_position_mm = Vec2::Zero();
};
BiasSpread ShiftSpread(const Model& model, Estimator estimator, const double* shift_x_mm);

}  // namespace patlab::estimate
