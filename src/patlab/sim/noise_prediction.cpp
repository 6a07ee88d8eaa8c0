#include "patlab/sim/noise_prediction.h"

#include <array>
#include <cmath>

#include "patlab/estimate/mixture_bound.h"

namespace patlab::sim {

PredictedError PredictError(const estimate::Model& model, estimate::Estimator estimator,
                            const NoiseModel& noise, double sigma_mm, double field_length_mm,
                            double field_width_mm) {
  const estimate::StdPerSigma independent =
      noise.correlation_length_mm > 0.0
          ? estimate::PredictedStdCorrelated(model, estimator, noise.correlation_length_mm)
          : estimate::PredictedStd(model, estimator);
  const double rho = noise.EffectiveSigmaRatio();
  const double g = noise.common_sigma_ratio;
  double var_pos =
      std::pow(sigma_mm * rho * independent.position_per_axis, 2) + std::pow(sigma_mm * g, 2);
  double var_theta = std::pow(sigma_mm * rho * independent.theta, 2);
  // E|T|^2 for T uniform over the field centred on the camera axis.
  const double mean_t2 =
      (field_length_mm * field_length_mm + field_width_mm * field_width_mm) / 12.0;
  const double phi = noise.rotation_jitter_rad;
  var_pos += phi * phi * mean_t2 / 2.0;
  var_theta += phi * phi;
  const double eps = 1e-6 * noise.scale_jitter_ppm;
  var_pos += eps * eps * (mean_t2 + model.centroid_mm.squaredNorm()) / 2.0;
  if (noise.key_shift_x_mm != 0.0 || noise.id_shift_x_mm != 0.0) {
    std::array<double, kMaxPatches> shift{};
    for (int i = 0; i < model.num_patches; ++i) {
      shift[i] = i == model.key_index ? noise.key_shift_x_mm : noise.id_shift_x_mm;
    }
    const estimate::BiasSpread bias = estimate::ShiftSpread(model, estimator, shift.data());
    var_pos += bias.std.position_per_axis * bias.std.position_per_axis;
    var_theta += bias.std.theta * bias.std.theta;
  }
  return {std::sqrt(var_pos), std::sqrt(var_theta)};
}

std::optional<estimate::StdPerSigma> NoiseCramerRaoBound(const estimate::Model& model,
                                                         const NoiseModel& noise) {
  if (noise.IsIsotropicGaussian()) return estimate::CramerRaoBound(model);
  NoiseModel inliers = noise;
  inliers.outlier_probability = 0.0;
  if (noise.outlier_probability > 0.0 && inliers.IsIsotropicGaussian()) {
    return estimate::MixtureCramerRaoBound(model, noise.outlier_probability,
                                           noise.outlier_sigma_ratio);
  }
  if (!noise.IsGaussian()) return std::nullopt;
  return estimate::GaussianCramerRaoBound(
      model, estimate::GaussianWeights::Make(model, noise.GaussianPart()));
}

}  // namespace patlab::sim
