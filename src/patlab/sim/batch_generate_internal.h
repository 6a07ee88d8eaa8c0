// The Monte-Carlo kernel's first stage (sim/batch.cpp): the true poses and the noisy patch
// positions of a batch, with the block layout of batch.h, every step a plain loop over the
// trials. Included by batch.cpp only, whose ISA versions inline these functions into each
// version of the kernel (so they are defined here, inline, not compiled on their own).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "patlab/core/portable_math.h"
#include "patlab/core/rng.h"
#include "patlab/sim/batch.h"

namespace patlab::sim::batch_internal {

inline constexpr double kPi = std::numbers::pi;
inline constexpr int kB = kBatchSize;

struct Scratch {
  alignas(64) double ox[kMaxPatches][kB];  // observed patch positions
  alignas(64) double oy[kMaxPatches][kB];
  alignas(64) double true_x[kB], true_y[kB], true_t[kB], true_c[kB], true_s[kB];
  alignas(64) uint32_t counter[kB];   // low word of each trial's Philox counter
  alignas(64) uint32_t words[4][kB];  // one Philox block per trial
  alignas(64) uint32_t saved[2][kB];
  alignas(64) double u1[kB], u2[kB], radius[kB], zx[kB], zy[kB];
  alignas(64) double common_x[kB], common_y[kB];
  alignas(64) double ex[kMaxPatches][kB];  // independent patch errors before correlation
  alignas(64) double ey[kMaxPatches][kB];
  alignas(64) double mean_x[kB], mean_y[kB];
  alignas(64) double fast_t[kB], fast_c[kB], fast_s[kB];
  alignas(64) double sum_a[kB], sum_b[kB];
  alignas(64) double est_t[kB], est_c[kB], est_s[kB];
  // Newton state
  alignas(64) double ml_x[kB], ml_y[kB], ml_t[kB];
  alignas(64) double active[kB];           // 1.0 while iterating, 0.0 once stopped
  alignas(64) double needs_reference[kB];  // > 0: hand the trial to the reference estimator
  alignas(64) double iterations[kB];       // Newton steps taken (doubles keep the loop vector)
};

// out[k] = WrapAngle(in[k]) (core/portable_math.h), exact for any finite angle: the branch-free
// form in a loop that vectorises, then the rare angles beyond its range (a diverging Newton
// iteration) one by one. `in` and `out` do not overlap.
inline void WrapAngles(const double* in, double* out, int m) {
  for (int k = 0; k < m; ++k) out[k] = pmath::WrapAngleNear(in[k]);
  for (int k = 0; k < m; ++k) {
    if (!(std::abs(in[k]) < pmath::kWrapNearLimit)) out[k] = pmath::WrapAngleFar(in[k]);
  }
}

// Philox block `block` of the m trials starting at t0 (a batch never crosses a multiple of
// 2^32 trials, so the high counter word is constant), as documented in batch.h.
inline void Blocks(const PointSetup& s, uint64_t t0, int m, uint32_t block, Scratch& w) {
  for (int k = 0; k < m; ++k) w.counter[k] = static_cast<uint32_t>(t0) + static_cast<uint32_t>(k);
  PhiloxBatch(s.seed, w.counter, static_cast<uint32_t>(t0 >> 32), s.point, block, m, w.words[0],
              w.words[1], w.words[2], w.words[3]);
}

// Box-Muller standard normals (zx, zy) for the m trials from two words per trial, one
// transcendental per loop.
inline void Normals(const uint32_t* radius_word, const uint32_t* angle_word, int m, Scratch& w) {
  for (int k = 0; k < m; ++k) w.u1[k] = UniformOpen01(radius_word[k]);
  for (int k = 0; k < m; ++k) w.u2[k] = 2.0 * kPi * UniformOpen01(angle_word[k]);
  for (int k = 0; k < m; ++k) w.radius[k] = std::sqrt(-2.0 * pmath::Log(w.u1[k]));
  for (int k = 0; k < m; ++k) {
    double sin_u2, cos_u2;
    pmath::SinCos(w.u2[k], &sin_u2, &cos_u2);
    w.zx[k] = w.radius[k] * cos_u2;
    w.zy[k] = w.radius[k] * sin_u2;
  }
}

// The true poses: uniform over the field and in (-pi, pi] (block 0), with cos and sin.
inline void TruePoses(const PointSetup& s, uint64_t t0, int m, Scratch& w) {
  Blocks(s, t0, m, 0, w);
  for (int k = 0; k < m; ++k) {
    w.true_x[k] = (UniformOpen01(w.words[0][k]) - 0.5) * s.field_length_mm;
    w.true_y[k] = (UniformOpen01(w.words[1][k]) - 0.5) * s.field_width_mm;
    w.true_t[k] = kPi * (2.0 * UniformOpen01(w.words[2][k]) - 1.0);
  }
  for (int k = 0; k < m; ++k) pmath::SinCos(w.true_t[k], &w.true_s[k], &w.true_c[k]);
}

// The common-mode offset of each trial (block first_common_block), or zero.
inline void CommonOffsets(const PointSetup& s, uint64_t t0, int m, uint32_t first_common_block,
                          Scratch& w) {
  if (!(s.noise.common_sigma_ratio > 0.0 && s.sigma_mm > 0.0)) {
    for (int k = 0; k < m; ++k) w.common_x[k] = w.common_y[k] = 0.0;
    return;
  }
  Blocks(s, t0, m, first_common_block, w);
  Normals(w.words[0], w.words[1], m, w);
  const double g = s.sigma_mm * s.noise.common_sigma_ratio;
  for (int k = 0; k < m; ++k) {
    w.common_x[k] = g * w.zx[k];
    w.common_y[k] = g * w.zy[k];
  }
}

// Patch i's standard normals (w.zx, w.zy) scaled to its error: sigma (x), sigma r (y), or an
// outlier's sigma k. Outlier selection of patch i: word i % 4 of block first_common_block + 1 +
// i / 4. The words of the normals' block are saved first: patch i + 1 still needs them.
inline void ScalePatchNormals(const PointSetup& s, uint64_t t0, int m, int i,
                              uint32_t first_common_block, Scratch& w) {
  const double sigma_x = s.sigma_mm;
  const double sigma_y = s.sigma_mm * s.noise.sigma_y_ratio;
  const double p_out = s.noise.outlier_probability;
  if (!(p_out > 0.0)) {
    for (int k = 0; k < m; ++k) {
      w.zx[k] *= sigma_x;
      w.zy[k] *= sigma_y;
    }
    return;
  }
  const double sigma_out = s.sigma_mm * s.noise.outlier_sigma_ratio;
  for (int k = 0; k < m; ++k) {
    w.saved[0][k] = w.words[2][k];
    w.saved[1][k] = w.words[3][k];
  }
  Blocks(s, t0, m, first_common_block + 1 + static_cast<uint32_t>(i / 4), w);
  const uint32_t* word = w.words[i % 4];
  for (int k = 0; k < m; ++k) {
    const bool outlier = UniformOpen01(word[k]) < p_out;
    w.zx[k] *= outlier ? sigma_out : sigma_x;
    w.zy[k] *= outlier ? sigma_out : sigma_y;
  }
  for (int k = 0; k < m; ++k) {
    w.words[2][k] = w.saved[0][k];
    w.words[3][k] = w.saved[1][k];
  }
}

// The lower Cholesky factor of C_ij = exp(-|p_i - p_j| / L) over the model positions (noise.h),
// row-major in a fixed array: computed per batch, a few hundred flops, no allocation (rule 7).
// exp(-d / L) is a positive definite kernel in the plane, so the factor exists for distinct
// patches; a non-positive pivot (coincident patches) is clamped to 0.
inline void CorrelationFactor(const estimate::Model& model, double length_mm,
                              std::array<double, kMaxPatches * kMaxPatches>& chol) {
  const int n = model.num_patches;
  chol.fill(0.0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) {
      double v = pmath::Exp(-(model.model_mm[i] - model.model_mm[j]).norm() / length_mm);
      for (int k = 0; k < j; ++k) v -= chol[i * kMaxPatches + k] * chol[j * kMaxPatches + k];
      if (i == j) {
        chol[i * kMaxPatches + i] = v > 0.0 ? std::sqrt(v) : 0.0;
      } else {
        const double pivot = chol[j * kMaxPatches + j];
        chol[i * kMaxPatches + j] = pivot > 0.0 ? v / pivot : 0.0;
      }
    }
  }
}

