#include "patlab/sim/noise.h"

#include <cmath>

#include "patlab/core/portable_math.h"

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

FrameCameraNoise::FrameCameraNoise(const NoiseModel& noise, const std::vector<Vec2>& positions_mm,
                                   int key_index, RandomStream& rng)
    : noise_(noise), num_patches_(static_cast<int>(positions_mm.size())), key_index_(key_index) {
  const int n = num_patches_;
  if (noise.correlation_length_mm > 0.0) {
    // Cholesky-Banachiewicz on C_ij = exp(-|p_i - p_j| / L), row by row: exp(-d / L) is positive
    // definite for distinct points in the plane, so every pivot is > 0 (a coincident pair would
    // give 0, clamped, and the patch then repeats its neighbour's error).
    factor_.assign(static_cast<size_t>(n) * n, 0.0);
    auto l = [this, n](int i, int j) -> double& { return factor_[static_cast<size_t>(i) * n + j]; };
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j <= i; ++j) {
        double v =
            pmath::Exp(-(positions_mm[i] - positions_mm[j]).norm() / noise.correlation_length_mm);
        for (int k = 0; k < j; ++k) v -= l(i, k) * l(j, k);
        if (i == j) {
          l(i, i) = v > 0.0 ? std::sqrt(v) : 0.0;
        } else {
          l(i, j) = l(j, j) > 0.0 ? v / l(j, j) : 0.0;
        }
      }
    }
  }
  independent_.resize(static_cast<size_t>(n));
  const double phi =
      noise.rotation_jitter_rad > 0.0 ? noise.rotation_jitter_rad * rng.Normal() : 0.0;
  const double eps =
      noise.scale_jitter_ppm > 0.0 ? 1e-6 * noise.scale_jitter_ppm * rng.Normal() : 0.0;
  double sin_phi, cos_phi;
  pmath::SinCos(phi, &sin_phi, &cos_phi);
  cos_ = (1.0 + eps) * cos_phi;
  sin_ = (1.0 + eps) * sin_phi;
}

Vec2 FrameCameraNoise::Next(const Vec2& base_mm, const Vec2& independent_mm) {
  const int i = next_;
  next_ = (next_ + 1) % num_patches_;
  independent_[static_cast<size_t>(i)] = independent_mm;
  Vec2 error = independent_mm;
  if (!factor_.empty()) {
    error = Vec2::Zero();
    for (int j = 0; j <= i; ++j) {
      error +=
          factor_[static_cast<size_t>(i) * num_patches_ + j] * independent_[static_cast<size_t>(j)];
    }
  }
  Vec2 v = base_mm + error;
  v.x() += i == key_index_ ? noise_.key_shift_x_mm : noise_.id_shift_x_mm;
  return {cos_ * v.x() - sin_ * v.y(), sin_ * v.x() + cos_ * v.y()};
}

}  // namespace patlab::sim
