// Replay (docs/architecture.md rule 3): `patlab simulate --replay POINT,TRIAL` reproduces what the
// run computed for that trial, bit for bit, for every estimator and noise model; and the angles
// the run reports are wrapped, whatever the estimator's iteration did.
#include "patlab/sim/replay.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/runner.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;

struct NoiseCase {
  std::string name;
  NoiseModel noise;
};

std::vector<NoiseCase> NoiseCases() {
  std::vector<NoiseCase> cases;
  cases.push_back({"isotropic", {}});
  NoiseModel aniso;
  aniso.sigma_y_ratio = 2.0;
  cases.push_back({"anisotropic", aniso});
  NoiseModel common;
  common.common_sigma_ratio = 0.7;
  cases.push_back({"common", common});
  NoiseModel correlated;
  correlated.correlation_length_mm = 60.0;
  cases.push_back({"correlated", correlated});
  NoiseModel outliers;
  outliers.outlier_probability = 0.05;
  outliers.outlier_sigma_ratio = 8.0;
  cases.push_back({"outliers", outliers});
  NoiseModel camera;
  camera.rotation_jitter_rad = 0.002;
  camera.scale_jitter_ppm = 200.0;
  camera.key_shift_x_mm = 0.3;
  cases.push_back({"camera", camera});
  return cases;
}

Experiment EveryEstimator(const std::string& pattern, const NoiseModel& noise, double sigma_mm,
                          int64_t trials) {
  Experiment e;
  e.name = "replay";
  e.patterns = {testing::ShippedPattern(pattern)};
  e.pattern_files = {pattern};
  e.estimators.assign(estimate::kEveryEstimator.begin(), estimate::kEveryEstimator.end());
  e.sigmas_mm = {sigma_mm};
  e.trials = trials;
  e.seed = 4242;
  e.noise = noise;
  return e;
}

uint64_t Bits(double v) { return std::bit_cast<uint64_t>(v); }

// The errors of every trial of point 0 as the runner's RunTrials computes them: batches of
// kBatchSize from trial 0, the last one short.
std::vector<std::array<Pose2, estimate::kNumEstimators>> RunnerErrors(const Experiment& e) {
  const estimate::Model model = estimate::Model::FromPattern(e.patterns[0]);
  const PointSetup setup = MakePointSetup(e, model, 0, 0);
  const size_t n = static_cast<size_t>(e.trials);
  std::vector<double> arrays(estimate::kNumEstimators * 3 * n);
  std::vector<uint8_t> iterations(n), termination(n);
  for (size_t first = 0; first < n; first += kBatchSize) {
    BatchOutput out;
    for (int k = 0; k < estimate::kNumEstimators; ++k) {
      double* a = arrays.data() + 3 * n * static_cast<size_t>(k) + first;
      out.errors[k] = {a, a + n, a + 2 * n};
    }
    out.ml_iterations = iterations.data() + first;
    out.ml_termination = termination.data() + first;
    RunBatch(setup, first, static_cast<int>(std::min<size_t>(kBatchSize, n - first)), out);
  }
  std::vector<std::array<Pose2, estimate::kNumEstimators>> errors(n);
  for (size_t t = 0; t < n; ++t) {
    for (size_t k = 0; k < estimate::kNumEstimators; ++k) {
      const double* a = arrays.data() + 3 * n * k + t;
      errors[t][k] = {a[0], a[n], a[2 * n]};
    }
  }
  return errors;
}

TEST(Replay, SampledTrialsOfEveryEstimatorAndNoiseModelAreTheRunsBits) {
  for (const NoiseCase& c : NoiseCases()) {
    SCOPED_TRACE(c.name);
    const Experiment e = EveryEstimator("butterfly", c.noise, 3.0, 2 * kBatchSize + 300);
    const std::vector<std::array<Pose2, estimate::kNumEstimators>> run = RunnerErrors(e);
    for (int64_t t = 0; t < e.trials; t += t < 2 * kBatchSize ? 97 : 13) {
      const TrialReplay r = ReplayTrial(e, {0, t, ""});
      for (Estimator est : e.estimators) {
        SCOPED_TRACE(std::string(estimate::EstimatorName(est)) + " trial " + std::to_string(t));
        const size_t k = static_cast<size_t>(est);
        const Pose2& got = r.errors[k];
        EXPECT_EQ(Bits(got.x_mm), Bits(run[t][k].x_mm));
        EXPECT_EQ(Bits(got.y_mm), Bits(run[t][k].y_mm));
        EXPECT_EQ(Bits(got.theta_rad), Bits(run[t][k].theta_rad));
        // The printed estimate is the one the error was taken from.
        const Pose2& p = r.estimates[k];
        EXPECT_EQ(Bits(p.x_mm - r.truth.x_mm), Bits(got.x_mm));
        EXPECT_EQ(Bits(WrapAngle(p.theta_rad - r.truth.theta_rad)), Bits(got.theta_rad));
        EXPECT_EQ(Bits(WrapAngle(p.theta_rad)), Bits(p.theta_rad));
      }
    }
  }
}

