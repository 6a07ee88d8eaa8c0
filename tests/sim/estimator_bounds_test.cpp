// The runner's estimators against their Cramer-Rao bounds under the noise models that have one:
// "ml" attains the bound (to Monte-Carlo error) at small sigma under every Gaussian model, and the
// runner reports the bound and ml's prediction.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../test_util.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/report.h"
#include "patlab/sim/runner.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;

Experiment Butterfly(const NoiseModel& noise, double sigma_mm, int64_t trials) {
  Experiment e;
  e.name = "bounds";
  e.patterns = {testing::ShippedPattern("butterfly")};
  e.pattern_files = {"butterfly"};
  e.estimators = {Estimator::kMl, Estimator::kLsq};
  e.sigmas_mm = {sigma_mm};
  e.trials = trials;
  e.seed = 31337;
  e.noise = noise;
  return e;
}

TEST(EstimatorBounds, MlAttainsTheGaussianBoundUnderAnisotropicCorrelatedAndCommonNoise) {
  NoiseModel aniso;
  aniso.sigma_y_ratio = 2.5;
  NoiseModel correlated;
  correlated.correlation_length_mm = 80.0;
  NoiseModel all;
  all.sigma_y_ratio = 0.4;
  all.correlation_length_mm = 40.0;
  all.common_sigma_ratio = 0.6;
  for (const NoiseModel& noise : {aniso, correlated, all}) {
    SCOPED_TRACE(noise.Describe());
    const Experiment e = Butterfly(noise, 0.2, 40000);
    const RunResult result = RunExperiment(e, RunOptions{});
    const EstimatorResult& ml = result.points[0].estimators[0];
    const EstimatorResult& lsq = result.points[0].estimators[1];
    ASSERT_FALSE(std::isnan(ml.crlb_theta_rad));
    EXPECT_EQ(ml.crlb_position_mm, lsq.crlb_position_mm);
    EXPECT_EQ(ml.predicted_position_mm, ml.crlb_position_mm);
    EXPECT_EQ(ml.predicted_theta_rad, ml.crlb_theta_rad);
    EXPECT_EQ(ml.nonconverged, 0);
    // 4 standard errors of a std: 1/sqrt(2 (n - 1)) relative (the position's two axes pooled
    // are not independent, so count them as one).
    const double se = 1.0 / std::sqrt(2.0 * (e.trials - 1));
    EXPECT_NEAR(ml.theta.std / ml.crlb_theta_rad, 1.0, 4.0 * se);
    EXPECT_NEAR(ml.position_std_mm / ml.crlb_position_mm, 1.0, 4.0 * se);
    // Least squares is no better than the bound.
    EXPECT_GT(lsq.theta.std / lsq.crlb_theta_rad, 1.0 - 4.0 * se);
  }
}

TEST(EstimatorBounds, AnisotropicNoiseSeparatesMlFromLeastSquares) {
  // With sigma_y = 3 sigma_x least squares weighs the noisy axis like the good one. The origin is
  // (nearly) the patches' mean either way, but the angle's std is well above the bound, which ml
  // attains: for spread S about the origin, var(theta) of least squares (1 + r^2) / (2 S) against
  // the bound's 2 r^2 / ((1 + r^2) S), a ratio of (1 + r^2) / (2 r) = 1.67 in std at r = 3.
  NoiseModel aniso;
  aniso.sigma_y_ratio = 3.0;
  const Experiment e = Butterfly(aniso, 0.2, 20000);
  const RunResult result = RunExperiment(e, RunOptions{});
  const EstimatorResult& ml = result.points[0].estimators[0];
  const EstimatorResult& lsq = result.points[0].estimators[1];
  EXPECT_GT(lsq.theta.std / ml.theta.std, 1.4);
  EXPECT_GT(lsq.theta.std / lsq.crlb_theta_rad, 1.4);
}

TEST(EstimatorBounds, NoBoundWithoutAGaussianModel) {
  NoiseModel jitter;
  jitter.rotation_jitter_rad = 0.001;
  jitter.sigma_y_ratio = 2.0;
  const RunResult result = RunExperiment(Butterfly(jitter, 0.5, 200), RunOptions{});
  for (const EstimatorResult& r : result.points[0].estimators) {
    EXPECT_TRUE(std::isnan(r.crlb_position_mm));
    EXPECT_TRUE(std::isnan(r.crlb_theta_rad));
  }
  EXPECT_TRUE(std::isnan(result.points[0].estimators[0].predicted_theta_rad));  // ml: GLS
  EXPECT_FALSE(std::isnan(result.points[0].estimators[1].predicted_theta_rad));
}

