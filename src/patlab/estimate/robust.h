// The outlier-robust pose ("robust"): the maximum of the outlier mixture's own likelihood when
// the noise model has outliers, a Huber M-estimator otherwise.
//
// Outlier mixture (sim/noise.h): each patch error is N(0, sigma^2 I) with probability 1 - p and
// N(0, k^2 sigma^2 I) with probability p. Its likelihood is maximised by EM (Dempster, Laird and
// Rubin 1977), which here is iteratively reweighted least squares: with gamma_i the posterior
// probability that patch i is an inlier at the current pose, the M-step is the weighted
// Procrustes fit with weights w_i = gamma_i + (1 - gamma_i) / k^2 (every step raises the
// likelihood). EM finds the maximum nearest its start, so it starts from the most likely of the
// least-squares fit and the n leave-one-out fits (a single outlier never spoils them all).
//
// Without outliers in the model: Huber's M-estimator (Huber 1964) on the 2-D residual norm,
// rho(r) = r^2 / 2 for r <= c, c r - c^2 / 2 beyond, r = |residual| / sigma, with c = 2.5 (in
// units of sigma: under isotropic Gaussian noise 4.4% of patches lie beyond it, and the loss of
// efficiency against least squares is below 1%), by IRLS with weights min(1, c / r) from the
// least-squares fit. Both are pure functions on small fixed-size data and never allocate.
#pragma once

#include "patlab/core/geometry.h"
#include "patlab/estimate/estimators.h"

namespace patlab::estimate {

struct RobustModel {
  double sigma_mm = 1.0;                       // inlier per-axis std (mm), > 0
  double outlier_probability = 0.0;            // p in [0, 1); 0: Huber
  double outlier_sigma_ratio = 10.0;           // k > 0: an outlier's std / sigma_mm
  static constexpr double kHuberTuning = 2.5;  // c, in units of sigma_mm
  bool IsMixture() const { return outlier_probability > 0.0; }
};

// Pose by a weighted least-squares fit: minimises sum w_i |R p_i + t - v_i|^2 in closed form
// (weighted centroids, then the 2-D Procrustes angle). Patches of zero weight are ignored.
Pose2 WeightedLeastSquares(const Model& model, const Vec2* observed, const double* weights);

// The objective the robust estimator maximises, at `pose`: the mixture's log-likelihood (up to a
// constant), or minus the Huber loss sum rho(|e_i| / sigma).
double RobustObjective(const Model& model, const Vec2* observed, const RobustModel& robust,
                       const Pose2& pose);

// The robust pose. Converged when a step moves the pose by less than 1e-9 mm and 1e-11 rad, at
// most 200 steps. `summary` may be null; its costs are minus RobustObjective.
Pose2 Robust(const Model& model, const Vec2* observed, const RobustModel& robust, Summary* summary);

}  // namespace patlab::estimate
