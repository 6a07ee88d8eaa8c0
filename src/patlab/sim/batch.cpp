// The Monte-Carlo kernel: every stage is a plain loop over the trials of the batch that GCC
// vectorises at whatever width the target has. Its transcendentals are patlab's own
// (core/portable_math.h), in plain IEEE arithmetic, and the file is compiled like the rest of
// patlab (no -ffast-math, no fused multiply-add contraction): a trial's numbers are then the same
// bits on every x86-64 CPU, whatever vector width the loops were given (docs/architecture.md,
// "Same bytes on every machine"). Nothing here relies on NaN or infinity: inputs are validated
// before they reach the kernel, and the few trials whose Newton iteration needs care are re-run
// by the reference estimator.
#include "patlab/sim/batch.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "patlab/core/portable_math.h"
#include "patlab/core/rng.h"

namespace patlab::sim {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kB = kBatchSize;

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

thread_local Scratch scratch;

inline double Wrap(double d) {  // for d in (-2 pi, 2 pi)
  d = d > kPi ? d - 2.0 * kPi : d;
  return d <= -kPi ? d + 2.0 * kPi : d;
}

// Philox block `block` of the m trials starting at t0 (a batch never crosses a multiple of
// 2^32 trials, so the high counter word is constant), as documented in batch.h.
void Blocks(const PointSetup& s, uint64_t t0, int m, uint32_t block, Scratch& w) {
  for (int k = 0; k < m; ++k) w.counter[k] = static_cast<uint32_t>(t0) + static_cast<uint32_t>(k);
  PhiloxBatch(s.seed, w.counter, static_cast<uint32_t>(t0 >> 32), s.point, block, m, w.words[0],
              w.words[1], w.words[2], w.words[3]);
}

// Box-Muller standard normals (zx, zy) for the m trials from two words per trial, one
// transcendental per loop.
void Normals(const uint32_t* radius_word, const uint32_t* angle_word, int m, Scratch& w) {
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
void TruePoses(const PointSetup& s, uint64_t t0, int m, Scratch& w) {
  Blocks(s, t0, m, 0, w);
  for (int k = 0; k < m; ++k) {
    w.true_x[k] = (UniformOpen01(w.words[0][k]) - 0.5) * s.field_length_mm;
    w.true_y[k] = (UniformOpen01(w.words[1][k]) - 0.5) * s.field_width_mm;
    w.true_t[k] = kPi * (2.0 * UniformOpen01(w.words[2][k]) - 1.0);
  }
  for (int k = 0; k < m; ++k) pmath::SinCos(w.true_t[k], &w.true_s[k], &w.true_c[k]);
}

// The common-mode offset of each trial (block first_common_block), or zero.
void CommonOffsets(const PointSetup& s, uint64_t t0, int m, uint32_t first_common_block,
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
void ScalePatchNormals(const PointSetup& s, uint64_t t0, int m, int i, uint32_t first_common_block,
                       Scratch& w) {
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
void CorrelationFactor(const estimate::Model& model, double length_mm,
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
void MixCorrelated(const PointSetup& s, int m, Scratch& w) {
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
void ShiftColours(const PointSetup& s, int m, Scratch& w) {
  const estimate::Model& model = *s.model;
  for (int i = 0; i < model.num_patches; ++i) {
    const double dx = i == model.key_index ? s.noise.key_shift_x_mm : s.noise.id_shift_x_mm;
    for (int k = 0; k < m; ++k) w.ox[i][k] += dx;
  }
}

// Camera jitter: every patch of trial k rotated by phi_k and scaled by 1 + eps_k about the world
// origin; phi, eps from block `block` (words 0, 1, Box-Muller).
void CameraJitter(const PointSetup& s, uint64_t t0, int m, uint32_t block, Scratch& w) {
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
void Generate(const PointSetup& s, uint64_t t0, int m, Scratch& w) {
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

// Errors of the pose (origin = mean - R(t) centroid-like point `ref`, angle t given by c, s).
void WriteErrors(const double* anchor_x, const double* anchor_y, const Vec2& ref, const double* t,
                 const double* c, const double* s, int m, const Scratch& w,
                 const ErrorArrays& out) {
  const double rx = ref.x(), ry = ref.y();
  for (int k = 0; k < m; ++k) {
    out.x_mm[k] = anchor_x[k] - (c[k] * rx - s[k] * ry) - w.true_x[k];
    out.y_mm[k] = anchor_y[k] - (s[k] * rx + c[k] * ry) - w.true_y[k];
    out.theta_rad[k] = Wrap(t[k] - w.true_t[k]);
  }
}

// Stage 2: the paper's fast estimator (kept in w.fast_* for ml and key).
void Fast(const PointSetup& s, int m, Scratch& w) {
  const estimate::Model& model = *s.model;
  const int n = model.num_patches;
  for (int k = 0; k < m; ++k) w.mean_x[k] = w.mean_y[k] = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < m; ++k) {
      w.mean_x[k] += w.ox[i][k];
      w.mean_y[k] += w.oy[i][k];
    }
  }
  const double inv_n = 1.0 / n;
  for (int k = 0; k < m; ++k) {
    w.mean_x[k] *= inv_n;
    w.mean_y[k] *= inv_n;
    w.sum_a[k] = w.sum_b[k] = 0.0;
  }
  for (int j = 0; j < model.num_pairs; ++j) {
    const double* fx = w.ox[model.pair_from[j]];
    const double* fy = w.oy[model.pair_from[j]];
    const double* tx = w.ox[model.pair_to[j]];
    const double* ty = w.oy[model.pair_to[j]];
    const double c = model.pair_cos[j], sn = model.pair_sin[j];
    for (int k = 0; k < m; ++k) {
      const double dx = tx[k] - fx[k], dy = ty[k] - fy[k];
      w.sum_a[k] += c * dx + sn * dy;
      w.sum_b[k] += -sn * dx + c * dy;
    }
  }
  for (int k = 0; k < m; ++k) w.fast_t[k] = pmath::Atan2(w.sum_b[k], w.sum_a[k]);
  for (int k = 0; k < m; ++k) pmath::SinCos(w.fast_t[k], &w.fast_s[k], &w.fast_c[k]);
}

// The closed-form least-squares fit (2-D Procrustes).
void LeastSquares(const PointSetup& s, int m, Scratch& w, const ErrorArrays& out) {
  const estimate::Model& model = *s.model;
  for (int k = 0; k < m; ++k) w.sum_a[k] = w.sum_b[k] = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const double qx = model.model_mm[i].x() - model.centroid_mm.x();
    const double qy = model.model_mm[i].y() - model.centroid_mm.y();
    for (int k = 0; k < m; ++k) {
      const double wx = w.ox[i][k] - w.mean_x[k], wy = w.oy[i][k] - w.mean_y[k];
      w.sum_a[k] += qx * wx + qy * wy;
      w.sum_b[k] += qx * wy - qy * wx;
    }
  }
  for (int k = 0; k < m; ++k) w.est_t[k] = pmath::Atan2(w.sum_b[k], w.sum_a[k]);
  for (int k = 0; k < m; ++k) pmath::SinCos(w.est_t[k], &w.est_s[k], &w.est_c[k]);
  WriteErrors(w.mean_x, w.mean_y, model.centroid_mm, w.est_t, w.est_c, w.est_s, m, w, out);
}

// Newton's method on the sum-squared error, every trial of the batch in lock step, from the fast
// estimate: the iteration of estimate::MaximumLikelihood, with the paper's gradient and the
// exact Hessian evaluated through per-trial sums. With u_i = v_i - mean(v) and the origin
// (x, y) measured from mean(v), a_i = c p_ix - s p_iy, b_i = s p_ix + c p_iy, A = sum a_i,
// B = sum b_i, D = sum u_i . p_i, C = sum p_i x u_i, the paper's sums reduce to
//   dE/dx = 2 (n x + A)          dE/dy = 2 (n y + B)        dE/dtheta = 2 (y A - x B + s D - c C)
//   d2E/dxdtheta = -2 B          d2E/dydtheta = 2 A         d2E/dtheta2 = 2 (c D + s C - x A - y B)
// (expand x_i = x + a_i - u_ix, y_i = y + b_i - u_iy and use sum a_i (-b_i) + b_i a_i = 0), so
// an iteration costs O(1) per trial instead of O(n). Trials that need the Levenberg damping or
// do not converge are re-run by the reference estimator, whose Summary is then reported.
// The per-trial sums D and C (in w.sum_a, w.sum_b), fixed during the iteration, and the start:
// the fast estimate with its origin measured from mean(v).
void StartNewton(const estimate::Model& model, int m, Scratch& w) {
  for (int k = 0; k < m; ++k) w.sum_a[k] = w.sum_b[k] = 0.0;
  for (int i = 0; i < model.num_patches; ++i) {
    const double px = model.model_mm[i].x(), py = model.model_mm[i].y();
    for (int k = 0; k < m; ++k) {
      const double ux = w.ox[i][k] - w.mean_x[k], uy = w.oy[i][k] - w.mean_y[k];
      w.sum_a[k] += ux * px + uy * py;
      w.sum_b[k] += px * uy - py * ux;
    }
  }
  const Vec2 pbar = model.centroid_mm;
  for (int k = 0; k < m; ++k) {
    w.ml_x[k] = -(w.fast_c[k] * pbar.x() - w.fast_s[k] * pbar.y());
    w.ml_y[k] = -(w.fast_s[k] * pbar.x() + w.fast_c[k] * pbar.y());
    w.ml_t[k] = w.fast_t[k];
    w.active[k] = 1.0;
    w.needs_reference[k] = 0.0;
    w.iterations[k] = 0.0;
  }
}

// Newton steps until every trial has stopped (gradient or step tolerance, an indefinite
// Hessian, or max_iterations).
void NewtonSteps(const estimate::Model& model, const estimate::Options& o, int m, Scratch& w) {
  const int n = model.num_patches;
  double px_sum = 0.0, py_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    px_sum += model.model_mm[i].x();
    py_sum += model.model_mm[i].y();
  }
  const double dn = n, two_n = 2.0 * n;
  const double grad_tol2 = o.gradient_tolerance * o.gradient_tolerance;
  // A step is small when max(|dx|, |dy|) / tol_mm and |dtheta| / tol_rad are <= 1.
  const double inv_tol_mm = 1.0 / std::max(o.step_tolerance_mm, 1e-300);
  const double inv_tol_rad = 1.0 / std::max(o.step_tolerance_rad, 1e-300);
  for (int it = 0; it < o.max_iterations; ++it) {
    for (int k = 0; k < m; ++k) pmath::SinCos(w.ml_t[k], &w.est_s[k], &w.est_c[k]);
    double any_active = 0.0;
    for (int k = 0; k < m; ++k) {
      const double c = w.est_c[k], sn = w.est_s[k];
      const double x = w.ml_x[k], y = w.ml_y[k];
      const double d = w.sum_a[k], cr = w.sum_b[k];
      const double big_a = c * px_sum - sn * py_sum, big_b = sn * px_sum + c * py_sum;
      const double gx = 2.0 * (dn * x + big_a);
      const double gy = 2.0 * (dn * y + big_b);
      const double gt = 2.0 * (y * big_a - x * big_b + sn * d - c * cr);
      const double hxt = -2.0 * big_b, hyt = 2.0 * big_a;
      const double htt = 2.0 * (c * d + sn * cr - x * big_a - y * big_b);
      // Branch-free (0/1 doubles) so that the loop vectorises.
      const double a = w.active[k];
      const double at_minimum = gx * gx + gy * gy + gt * gt <= grad_tol2 ? 1.0 : 0.0;
      const double schur = htt - (hxt * hxt + hyt * hyt) / two_n;
      const double indefinite = schur > 0.0 ? 0.0 : 1.0;
      const double st = -(gt - (hxt * gx + hyt * gy) / two_n) / (schur > 0.0 ? schur : 1.0);
      const double sx = -(gx + hxt * st) / two_n;
      const double sy = -(gy + hyt * st) / two_n;
      const double take = a * (1.0 - at_minimum) * (1.0 - indefinite);
      w.ml_x[k] = x + take * sx;
      w.ml_y[k] = y + take * sy;
      w.ml_t[k] += take * st;
      w.iterations[k] += take;
      const double step =
          std::max(std::max(std::abs(sx), std::abs(sy)) * inv_tol_mm, std::abs(st) * inv_tol_rad);
      const double small = step <= 1.0 ? 1.0 : 0.0;
      w.needs_reference[k] += a * (1.0 - at_minimum) * indefinite;
      w.active[k] = a * (1.0 - std::max(std::max(at_minimum, indefinite), small));
      any_active += w.active[k];
    }
    if (any_active == 0.0) break;
  }
}

// Rare: the Hessian was indefinite or max_iterations was reached. The reference estimator
// decides trial k, and its Summary is what the results report.
void ReferenceTrial(const estimate::Model& model, const estimate::Options& o, int k,
                    const Scratch& w, const ErrorArrays& out, uint8_t* iterations_out,
                    uint8_t* termination_out) {
  std::array<Vec2, kMaxPatches> observed;
  for (int i = 0; i < model.num_patches; ++i) observed[i] = Vec2(w.ox[i][k], w.oy[i][k]);
  const Pose2 start = estimate::Fast(model, observed.data());
  estimate::Summary summary;
  const Pose2 pose = estimate::MaximumLikelihood(model, observed.data(), start, o, &summary);
  out.x_mm[k] = pose.x_mm - w.true_x[k];
  out.y_mm[k] = pose.y_mm - w.true_y[k];
  out.theta_rad[k] = WrapAngle(pose.theta_rad - w.true_t[k]);
  iterations_out[k] = static_cast<uint8_t>(std::min(summary.iterations, 255));
  termination_out[k] = static_cast<uint8_t>(summary.termination);
}

// Newton's method on the sum-squared error, every trial of the batch in lock step, from the fast
// estimate: the iteration of estimate::MaximumLikelihood, with the paper's gradient and the
// exact Hessian evaluated through per-trial sums. With u_i = v_i - mean(v) and the origin
// (x, y) measured from mean(v), a_i = c p_ix - s p_iy, b_i = s p_ix + c p_iy, A = sum a_i,
// B = sum b_i, D = sum u_i . p_i, C = sum p_i x u_i, the paper's sums reduce to
//   dE/dx = 2 (n x + A)          dE/dy = 2 (n y + B)        dE/dtheta = 2 (y A - x B + s D - c C)
//   d2E/dxdtheta = -2 B          d2E/dydtheta = 2 A         d2E/dtheta2 = 2 (c D + s C - x A - y B)
// (expand x_i = x + a_i - u_ix, y_i = y + b_i - u_iy and use sum a_i (-b_i) + b_i a_i = 0), so
// an iteration costs O(1) per trial instead of O(n). Trials that need the Levenberg damping or
// do not converge are re-run by the reference estimator, whose Summary is then reported.
void MaximumLikelihood(const PointSetup& s, int m, Scratch& w, const ErrorArrays& out,
                       uint8_t* iterations_out, uint8_t* termination_out) {
  const estimate::Model& model = *s.model;
  StartNewton(model, m, w);
  NewtonSteps(model, s.ml_options, m, w);
  for (int k = 0; k < m; ++k) {
    w.ml_x[k] += w.mean_x[k];
    w.ml_y[k] += w.mean_y[k];
    w.est_t[k] = w.ml_t[k];
  }
  for (int k = 0; k < m; ++k) pmath::SinCos(w.est_t[k], &w.est_s[k], &w.est_c[k]);
  const Vec2 zero = Vec2::Zero();
  WriteErrors(w.ml_x, w.ml_y, zero, w.est_t, w.est_c, w.est_s, m, w, out);
  for (int k = 0; k < m; ++k) {
    iterations_out[k] = static_cast<uint8_t>(w.iterations[k]);
    termination_out[k] = static_cast<uint8_t>(estimate::Termination::kConverged);
    if (w.active[k] == 0.0 && w.needs_reference[k] == 0.0) continue;
    ReferenceTrial(model, s.ml_options, k, w, out, iterations_out, termination_out);
  }
}

// RunBatch's stages in one function, compiled once per instruction set below.
inline void RunBatchStages(const PointSetup& setup, uint64_t first_trial, int count,
                           const BatchOutput& out) {
  Scratch& w = scratch;
  const int m = count;
  // Always a whole batch of patch positions, so that GenerateTrial reproduces them lane for lane.
  Generate(setup, first_trial, kB, w);
  using estimate::Estimator;
  const estimate::Model& model = *setup.model;
  // With no estimator to run (sim_bench's floor: the cost of the noisy inputs alone), stop here.
  if (!setup.run[0] && !setup.run[1] && !setup.run[2] && !setup.run[3]) return;
  Fast(setup, m, w);
  if (setup.run[static_cast<int>(Estimator::kFast)]) {
    WriteErrors(w.mean_x, w.mean_y, model.centroid_mm, w.fast_t, w.fast_c, w.fast_s, m, w,
                out.errors[static_cast<int>(Estimator::kFast)]);
  }
  if (setup.run[static_cast<int>(Estimator::kKey)]) {
    const int key = model.key_index;
    WriteErrors(w.ox[key], w.oy[key], model.model_mm[key], w.fast_t, w.fast_c, w.fast_s, m, w,
                out.errors[static_cast<int>(Estimator::kKey)]);
  }
  if (setup.run[static_cast<int>(Estimator::kLsq)]) {
    LeastSquares(setup, m, w, out.errors[static_cast<int>(Estimator::kLsq)]);
  }
  if (setup.run[static_cast<int>(Estimator::kMl)]) {
    MaximumLikelihood(setup, m, w, out.errors[static_cast<int>(Estimator::kMl)], out.ml_iterations,
                      out.ml_termination);
  }
}

}  // namespace

// The kernel for the baseline x86-64 (SSE2: two trials a vector), x86-64-v3 (AVX2: four) and
// x86-64-v4 (AVX-512: eight), every stage inlined into each (flatten). Wider vectors only run
// more trials at once: without fused multiply-add (-ffp-contract=off) and with patlab's own
// transcendentals every lane computes the same operations in the same order, so every version
// gives the same bits (tests/sim/batch_test.cpp runs each one the CPU has). clang builds (the
// sanitizer build) have the baseline version only.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define PATLAB_KERNEL_ISA_VERSIONS 1
#else
#define PATLAB_KERNEL_ISA_VERSIONS 0
#endif

namespace {

__attribute__((flatten)) void RunBatchBaseline(const PointSetup& setup, uint64_t first_trial,
                                               int count, const BatchOutput& out) {
  RunBatchStages(setup, first_trial, count, out);
}

#if PATLAB_KERNEL_ISA_VERSIONS
__attribute__((flatten, target("arch=x86-64-v3"))) void RunBatchAvx2(const PointSetup& setup,
                                                                     uint64_t first_trial,
                                                                     int count,
                                                                     const BatchOutput& out) {
  RunBatchStages(setup, first_trial, count, out);
}

__attribute__((flatten, target("arch=x86-64-v4"))) void RunBatchAvx512(const PointSetup& setup,
                                                                       uint64_t first_trial,
                                                                       int count,
                                                                       const BatchOutput& out) {
  RunBatchStages(setup, first_trial, count, out);
}
#endif

}  // namespace

KernelIsa WidestKernelIsa() {
#if PATLAB_KERNEL_ISA_VERSIONS
  if (__builtin_cpu_supports("x86-64-v4")) return KernelIsa::kAvx512;
  if (__builtin_cpu_supports("x86-64-v3")) return KernelIsa::kAvx2;
#endif
  return KernelIsa::kBaseline;
}

std::vector<KernelIsa> SupportedKernelIsas() {
  std::vector<KernelIsa> isas;
  for (KernelIsa isa : {KernelIsa::kBaseline, KernelIsa::kAvx2, KernelIsa::kAvx512}) {
    if (isa <= WidestKernelIsa()) isas.push_back(isa);
  }
  return isas;
}

void RunBatchWith(KernelIsa isa, const PointSetup& setup, uint64_t first_trial, int count,
                  const BatchOutput& out) {
  switch (isa) {
#if PATLAB_KERNEL_ISA_VERSIONS
    case KernelIsa::kAvx512:
      return RunBatchAvx512(setup, first_trial, count, out);
    case KernelIsa::kAvx2:
      return RunBatchAvx2(setup, first_trial, count, out);
#endif
    default:
      return RunBatchBaseline(setup, first_trial, count, out);
  }
}

void RunBatch(const PointSetup& setup, uint64_t first_trial, int count, const BatchOutput& out) {
  static const KernelIsa widest = WidestKernelIsa();  // no allocation: the inner loop (rule 7)
  RunBatchWith(widest, setup, first_trial, count, out);
}

void GenerateTrial(const PointSetup& setup, uint64_t trial, Pose2* truth, Vec2* observed) {
  // Generate the whole aligned batch the trial belongs to, exactly as RunBatch does.
  const uint64_t first = trial - trial % kBatchSize;
  const int slot = static_cast<int>(trial - first);
  Scratch& w = scratch;
  Generate(setup, first, kB, w);
  *truth = Pose2{w.true_x[slot], w.true_y[slot], w.true_t[slot]};
  for (int i = 0; i < setup.model->num_patches; ++i) {
    observed[i] = Vec2(w.ox[i][slot], w.oy[i][slot]);
  }
}

}  // namespace patlab::sim
