// First-order predictions of an estimator's error std under the whole noise model (noise.h),
// known-correspondence mode: each mechanism's variance, added (they are independent, and their
// cross terms are of second order in the small errors).
//
//   independent patch noise   (sigma rho P)^2, P = estimate::PredictedStd per unit sigma, rho =
//                             NoiseModel::EffectiveSigmaRatio (PredictedStdCorrelated when
//                             correlation_length_mm > 0)
//   common offset             (sigma g)^2 on position only (translation equivariance)
//   rotation jitter phi       theta: sigma_phi^2 (every estimator is rotation equivariant, the
//                             angle moves by phi exactly); origin T moves by phi J T, per axis
//                             sigma_phi^2 E|T|^2 / 2 with E|T|^2 = (length^2 + width^2) / 12 for
//                             poses uniform over the field centred on the camera axis
//   scale jitter eps          theta: 0 (scaling leaves directions unchanged); the origin moves
//                             by eps (T + R pbar), per axis sigma_eps^2 (E|T|^2 + |pbar|^2) / 2
//   colour-edge bias          its spread over heading (estimate::ShiftSpread): a fixed world
//                             shift of some patches rotates with the pattern into a different
//                             pose error at each heading
#pragma once

#include <optional>

#include "patlab/estimate/bounds.h"
#include "patlab/estimate/estimators.h"
#include "patlab/sim/noise.h"

namespace patlab::sim {

struct PredictedError {
  double position_mm = 0.0;  // per-axis std of the reported origin, pooled over x and y
  double theta_rad = 0.0;
};

// The prediction at patch sigma `sigma_mm` for poses uniform over a field_length_mm x
// field_width_mm field centred on the camera axis with uniform heading (the known-mode trials,
// batch.h).
PredictedError PredictError(const estimate::Model& model, estimate::Estimator estimator,
                            const NoiseModel& noise, double sigma_mm, double field_length_mm,
                            double field_width_mm);

// The Cramer-Rao bound per unit sigma under `noise` where patlab has one: the closed form for the
// isotropic Gaussian (estimate::CramerRaoBound, the paper's model), the Fisher information
// J^T A^-1 J of every other Gaussian model (estimate::GaussianCramerRaoBound), the outlier
// mixture's exact bound when the inliers are the isotropic Gaussian
// (estimate::MixtureCramerRaoBound); nullopt for the rest (outliers on top of another model,
// camera roll and scale jitter, colour-edge bias).
std::optional<estimate::StdPerSigma> NoiseCramerRaoBound(const estimate::Model& model,
                                                         const NoiseModel& noise);

// True when "ml" is generalised least squares under `noise` (estimate/gls.h): its first-order
// covariance is then the inverse information, the bound itself, when the noise is Gaussian, and
// patlab makes no first-order prediction for it otherwise (NaN).
inline bool MlIsGeneralised(const NoiseModel& noise) {
  return !noise.GaussianPart().IsLeastSquares();
}

}  // namespace patlab::sim
