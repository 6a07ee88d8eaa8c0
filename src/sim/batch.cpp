// Compiled with -O3 -ffast-math (src/sim/CMakeLists.txt) so that GCC vectorises log, sqrt, sin,
// cos and atan2 through glibc's libmvec. Every stage is a plain loop over the trials of the
// batch; sin and cos of one angle are computed in separate loops because GCC 12 will not
// vectorise a loop that needs both. Fast-math may reassociate sums, which changes results only
// between builds, never between thread counts (the batch layout is fixed). Nothing here relies on
// NaN or infinity: inputs are validated before they reach the kernel, and the few trials whose
// Newton iteration needs care are re-run by the reference estimator (compiled without
// fast-math).
#include "sim/batch.h"

#include <cmath>
#include <numbers>

#include "core/rng.h"

namespace patlab::sim {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kB = kBatchSize;

struct Scratch {
  alignas(64) double ox[kMaxPatches][kB];  // observed patch positions
  alignas(64) double oy[kMaxPatches][kB];
  alignas(64) double true_x[kB], true_y[kB], true_t[kB], true_c[kB], true_s[kB];
  alignas(64) double u1[kB], u2[kB], radius[kB], zx[kB], zy[kB];
  alignas(64) double common_x[kB], common_y[kB];
  alignas(64) double mean_x[kB], mean_y[kB];
  alignas(64) double fast_t[kB], fast_c[kB], fast_s[kB];
  alignas(64) double sum_a[kB], sum_b[kB];
  alignas(64) double est_t[kB], est_c[kB], est_s[kB];
  // Newton state
  alignas(64) double ml_x[kB], ml_y[kB], ml_t[kB];
  alignas(64) double gx[kB], gy[kB], gt[kB], hxt[kB], hyt[kB], htt[kB];
  alignas(64) double active[kB];  // 1.0 while iterating, 0.0 once converged or handed over
  alignas(64) uint8_t needs_reference[kB];
  alignas(64) uint8_t iterations[kB];
};

thread_local Scratch scratch;

inline double Wrap(double d) {  // for d in (-2 pi, 2 pi)
  d = d > kPi ? d - 2.0 * kPi : d;
  return d <= -kPi ? d + 2.0 * kPi : d;
}

// Philox block of trial t of the point, as documented in batch.h.
inline std::array<uint32_t, 4> Block(const PointSetup& s, uint64_t trial, uint32_t block) {
  return PhiloxBlock(s.seed, static_cast<uint32_t>(trial), static_cast<uint32_t>(trial >> 32),
                     s.point, block);
}

// Standard normals (zx, zy) of `block` for the m trials starting at t0.
void Normals(const PointSetup& s, uint64_t t0, int m, uint32_t block, Scratch& w) {
  for (int k = 0; k < m; ++k) {
    const auto b = Block(s, t0 + k, block);
    w.u1[k] = UniformOpen01(b[0], b[1]);
    w.u2[k] = UniformOpen01(b[2], b[3]);
  }
  // Box-Muller, one transcendental per loop.
  for (int k = 0; k < m; ++k) w.radius[k] = std::sqrt(-2.0 * std::log(w.u1[k]));
  for (int k = 0; k < m; ++k) w.zx[k] = w.radius[k] * std::cos(2.0 * kPi * w.u2[k]);
  for (int k = 0; k < m; ++k) w.zy[k] = w.radius[k] * std::sin(2.0 * kPi * w.u2[k]);
}

// Stage 1: true poses and noisy patch positions.
void Generate(const PointSetup& s, uint64_t t0, int m, Scratch& w) {
  const estimate::Model& model = *s.model;
  const int n = model.num_patches;
  for (int k = 0; k < m; ++k) {
    const auto b0 = Block(s, t0 + k, 0);
    const auto b1 = Block(s, t0 + k, 1);
    w.true_x[k] = (UniformOpen01(b0[0], b0[1]) - 0.5) * s.field_length_mm;
    w.true_y[k] = (UniformOpen01(b0[2], b0[3]) - 0.5) * s.field_width_mm;
    w.true_t[k] = kPi * (2.0 * UniformOpen01(b1[0], b1[1]) - 1.0);
  }
  for (int k = 0; k < m; ++k) w.true_c[k] = std::cos(w.true_t[k]);
  for (int k = 0; k < m; ++k) w.true_s[k] = std::sin(w.true_t[k]);

  const double sigma_x = s.sigma_mm;
  const double sigma_y = s.sigma_mm * s.noise.sigma_y_ratio;
  const double sigma_out = s.sigma_mm * s.noise.outlier_sigma_ratio;
  const double p_out = s.noise.outlier_probability;

  if (s.noise.common_sigma_ratio > 0.0) {
    Normals(s, t0, m, 2 + n, w);
    const double g = s.sigma_mm * s.noise.common_sigma_ratio;
    for (int k = 0; k < m; ++k) {
      w.common_x[k] = g * w.zx[k];
      w.common_y[k] = g * w.zy[k];
    }
  } else {
    for (int k = 0; k < m; ++k) w.common_x[k] = w.common_y[k] = 0.0;
  }

  for (int i = 0; i < n; ++i) {
    const double px = model.model_mm[i].x(), py = model.model_mm[i].y();
    double* ox = w.ox[i];
    double* oy = w.oy[i];
    if (s.sigma_mm > 0.0) {
      Normals(s, t0, m, 2 + i, w);
    } else {
      for (int k = 0; k < m; ++k) w.zx[k] = w.zy[k] = 0.0;
    }
    if (p_out > 0.0) {
      // Outlier selection: uniform (2 words) for patch i from block 3 + n + i / 2.
      for (int k = 0; k < m; ++k) {
        const auto b = Block(s, t0 + k, 3 + n + i / 2);
        const double u = (i % 2 == 0) ? UniformOpen01(b[0], b[1]) : UniformOpen01(b[2], b[3]);
        const bool outlier = u < p_out;
        w.zx[k] *= outlier ? sigma_out : sigma_x;
        w.zy[k] *= outlier ? sigma_out : sigma_y;
      }
    } else {
      for (int k = 0; k < m; ++k) {
        w.zx[k] *= sigma_x;
        w.zy[k] *= sigma_y;
      }
    }
    for (int k = 0; k < m; ++k) {
      ox[k] = w.true_x[k] + w.true_c[k] * px - w.true_s[k] * py + w.zx[k] + w.common_x[k];
      oy[k] = w.true_y[k] + w.true_s[k] * px + w.true_c[k] * py + w.zy[k] + w.common_y[k];
    }
  }
}

// Errors of the pose (origin = mean - R(t) centroid-like point `ref`, angle t given by c, s).
void WriteErrors(const double* anchor_x, const double* anchor_y, const Vec2& ref,
                 const double* t, const double* c, const double* s, int m, const Scratch& w,
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
  for (int k = 0; k < m; ++k) w.fast_t[k] = std::atan2(w.sum_b[k], w.sum_a[k]);
  for (int k = 0; k < m; ++k) w.fast_c[k] = std::cos(w.fast_t[k]);
  for (int k = 0; k < m; ++k) w.fast_s[k] = std::sin(w.fast_t[k]);
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
  for (int k = 0; k < m; ++k) w.est_t[k] = std::atan2(w.sum_b[k], w.sum_a[k]);
  for (int k = 0; k < m; ++k) w.est_c[k] = std::cos(w.est_t[k]);
  for (int k = 0; k < m; ++k) w.est_s[k] = std::sin(w.est_t[k]);
  WriteErrors(w.mean_x, w.mean_y, model.centroid_mm, w.est_t, w.est_c, w.est_s, m, w, out);
}

// Newton's method on the sum-squared error, every trial of the batch in lock step, from the fast
// estimate. The same iteration as estimate::MaximumLikelihood; trials that need the Levenberg
// damping or do not converge are re-run by it, so its Summary is what gets reported.
void MaximumLikelihood(const PointSetup& s, int m, Scratch& w,
                       const ErrorArrays& out, uint8_t* iterations_out,
                       uint8_t* termination_out) {
  const estimate::Model& model = *s.model;
  const estimate::Options& o = s.ml_options;
  const int n = model.num_patches;
  const Vec2 pbar = model.centroid_mm;
  for (int k = 0; k < m; ++k) {
    w.ml_x[k] = w.mean_x[k] - (w.fast_c[k] * pbar.x() - w.fast_s[k] * pbar.y());
    w.ml_y[k] = w.mean_y[k] - (w.fast_s[k] * pbar.x() + w.fast_c[k] * pbar.y());
    w.ml_t[k] = w.fast_t[k];
    w.active[k] = 1.0;
    w.needs_reference[k] = 0;
    w.iterations[k] = 0;
  }
  int it = 0;
  for (; it < o.max_iterations; ++it) {
    for (int k = 0; k < m; ++k) w.est_c[k] = std::cos(w.ml_t[k]);
    for (int k = 0; k < m; ++k) w.est_s[k] = std::sin(w.ml_t[k]);
    for (int k = 0; k < m; ++k) w.gx[k] = w.gy[k] = w.gt[k] = w.hxt[k] = w.hyt[k] = w.htt[k] = 0.0;
    for (int i = 0; i < n; ++i) {
      const double px = model.model_mm[i].x(), py = model.model_mm[i].y();
      const double* vx = w.ox[i];
      const double* vy = w.oy[i];
      for (int k = 0; k < m; ++k) {
        const double c = w.est_c[k], sn = w.est_s[k];
        const double xi = w.ml_x[k] + c * px - sn * py - vx[k];
        const double yi = w.ml_y[k] + sn * px + c * py - vy[k];
        const double dx = -sn * px - c * py;
        const double dy = c * px - sn * py;
        w.gx[k] += 2.0 * xi;
        w.gy[k] += 2.0 * yi;
        w.gt[k] += 2.0 * (xi * dx + yi * dy);
        w.hxt[k] += 2.0 * dx;
        w.hyt[k] += 2.0 * dy;
        w.htt[k] += 2.0 * (dx * dx + dy * dy) - 2.0 * (xi * dy - yi * dx);
      }
    }
    const double two_n = 2.0 * n;
    double any_active = 0.0;
    for (int k = 0; k < m; ++k) {
      const double a = w.active[k];
      const double g2 = w.gx[k] * w.gx[k] + w.gy[k] * w.gy[k] + w.gt[k] * w.gt[k];
      const bool at_minimum = g2 <= o.gradient_tolerance * o.gradient_tolerance;
      const double schur = w.htt[k] - (w.hxt[k] * w.hxt[k] + w.hyt[k] * w.hyt[k]) / two_n;
      const bool indefinite = !(schur > 0.0);
      const double safe_schur = indefinite ? 1.0 : schur;
      const double st = -(w.gt[k] - (w.hxt[k] * w.gx[k] + w.hyt[k] * w.gy[k]) / two_n) / safe_schur;
      const double sx = -(w.gx[k] + w.hxt[k] * st) / two_n;
      const double sy = -(w.gy[k] + w.hyt[k] * st) / two_n;
      const bool take_step = a > 0.0 && !at_minimum && !indefinite;
      const double g = take_step ? 1.0 : 0.0;
      w.ml_x[k] += g * sx;
      w.ml_y[k] += g * sy;
      w.ml_t[k] += g * st;
      w.iterations[k] += take_step ? 1 : 0;
      const bool small = std::abs(sx) <= o.step_tolerance_mm &&
                         std::abs(sy) <= o.step_tolerance_mm && std::abs(st) <= o.step_tolerance_rad;
      w.needs_reference[k] |= (a > 0.0 && !at_minimum && indefinite) ? 1 : 0;
      const bool done = a > 0.0 && (at_minimum || indefinite || small);
      w.active[k] = done ? 0.0 : a;
      any_active += w.active[k];
    }
    if (any_active == 0.0) break;
  }
  for (int k = 0; k < m; ++k) w.est_t[k] = w.ml_t[k];
  for (int k = 0; k < m; ++k) w.est_c[k] = std::cos(w.est_t[k]);
  for (int k = 0; k < m; ++k) w.est_s[k] = std::sin(w.est_t[k]);
  const Vec2 zero = Vec2::Zero();
  WriteErrors(w.ml_x, w.ml_y, zero, w.est_t, w.est_c, w.est_s, m, w, out);
  for (int k = 0; k < m; ++k) {
    iterations_out[k] = w.iterations[k];
    termination_out[k] = static_cast<uint8_t>(estimate::Termination::kConverged);
    if (w.active[k] == 0.0 && w.needs_reference[k] == 0) continue;
    // Rare: the Hessian was indefinite or max_iterations was reached. The reference estimator
    // decides, and its Summary is what the results report.
    std::array<Vec2, kMaxPatches> observed;
    for (int i = 0; i < n; ++i) observed[i] = Vec2(w.ox[i][k], w.oy[i][k]);
    const Pose2 start = estimate::Fast(model, observed.data());
    estimate::Summary summary;
    const Pose2 pose =
        estimate::MaximumLikelihood(model, observed.data(), start, o, &summary);
    out.x_mm[k] = pose.x_mm - w.true_x[k];
    out.y_mm[k] = pose.y_mm - w.true_y[k];
    out.theta_rad[k] = WrapAngle(pose.theta_rad - w.true_t[k]);
    iterations_out[k] = static_cast<uint8_t>(std::min(summary.iterations, 255));
    termination_out[k] = static_cast<uint8_t>(summary.termination);
  }
}

}  // namespace

void RunBatch(const PointSetup& setup, uint64_t first_trial, int count, const BatchOutput& out) {
  Scratch& w = scratch;
  const int m = count;
  // Always a whole batch of patch positions, so that GenerateTrial reproduces them lane for lane.
  Generate(setup, first_trial, kB, w);
  using estimate::Estimator;
  const estimate::Model& model = *setup.model;
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
    MaximumLikelihood(setup, m, w, out.errors[static_cast<int>(Estimator::kMl)],
                      out.ml_iterations, out.ml_termination);
  }
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