// Correlated noise: V_i += sum_j L_ij e'_j (e' saved in w.ex, w.ey by Generate).
inline void MixCorrelated(const PointSetup& s, int m, Scratch& w) {
  const estimate::Model& model = *s.model;
  std::array<double, kMaxPatches * kMaxPatches> chol;
  CorrelationFactor(model, s.noise.correlation_length_mm, chol);
  for (int i = 0; i < model.num_patches; ++i) {
    for (int j = 0; j <= i; ++j) {
      const double l = chol[i * kMaxPatches + j];
      for (int k = 0; k < m; ++k) {
        w.ox[i][k] += l * w.ex[j][k];
        w.oy[i][k] += l * w.ey[j][k];
      }
    }
  }
}

// Colour-edge bias: a fixed shift along x by the patch's colour class (key or ID).
inline void ShiftColours(const PointSetup& s, int m, Scratch& w) {
  const estimate::Model& model = *s.model;
  for (int i = 0; i < model.num_patches; ++i) {
    const double dx = i == model.key_index ? s.noise.key_shift_x_mm : s.noise.id_shift_x_mm;
    for (int k = 0; k < m; ++k) w.ox[i][k] += dx;
  }
}

// Camera jitter: every patch of trial k rotated by phi_k and scaled by 1 + eps_k about the world
// origin; phi, eps from block `block` (words 0, 1, Box-Muller).
inline void CameraJitter(const PointSetup& s, uint64_t t0, int m, uint32_t block, Scratch& w) {
  Blocks(s, t0, m, block, w);
  Normals(w.words[0], w.words[1], m, w);
  const double sigma_phi = s.noise.rotation_jitter_rad;
  const double sigma_eps = 1e-6 * s.noise.scale_jitter_ppm;
  // zx -> (1 + eps) cos(phi), zy -> (1 + eps) sin(phi); u1, u2 as scratch.
  for (int k = 0; k < m; ++k) {
    w.u1[k] = sigma_phi * w.zx[k];
    w.u2[k] = 1.0 + sigma_eps * w.zy[k];
  }
  for (int k = 0; k < m; ++k) {
    double sin_phi, cos_phi;
    pmath::SinCos(w.u1[k], &sin_phi, &cos_phi);
    w.zx[k] = w.u2[k] * cos_phi;
    w.zy[k] = w.u2[k] * sin_phi;
  }
  for (int i = 0; i < s.model->num_patches; ++i) {
    for (int k = 0; k < m; ++k) {
      const double x = w.ox[i][k], y = w.oy[i][k];
      w.ox[i][k] = w.zx[k] * x - w.zy[k] * y;
      w.oy[i][k] = w.zy[k] * x + w.zx[k] * y;
    }
  }
}