TEST(EstimatorBounds, RobustComesWithinThirtyPercentOfTheMixtureBound) {
  // Butterfly, sigma 1 mm, 5% outliers of 10 sigma: the mixture's bound is the isotropic one over
  // sqrt(i(0.05, 10)) = sqrt(0.936); least squares ("ml" here) pays the mixture's whole variance,
  // sqrt(0.95 + 5) = 2.4 times the isotropic bound.
  NoiseModel outliers;
  outliers.outlier_probability = 0.05;
  outliers.outlier_sigma_ratio = 10.0;
  Experiment e = Butterfly(outliers, 1.0, 20000);
  e.estimators = {Estimator::kMl, Estimator::kRobust};
  const RunResult result = RunExperiment(e, RunOptions{});
  const EstimatorResult& ml = result.points[0].estimators[0];
  const EstimatorResult& robust = result.points[0].estimators[1];
  ASSERT_FALSE(std::isnan(robust.crlb_theta_rad));
  EXPECT_LT(robust.theta.std / robust.crlb_theta_rad, 1.3);
  EXPECT_LT(robust.position_std_mm / robust.crlb_position_mm, 1.3);
  EXPECT_GT(robust.theta.std / robust.crlb_theta_rad, 1.0 - 4.0 / std::sqrt(2.0 * e.trials));
  EXPECT_GT(ml.theta.std / ml.crlb_theta_rad, 2.0);
  EXPECT_TRUE(std::isnan(robust.predicted_theta_rad));
}

TEST(EstimatorBounds, RobustLosesLessThanFivePercentToMlUnderIsotropicNoise) {
  for (const char* pattern : {"butterfly", "triangle"}) {
    Experiment e = Butterfly(NoiseModel{}, 1.0, 20000);
    e.patterns = {testing::ShippedPattern(pattern)};
    e.estimators = {Estimator::kMl, Estimator::kRobust};
    const RunResult result = RunExperiment(e, RunOptions{});
    const EstimatorResult& ml = result.points[0].estimators[0];
    const EstimatorResult& robust = result.points[0].estimators[1];
    EXPECT_LT(robust.theta.std / ml.theta.std, 1.05) << pattern;
    EXPECT_LT(robust.position_std_mm / ml.position_std_mm, 1.05) << pattern;
  }
}

// robust reports its steps and non-converged trials as ml does: the runner's counters (batches
// on two threads, folded in order) against every trial's own from the batch kernel, and the
// ml_* columns of the results CSV filled on the robust row.
TEST(EstimatorBounds, RobustCountsItsStepsLikeMl) {
  NoiseModel outliers;
  outliers.outlier_probability = 0.05;
  outliers.outlier_sigma_ratio = 10.0;
  Experiment e = Butterfly(outliers, 1.0, 5000);
  e.estimators = {Estimator::kFast, Estimator::kRobust};
  RunOptions options;
  options.threads = 2;
  const RunResult result = RunExperiment(e, options);
  const EstimatorResult& robust = result.points[0].estimators[1];

  const auto n = static_cast<size_t>(e.trials);
  const estimate::Model model = estimate::Model::FromPattern(e.patterns[0]);
  const PointSetup setup = MakePointSetup(e, model, 0, 0);
  std::vector<double> x(n), y(n), theta(n), fx(n), fy(n), ftheta(n);
  std::vector<uint8_t> iterations(n), termination(n);
  for (size_t first = 0; first < n; first += kBatchSize) {
    BatchOutput out;
    out.errors[static_cast<int>(Estimator::kFast)] = {fx.data() + first, fy.data() + first,
                                                      ftheta.data() + first};
    out.errors[static_cast<int>(Estimator::kRobust)] = {x.data() + first, y.data() + first,
                                                        theta.data() + first};
    out.robust_iterations = iterations.data() + first;
    out.robust_termination = termination.data() + first;
    RunBatch(setup, first, static_cast<int>(std::min<size_t>(kBatchSize, n - first)), out);
  }
  int64_t steps = 0, nonconverged = 0, first_nonconverged = -1;
  for (size_t t = 0; t < n; ++t) {
    steps += iterations[t];
    if (termination[t] == static_cast<uint8_t>(estimate::Termination::kConverged)) continue;
    if (first_nonconverged < 0) first_nonconverged = static_cast<int64_t>(t);
    ++nonconverged;
  }
  EXPECT_GT(steps, static_cast<int64_t>(n));  // EM takes more than one step per trial
  EXPECT_EQ(robust.mean_iterations, static_cast<double>(steps) / static_cast<double>(n));
  EXPECT_EQ(robust.nonconverged, nonconverged);
  EXPECT_EQ(robust.first_nonconverged_trial, first_nonconverged);
  // The CSV: the fast row leaves the counters empty, the robust row has them.
  const std::string csv = ResultsCsv(e, result);
  EXPECT_NE(csv.find(",robust,"), std::string::npos);
  const size_t row = csv.find("\nbutterfly,robust,");
  ASSERT_NE(row, std::string::npos) << csv;
  const std::string line = csv.substr(row + 1, csv.find('\n', row + 1) - row - 1);
  EXPECT_NE(line.find("," + std::to_string(nonconverged) + "," +
                      std::to_string(first_nonconverged) + ","),
            std::string::npos)
      << line;
}

}  // namespace
}  // namespace patlab::sim
