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

#include "patlab/core/error.h"
#include "patlab/core/portable_math.h"
#include "patlab/sim/batch_generate_internal.h"

namespace patlab::sim {

namespace {

using namespace batch_internal;

thread_local Scratch scratch;

// The estimate (origin = anchor - R(t) ref for a point `ref` of the model, angle t in (-pi, pi]
// given with its c, s) and its error against the truth, theta wrapped (t and the true angle are
// both in (-pi, pi], so WrapAngleNear is exact on their difference).
void WriteErrors(const double* anchor_x, const double* anchor_y, const Vec2& ref, const double* t,
                 const double* c, const double* s, int m, const Scratch& w, const ErrorArrays& out,
                 const ErrorArrays& estimates) {
  const double rx = ref.x(), ry = ref.y();
  for (int k = 0; k < m; ++k) {
    const double x = anchor_x[k] - (c[k] * rx - s[k] * ry);
    const double y = anchor_y[k] - (s[k] * rx + c[k] * ry);
    out.x_mm[k] = x - w.true_x[k];
    out.y_mm[k] = y - w.true_y[k];
    out.theta_rad[k] = pmath::WrapAngleNear(t[k] - w.true_t[k]);
  }
  if (estimates.x_mm == nullptr) return;
  for (int k = 0; k < m; ++k) {
    estimates.x_mm[k] = anchor_x[k] - (c[k] * rx - s[k] * ry);
    estimates.y_mm[k] = anchor_y[k] - (s[k] * rx + c[k] * ry);
    estimates.theta_rad[k] = t[k];
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
  for (int k = 0; k < m; ++k)
    w.fast_t[k] = pmath::WrapAngleNear(pmath::Atan2(w.sum_b[k], w.sum_a[k]));
  for (int k = 0; k < m; ++k) pmath::SinCos(w.fast_t[k], &w.fast_s[k], &w.fast_c[k]);
}

// The closed-form least-squares fit (2-D Procrustes).
void LeastSquares(const PointSetup& s, int m, Scratch& w, const ErrorArrays& out,
                  const ErrorArrays& estimates) {
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
  for (int k = 0; k < m; ++k)
    w.est_t[k] = pmath::WrapAngleNear(pmath::Atan2(w.sum_b[k], w.sum_a[k]));
  for (int k = 0; k < m; ++k) pmath::SinCos(w.est_t[k], &w.est_s[k], &w.est_c[k]);
  WriteErrors(w.mean_x, w.mean_y, model.centroid_mm, w.est_t, w.est_c, w.est_s, m, w, out,
              estimates);
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

// One trial's pose written as WriteErrors writes it (the scalar estimators' poses are wrapped).
void WritePose(const Pose2& pose, int k, const Scratch& w, const ErrorArrays& out,
               const ErrorArrays& estimates) {
  out.x_mm[k] = pose.x_mm - w.true_x[k];
  out.y_mm[k] = pose.y_mm - w.true_y[k];
  out.theta_rad[k] = pmath::WrapAngleNear(pose.theta_rad - w.true_t[k]);
  if (estimates.x_mm == nullptr) return;
  estimates.x_mm[k] = pose.x_mm;
  estimates.y_mm[k] = pose.y_mm;
  estimates.theta_rad[k] = pose.theta_rad;
}

// Rare: the Hessian was indefinite or max_iterations was reached. The reference estimator
// decides trial k, and its Summary is what the results report.
void ReferenceTrial(const estimate::Model& model, const estimate::Options& o, int k,
                    const Scratch& w, const ErrorArrays& out, const ErrorArrays& estimates,
                    uint8_t* iterations_out, uint8_t* termination_out) {
  std::array<Vec2, kMaxPatches> observed;
  for (int i = 0; i < model.num_patches; ++i) observed[i] = Vec2(w.ox[i][k], w.oy[i][k]);
  const Pose2 start = estimate::Fast(model, observed.data());
  estimate::Summary summary;
  const Pose2 pose = estimate::MaximumLikelihood(model, observed.data(), start, o, &summary);
  WritePose(pose, k, w, out, estimates);
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
// The angle is wrapped before the error is taken: Newton's angle can leave (-pi, pi] by any
// number of turns (a trial far from the truth), and WrapAngles is exact for all of them.
void MaximumLikelihood(const PointSetup& s, int m, Scratch& w, const ErrorArrays& out,
                       const ErrorArrays& estimates, uint8_t* iterations_out,
                       uint8_t* termination_out) {
  const estimate::Model& model = *s.model;
  StartNewton(model, m, w);
  NewtonSteps(model, s.ml_options, m, w);
  for (int k = 0; k < m; ++k) {
    w.ml_x[k] += w.mean_x[k];
    w.ml_y[k] += w.mean_y[k];
  }
  WrapAngles(w.ml_t, w.est_t, m);
  // The origin is (ml_x, ml_y) itself: R(t) applied to the point 0 (c, s unused).
  const Vec2 zero = Vec2::Zero();
  WriteErrors(w.ml_x, w.ml_y, zero, w.est_t, w.est_t, w.est_t, m, w, out, estimates);
  for (int k = 0; k < m; ++k) {
    iterations_out[k] = static_cast<uint8_t>(w.iterations[k]);
    termination_out[k] = static_cast<uint8_t>(estimate::Termination::kConverged);
    if (w.active[k] == 0.0 && w.needs_reference[k] == 0.0) continue;
    ReferenceTrial(model, s.ml_options, k, w, out, estimates, iterations_out, termination_out);
  }
}

// "ml" under Gaussian noise that is not least squares (PointSetup::ml_weights): generalised least
// squares, trial by trial, from the least-squares pose.
void GeneralisedLeastSquares(const PointSetup& s, int m, const Scratch& w, const ErrorArrays& out,
                             const ErrorArrays& estimates, uint8_t* iterations_out,
                             uint8_t* termination_out) {
  const estimate::Model& model = *s.model;
  std::array<Vec2, kMaxPatches> observed;
  for (int k = 0; k < m; ++k) {
    for (int i = 0; i < model.num_patches; ++i) observed[i] = Vec2(w.ox[i][k], w.oy[i][k]);
    estimate::Summary summary;
    const Pose2 pose = estimate::GeneralisedLeastSquares(
        model, *s.ml_weights, observed.data(), estimate::LeastSquares(model, observed.data()),
        s.ml_options, &summary);
    WritePose(pose, k, w, out, estimates);
    iterations_out[k] = static_cast<uint8_t>(std::min(summary.iterations, 255));
    termination_out[k] = static_cast<uint8_t>(summary.termination);
  }
}

// "robust" (estimate/robust.h), trial by trial; its steps and termination per trial when the
// arrays are given.
void RobustTrials(const PointSetup& s, int m, const Scratch& w, const ErrorArrays& out,
                  const ErrorArrays& estimates, uint8_t* iterations_out, uint8_t* termination_out) {
  const estimate::Model& model = *s.model;
  std::array<Vec2, kMaxPatches> observed;
  for (int k = 0; k < m; ++k) {
    for (int i = 0; i < model.num_patches; ++i) observed[i] = Vec2(w.ox[i][k], w.oy[i][k]);
    estimate::Summary summary;
    WritePose(estimate::Robust(model, observed.data(), s.robust, &summary), k, w, out, estimates);
    if (iterations_out != nullptr) {
      iterations_out[k] = static_cast<uint8_t>(std::min(summary.iterations, 255));
      termination_out[k] = static_cast<uint8_t>(summary.termination);
    }
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
  if (std::none_of(std::begin(setup.run), std::end(setup.run), [](bool r) { return r; })) return;
  Fast(setup, m, w);
  const auto errors = [&out](Estimator e) { return out.errors[static_cast<int>(e)]; };
  const auto estimates = [&out](Estimator e) { return out.estimates[static_cast<int>(e)]; };
  if (setup.run[static_cast<int>(Estimator::kFast)]) {
    WriteErrors(w.mean_x, w.mean_y, model.centroid_mm, w.fast_t, w.fast_c, w.fast_s, m, w,
                errors(Estimator::kFast), estimates(Estimator::kFast));
  }
  if (setup.run[static_cast<int>(Estimator::kKey)]) {
    const int key = model.key_index;
    WriteErrors(w.ox[key], w.oy[key], model.model_mm[key], w.fast_t, w.fast_c, w.fast_s, m, w,
                errors(Estimator::kKey), estimates(Estimator::kKey));
  }
  if (setup.run[static_cast<int>(Estimator::kLsq)]) {
    LeastSquares(setup, m, w, errors(Estimator::kLsq), estimates(Estimator::kLsq));
  }
  if (setup.run[static_cast<int>(Estimator::kMl)] && setup.ml_weights != nullptr) {
    GeneralisedLeastSquares(setup, m, w, errors(Estimator::kMl), estimates(Estimator::kMl),
                            out.ml_iterations, out.ml_termination);
  } else if (setup.run[static_cast<int>(Estimator::kMl)]) {
    MaximumLikelihood(setup, m, w, errors(Estimator::kMl), estimates(Estimator::kMl),
                      out.ml_iterations, out.ml_termination);
  }
  if (setup.run[static_cast<int>(Estimator::kRobust)]) {
    RobustTrials(setup, m, w, errors(Estimator::kRobust), estimates(Estimator::kRobust),
                 out.robust_iterations, out.robust_termination);
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

TrialOutcome RunTrialAsInBatch(const PointSetup& setup, uint64_t trial, uint64_t trials) {
  PATLAB_CHECK(trial < trials);
  const uint64_t first = trial - trial % kBatchSize;
  const int count = static_cast<int>(std::min<uint64_t>(kBatchSize, trials - first));
  const size_t slot = static_cast<size_t>(trial - first);
  std::vector<double> arrays(static_cast<size_t>(6 * estimate::kNumEstimators * kBatchSize));
  std::vector<uint8_t> iterations(kBatchSize), termination(kBatchSize);
  BatchOutput out;
  for (int e = 0; e < estimate::kNumEstimators; ++e) {
    if (!setup.run[e]) continue;
    double* a = arrays.data() + static_cast<size_t>(6 * e * kBatchSize);
    out.errors[e] = {a, a + kBatchSize, a + 2 * kBatchSize};
    out.estimates[e] = {a + 3 * kBatchSize, a + 4 * kBatchSize, a + 5 * kBatchSize};
  }
  out.ml_iterations = iterations.data();
  out.ml_termination = termination.data();
  RunBatch(setup, first, count, out);
  TrialOutcome outcome;
  for (int e = 0; e < estimate::kNumEstimators; ++e) {
    if (!setup.run[e]) continue;
    const ErrorArrays& err = out.errors[e];
    const ErrorArrays& est = out.estimates[e];
    outcome.errors[e] = {err.x_mm[slot], err.y_mm[slot], err.theta_rad[slot]};
    outcome.estimates[e] = {est.x_mm[slot], est.y_mm[slot], est.theta_rad[slot]};
  }
  outcome.ml_iterations = iterations[slot];
  outcome.ml_termination = static_cast<estimate::Termination>(termination[slot]);
  return outcome;
}

}  // namespace patlab::sim