// Stage 1: true poses and noisy patch positions, with the block layout of batch.h.
inline void Generate(const PointSetup& s, uint64_t t0, int m, Scratch& w) {
  const estimate::Model& model = *s.model;
  const int n = model.num_patches;
  const uint32_t first_common_block = 1 + static_cast<uint32_t>((n + 1) / 2);
  const bool correlated = s.noise.correlation_length_mm > 0.0;
  TruePoses(s, t0, m, w);
  CommonOffsets(s, t0, m, first_common_block, w);
  for (int i = 0; i < n; ++i) {
    const double px = model.model_mm[i].x(), py = model.model_mm[i].y();
    double* ox = w.ox[i];
    double* oy = w.oy[i];
    if (s.sigma_mm > 0.0) {
      // Patches 2j and 2j + 1 share block 1 + j: words (0, 1) and (2, 3).
      if (i % 2 == 0) Blocks(s, t0, m, 1 + static_cast<uint32_t>(i / 2), w);
      Normals(w.words[i % 2 == 0 ? 0 : 2], w.words[i % 2 == 0 ? 1 : 3], m, w);
    } else {
      for (int k = 0; k < m; ++k) w.zx[k] = w.zy[k] = 0.0;
    }
    ScalePatchNormals(s, t0, m, i, first_common_block, w);
    if (correlated) {
      // Mixed in below, once every patch's independent error is known.
      std::copy_n(w.zx, m, w.ex[i]);
      std::copy_n(w.zy, m, w.ey[i]);
      for (int k = 0; k < m; ++k) w.zx[k] = w.zy[k] = 0.0;
    }
    for (int k = 0; k < m; ++k) {
      ox[k] = w.true_x[k] + w.true_c[k] * px - w.true_s[k] * py + w.zx[k] + w.common_x[k];
      oy[k] = w.true_y[k] + w.true_s[k] * px + w.true_c[k] * py + w.zy[k] + w.common_y[k];
    }
  }
  if (!s.noise.HasCameraModels()) return;
  if (correlated) MixCorrelated(s, m, w);
  if (s.noise.key_shift_x_mm != 0.0 || s.noise.id_shift_x_mm != 0.0) ShiftColours(s, m, w);
  if (s.noise.rotation_jitter_rad > 0.0 || s.noise.scale_jitter_ppm > 0.0) {
    const uint32_t outlier_blocks = static_cast<uint32_t>((n + 3) / 4);
    CameraJitter(s, t0, m, first_common_block + 1 + outlier_blocks, w);
  }
}

}  // namespace patlab::sim::batch_internal