TEST(Replay, EveryTrialReplayedGivesTheRunsStatistics) {
  // The statistics of the run (RunExperiment) from the replayed errors of all its trials.
  NoiseModel outliers;
  outliers.outlier_probability = 0.1;
  const Experiment e = EveryEstimator("triangle", outliers, 4.0, 1500);
  const RunResult result = RunExperiment(e, RunOptions{});
  ASSERT_EQ(result.points.size(), 1u);
  for (const EstimatorResult& r : result.points[0].estimators) {
    SCOPED_TRACE(std::string(estimate::EstimatorName(r.estimator)));
    double sum = 0.0, sum_sq = 0.0;
    for (int64_t t = 0; t < e.trials; ++t) {
      const double v =
          ReplayTrial(e, {0, t, ""}).errors[static_cast<size_t>(r.estimator)].theta_rad;
      sum += v;
      sum_sq += v * v;
    }
    const double n = static_cast<double>(e.trials);
    const double mean = sum / n;
    const double std = std::sqrt((sum_sq - n * mean * mean) / (n - 1.0));
    EXPECT_NEAR(r.theta.mean, mean, 1e-12 * std);
    EXPECT_NEAR(r.theta.std, std, 1e-9 * std);
  }
}

// Three patches, the key 80 mm from the reported origin: at sigma 10 mm the Newton iteration
// of some trials runs off by whole turns before it converges.
Pattern OffOriginKeyTriangle() {
  Pattern p;
  p.name = "off-origin-key";
  for (const Vec2& at : {Vec2(80.0, 0.0), Vec2(110.0, 20.0), Vec2(110.0, -20.0)}) {
    Patch patch;
    patch.position_mm = at;
    patch.radius_mm = 10.0;
    p.patches.push_back(patch);
  }
  p.patches[0].role = PatchRole::kKey;
  p.key_index = 0;
  p.orientation_pairs = DefaultOrientationPairs(p.patches, p.key_index);
  return p;
}

TEST(Replay, MlAnglesAreWrappedOnAnOffOriginKeyAtLargeNoise) {
  Experiment e;
  e.name = "off-origin";
  e.patterns = {OffOriginKeyTriangle()};
  e.pattern_files = {"in code"};
  e.estimators = {Estimator::kMl, Estimator::kLsq};
  e.sigmas_mm = {10.0};
  e.trials = 20000;
  e.seed = 7;
  const RunResult result = RunExperiment(e, RunOptions{});
  const EstimatorResult& ml = result.points[0].estimators[0];
  const EstimatorResult& lsq = result.points[0].estimators[1];
  // Both minimise the same sum of squares (lsq in closed form), so their angle errors have the
  // same spread but for the rare trial where Newton stops in another minimum; a whole-turn error
  // would add 2 pi to a 0.2 rad spread. 4 standard errors of a std (1/sqrt(2 (n - 1))) apart.
  EXPECT_LT(lsq.theta.std, 1.0);
  EXPECT_NEAR(ml.theta.std, lsq.theta.std, 4.0 * lsq.theta.std / std::sqrt(2.0 * (e.trials - 1)));
  EXPECT_LE(std::abs(ml.theta.mean), 4.0 * ml.theta.std / std::sqrt(e.trials));
  // The kernel's estimates themselves are in (-pi, pi], every estimator's, every trial.
  const estimate::Model model = estimate::Model::FromPattern(e.patterns[0]);
  PointSetup setup = MakePointSetup(e, model, 0, 0);
  for (Estimator est : estimate::kEveryEstimator) setup.run[static_cast<int>(est)] = true;
  std::vector<double> arrays(6 * estimate::kNumEstimators * kBatchSize);
  std::vector<uint8_t> iterations(kBatchSize), termination(kBatchSize);
  int outside = 0;
  for (int64_t first = 0; first < e.trials; first += kBatchSize) {
    BatchOutput out;
    for (int k = 0; k < estimate::kNumEstimators; ++k) {
      double* a = arrays.data() + 6 * k * kBatchSize;
      out.errors[k] = {a, a + kBatchSize, a + 2 * kBatchSize};
      out.estimates[k] = {a + 3 * kBatchSize, a + 4 * kBatchSize, a + 5 * kBatchSize};
    }
    out.ml_iterations = iterations.data();
    out.ml_termination = termination.data();
    RunBatch(setup, static_cast<uint64_t>(first), kBatchSize, out);
    for (const ErrorArrays& est : out.estimates) {
      for (int k = 0; k < kBatchSize; ++k) {
        const double theta = est.theta_rad[k];
        outside += theta > -std::numbers::pi && theta <= std::numbers::pi ? 0 : 1;
      }
    }
  }
  EXPECT_EQ(outside, 0);
}

}  // namespace
}  // namespace patlab::sim
