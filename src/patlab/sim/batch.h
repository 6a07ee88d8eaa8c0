// The Monte-Carlo inner loop: a batch of trials of one data point in structure-of-arrays form.
//
// Trial t of a point draws every random number from Philox4x32-10 with counter
// (t mod 2^32, t div 2^32, point, block) under the key `seed` (docs/architecture.md rule 1); the
// runner sets seed = KnownPointKey (experiment seed, pattern content, noise, sigma: point_key.h)
// and point = kKnownStream, so a point draws the same numbers in any grid. Each 32-bit word
// gives one uniform (w + 1/2) 2^-32 in (0, 1); H = ceil(n / 2) for n patches:
//   block 0              words 0, 1, 2: pose x, y (uniform over the field), theta in (-pi, pi)
//   block 1 + j          Box-Muller normals of patch 2j (words 0, 1) and patch 2j + 1 (2, 3)
//   block 1 + H          common-mode normals (words 0, 1; only when common_sigma_ratio > 0)
//   block 2 + H + j      outlier selection uniforms of patches 4j .. 4j + 3 (only when p > 0)
//   block 2 + H + Q      camera jitter normals z_r, z_s (words 0, 1; Q = ceil(n / 4); only when
//                        rotation_jitter_rad or scale_jitter_ppm > 0)
// Correlated noise mixes the patches' own normals (no draws of its own); the colour-edge bias
// draws nothing.
// A 32-bit radius uniform caps |z| at sqrt(2 ln 2^33) = 6.76 (a Gaussian exceeds it with
// probability 1.4e-11): a documented truncation that halves the Philox work per trial.
// So a trial's numbers do not depend on which thread runs it or which batch it falls in, and
// any trial can be replayed alone (rule 3).
//
// Batches start at multiples of kBatchSize from trial 0, so the vectorised loops see the same
// lanes for any thread count and the results are byte-identical.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "patlab/core/geometry.h"
#include "patlab/estimate/estimators.h"
#include "patlab/estimate/gls.h"
#include "patlab/estimate/robust.h"
#include "patlab/sim/noise.h"

namespace patlab::sim {

inline constexpr int kBatchSize = 1024;

struct PointSetup {
  const estimate::Model* model = nullptr;
  NoiseModel noise;
  double sigma_mm = 0.0;
  double field_length_mm = 0.0;
  double field_width_mm = 0.0;
  uint64_t seed = 0;                        // the Philox key (the runner: KnownPointKey)
  uint32_t point = 0;                       // the stream word (the runner: kKnownStream)
  bool run[estimate::kNumEstimators] = {};  // indexed by estimate::Estimator
  estimate::Options ml_options;
  // Set when the noise's Gaussian part is not least squares (noise.GaussianPart()): "ml" is then
  // generalised least squares with these weights (estimate/gls.h), one trial at a time from the
  // least-squares pose; null: the batched Newton iteration on the sum of squares.
  std::shared_ptr<const estimate::GaussianWeights> ml_weights;
  // "robust" (estimate/robust.h): the inlier sigma and the outlier mixture of the noise model.
  estimate::RobustModel robust;
};

// Errors of one estimator, estimate minus truth; theta wrapped to (-pi, pi].
struct ErrorArrays {
  double* x_mm = nullptr;
  double* y_mm = nullptr;
  double* theta_rad = nullptr;
};

struct BatchOutput {
  ErrorArrays errors[estimate::kNumEstimators];  // indexed by estimate::Estimator; null if not run
  // The estimates themselves (origin in mm, theta wrapped to (-pi, pi]), written when not null;
  // errors = estimate - truth with these very values (replay, rule 3).
  ErrorArrays estimates[estimate::kNumEstimators];
  uint8_t* ml_iterations = nullptr;   // Newton steps per trial (ml only)
  uint8_t* ml_termination = nullptr;  // estimate::Termination per trial (ml only)
  // robust: its IRLS / EM steps and estimate::Termination per trial, written when not null.
  uint8_t* robust_iterations = nullptr;
  uint8_t* robust_termination = nullptr;
};

// Runs trials [first_trial, first_trial + count) of a point, count <= kBatchSize, writing slot
// k of every output array for trial first_trial + k, with the widest version of the kernel the
// CPU runs.
void RunBatch(const PointSetup& setup, uint64_t first_trial, int count, const BatchOutput& out);

// The kernel's versions: the same code compiled for the baseline x86-64 (SSE2), x86-64-v3
// (AVX2) and x86-64-v4 (AVX-512). They give the same bits (docs/reproducibility.md); the wider
// ones are faster. WidestKernelIsa is the one RunBatch runs; SupportedKernelIsas lists those
// this CPU and build have, baseline first and widest last; RunBatchWith runs a chosen one
// (tests and benchmarks).
enum class KernelIsa { kBaseline, kAvx2, kAvx512 };
KernelIsa WidestKernelIsa();
std::vector<KernelIsa> SupportedKernelIsas();
void RunBatchWith(KernelIsa isa, const PointSetup& setup, uint64_t first_trial, int count,
                  const BatchOutput& out);

// Replays one trial (rule 3): its true pose and noisy patch positions, exactly as RunBatch
// generated them.
void GenerateTrial(const PointSetup& setup, uint64_t trial, Pose2* truth, Vec2* observed);

// One trial as the runner computed it: the estimates, errors and ML counters RunBatch wrote for
// it, bit for bit. The runner runs a point's trials in batches of kBatchSize from trial 0, the
// last one short; `trials` (the point's trial count) gives the length of the trial's batch.
struct TrialOutcome {
  std::array<Pose2, estimate::kNumEstimators>
      estimates{};  // indexed by estimate::Estimator (those setup.run)
  std::array<Pose2, estimate::kNumEstimators> errors{};  // estimate - truth, theta wrapped
  int ml_iterations = 0;
  estimate::Termination ml_termination = estimate::Termination::kConverged;
};
TrialOutcome RunTrialAsInBatch(const PointSetup& setup, uint64_t trial, uint64_t trials);

}  // namespace patlab::sim
