#include "patlab/sim/noise.h"

#include <cmath>

namespace patlab::sim {

double NoiseModel::EffectiveSigmaRatio() const {
  const double p = outlier_probability;
  const double inlier = (1.0 + sigma_y_ratio * sigma_y_ratio) / 2.0;
  return std::sqrt((1.0 - p) * inlier + p * outlier_sigma_ratio * outlier_sigma_ratio);
}

std::string NoiseModel::Describe() const {
  std::string name = sigma_y_ratio == 1.0 ? "isotropic" : "anisotropic";
  if (common_sigma_ratio > 0.0) name += "+common";
  if (outlier_probability > 0.0) name += "+outliers";
  if (correlation_length_mm > 0.0) name += "+correlated";
  if (key_shift_x_mm != 0.0 || id_shift_x_mm != 0.0) name += "+colour-bias";
  if (rotation_jitter_rad > 0.0) name += "+rotation-jitter";
  if (scale_jitter_ppm > 0.0) name += "+scale-jitter";
  return name;
}

std::vector<OptionsProblem> Check(const NoiseModel& noise) {
  const double p = noise.outlier_probability;
  OptionsChecker check;
  check.Positive("sigma_y_ratio", noise.sigma_y_ratio)
      .NonNegative("common_sigma_ratio", noise.common_sigma_ratio)
      .Require("outlier_probability", p, p >= 0.0 && p < 1.0, "a probability in [0, 1)")
      .Positive("outlier_sigma_ratio", noise.outlier_sigma_ratio)
      .InRange("rotation_jitter_rad", noise.rotation_jitter_rad, 0.0, 0.1, "rad")
      .InRange("scale_jitter_ppm", noise.scale_jitter_ppm, 0.0, 1e5, "ppm")
      .NonNegative("correlation_length_mm", noise.correlation_length_mm, "mm")
      .InRange("key_shift_x_mm", noise.key_shift_x_mm, -100.0, 100.0, "mm")
      .InRange("id_shift_x_mm", noise.id_shift_x_mm, -100.0, 100.0, "mm");
  return check.Take();
}

void Validate(const NoiseModel& noise) { ThrowFirstProblem(Check(noise)); }

Vec2 NoiseModel::PatchError(double sigma_mm, RandomStream& rng) const {
  const double zx = rng.Normal();
  const double zy = rng.Normal();
  if (outlier_probability > 0.0 && rng.Uniform() < outlier_probability) {
    return sigma_mm * outlier_sigma_ratio * Vec2(zx, zy);
  }
  return sigma_mm * Vec2(zx, sigma_y_ratio * zy);
}

Vec2 NoiseModel::CommonOffset(double sigma_mm, RandomStream& rng) const {
  if (!(common_sigma_ratio > 0.0 && sigma_mm > 0.0)) return Vec2::Zero();
  const double zx = rng.Normal();
  const double zy = rng.Normal();
  return sigma_mm * common_sigma_ratio * Vec2(zx, zy);
}

}  // namespace patlab::sim
