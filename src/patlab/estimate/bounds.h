// Accuracy predictions from the geometry alone: the Cramer-Rao bound and each estimator's
// first-order (small sigma) standard deviation.
#pragma once

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

}  // namespace patlab::estimate
