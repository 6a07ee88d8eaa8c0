#include "patlab/sim/runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/noise_prediction.h"
#include "patlab/sim/replay.h"
#include "patlab/sim/report.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;

Experiment SmallExperiment(std::vector<std::string> patterns, std::vector<double> sigmas,
                           int64_t trials) {
  Experiment e;
  e.name = "test";
  for (const std::string& p : patterns) {
    e.patterns.push_back(testing::ShippedPattern(p));
    e.pattern_files.push_back(p);
  }
  e.estimators = {Estimator::kFast, Estimator::kMl, Estimator::kLsq, Estimator::kKey};
  e.sigmas_mm = std::move(sigmas);
  e.trials = trials;
  e.seed = 12345;
  return e;
}

TEST(Runner, SameSeedGivesByteIdenticalResultsOnOneTwoAndEightThreads) {
  // 5,000 trials: several batches, the last one partial.
  const Experiment e = SmallExperiment({"triangle", "butterfly"}, {0.5, 2.0}, 5000);
  std::string reference;
  for (int threads : {1, 2, 8}) {
    RunOptions options;
    options.threads = threads;
    const std::string csv = ResultsCsv(e, RunExperiment(e, options));
    if (reference.empty()) {
      reference = csv;
    } else {
      EXPECT_EQ(csv, reference) << threads << " threads";
    }
  }
  // And a different seed gives different numbers.
  Experiment other = e;
  other.seed = 12346;
  EXPECT_NE(ResultsCsv(other, RunExperiment(other, {})), reference);
}

// The CSV rows of `csv` (header dropped) whose sigma_mm cell (third) is `sigma`.
std::vector<std::string> RowsAtSigma(const std::string& csv, const std::string& sigma) {
  std::vector<std::string> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const size_t a = line.find(',');
    const size_t b = line.find(',', a + 1);
    const size_t c = line.find(',', b + 1);
    if (line.substr(b + 1, c - b - 1) == sigma) rows.push_back(line);
  }
  return rows;
}

// docs/architecture.md rule 1: a point's trials are keyed by what it is, so a one-sigma run, a
// run over another sigma grid, and a run over a subset of the patterns in another order give
// the same rows as the full sweep, byte for byte.
TEST(Runner, AOneSigmaRunEqualsTheCorrespondingRowsOfTheFullSweep) {
  const Experiment full = SmallExperiment({"triangle", "butterfly"}, {0.5, 1.0, 2.0}, 3000);
  const std::string full_csv = ResultsCsv(full, RunExperiment(full, {}));
  Experiment one = SmallExperiment({"butterfly", "triangle"}, {1.0}, 3000);
  const std::string one_csv = ResultsCsv(one, RunExperiment(one, {}));
  const std::vector<std::string> expected = RowsAtSigma(full_csv, "1");
  std::vector<std::string> got = RowsAtSigma(one_csv, "1");
  ASSERT_EQ(got.size(), 8u);  // 2 patterns x 4 estimators
  // The one-sigma run lists butterfly first: compare as sets of rows.
  std::vector<std::string> want = expected;
  std::sort(want.begin(), want.end());
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, want);
  Experiment other_grid = SmallExperiment({"butterfly"}, {1.0, 3.0}, 3000);
  const std::string other_csv = ResultsCsv(other_grid, RunExperiment(other_grid, {}));
  const std::vector<std::string> butterfly = RowsAtSigma(other_csv, "1");
  ASSERT_EQ(butterfly.size(), 4u);
  for (const std::string& row : butterfly) {
    EXPECT_NE(std::find(expected.begin(), expected.end(), row), expected.end()) << row;
  }
  // A renamed copy of a pattern is the same point; moving one patch makes it another.
  Experiment renamed = one;
  renamed.patterns = {one.patterns[0]};
  renamed.patterns[0].name = "a renamed butterfly";
  renamed.patterns[0].description = "a copy";
  Experiment moved = renamed;
  moved.patterns[0].patches[1].position_mm.x() += 1e-9;
  EXPECT_EQ(MakePointSetup(renamed, estimate::Model::FromPattern(renamed.patterns[0]), 0, 0).seed,
            MakePointSetup(one, estimate::Model::FromPattern(one.patterns[0]), 0, 0).seed);
  EXPECT_NE(MakePointSetup(moved, estimate::Model::FromPattern(moved.patterns[0]), 0, 0).seed,
            MakePointSetup(one, estimate::Model::FromPattern(one.patterns[0]), 0, 0).seed);
}

// Simulated std against the first-order prediction: at small sigma the estimators are linear in
// the noise, so the prediction is exact up to O(sigma^2) terms far below the tolerance; the
// sampling std of a std estimate is s / sqrt(2 (n - 1)).
TEST(Runner, SimulatedStdMatchesThePredictedStdWithinFourStandardErrors) {
  const int64_t n = 40000;
  const Experiment e = SmallExperiment(testing::ShippedPatternNames(), {0.1}, n);
  const RunResult result = RunExperiment(e, {});
  for (const PointResult& p : result.points) {
    for (const EstimatorResult& r : p.estimators) {
      SCOPED_TRACE(p.pattern + " " + std::string(estimate::EstimatorName(r.estimator)));
      const double se_theta = r.predicted_theta_rad / std::sqrt(2.0 * (n - 1));
      EXPECT_NEAR(r.theta.std, r.predicted_theta_rad, 4 * se_theta);
      // Pooled over x and y: 2 (n - 1) degrees of freedom.
      const double se_pos = r.predicted_position_mm / std::sqrt(4.0 * (n - 1));
      EXPECT_NEAR(r.position_std_mm, r.predicted_position_mm, 4 * se_pos);
      // |position error| is Rayleigh when the position error is isotropic in the model frame:
      // for the key estimator, and for every estimator on patterns whose centroid is the
      // origin (Linear, Triangle); then mean s sqrt(pi/2), std s sqrt(2 - pi/2) for per-axis
      // std s, and the std's standard error is (std / 2) sqrt((2 + kappa) / n) with the
      // Rayleigh excess kurtosis kappa = 0.245.
      const Vec2 centroid = testing::ShippedPattern(p.pattern).Centroid();
      if (r.estimator == Estimator::kKey || centroid.norm() < 1e-9) {
        const double s = r.predicted_position_mm;
        const double rayleigh_std = s * std::sqrt(2.0 - std::numbers::pi / 2.0);
        EXPECT_NEAR(r.radial.mean, s * std::sqrt(std::numbers::pi / 2.0),
                    4 * rayleigh_std / std::sqrt(n));
        EXPECT_NEAR(r.radial.std, rayleigh_std, 4 * rayleigh_std / 2 * std::sqrt(2.245 / n));
      }
      EXPECT_LT(r.radial.std_lower, r.radial.std);
      EXPECT_GT(r.radial.std_upper, r.radial.std);
      // Unbiased: |mean| within 4 standard errors of 0.
      EXPECT_NEAR(r.theta.mean, 0.0, 4 * r.theta.std / std::sqrt(n));
      EXPECT_NEAR(r.x.mean, 0.0, 4 * r.x.std / std::sqrt(n));
      // The interval contains the estimate.
      EXPECT_LT(r.theta.std_lower, r.theta.std);
      EXPECT_GT(r.theta.std_upper, r.theta.std);
      EXPECT_EQ(r.nonconverged, 0);
    }
  }
}

TEST(Runner, NoiseModelsChangeTheStdAsTheirFormulasSay) {
  const int64_t n = 40000;
  Experiment e = SmallExperiment({"butterfly"}, {0.1}, n);
  e.estimators = {Estimator::kFast};
  // Common mode: the angle is unaffected, the position std grows to sqrt(pred^2 + (g sigma)^2).
  e.noise.common_sigma_ratio = 2.0;
  RunResult r = RunExperiment(e, {});
  const EstimatorResult& common = r.points[0].estimators[0];
  EXPECT_NEAR(common.position_std_mm, common.predicted_position_mm,
              4 * common.predicted_position_mm / std::sqrt(4.0 * (n - 1)));
  EXPECT_GT(common.predicted_position_mm, 0.1 * 2.0);
  // The bound: the offset adds (g sigma)^2 to the isotropic bound's position variance, nothing
  // to the angle's (it lies in the translation columns of the Jacobian).
  const estimate::StdPerSigma iso =
      estimate::CramerRaoBound(estimate::Model::FromPattern(e.patterns[0]));
  EXPECT_NEAR(common.crlb_position_mm, std::hypot(0.1 * iso.position_per_axis, 0.1 * 2.0),
              1e-9 * common.crlb_position_mm);
  EXPECT_NEAR(common.crlb_theta_rad, 0.1 * iso.theta, 1e-9 * common.crlb_theta_rad);
  // Outliers: a linear estimator's variance is that of the mixture, per axis
  // sigma^2 ((1 - p) + p k^2). Its std estimate has standard error (s / 2) sqrt((2 + kappa) / n)
  // with kappa the excess kurtosis, at most the mixture's 3 (1 - p + p k^4) / (1 - p + p k^2)^2
  // - 3.
  e.noise = NoiseModel{};
  e.noise.outlier_probability = 0.1;
  e.noise.outlier_sigma_ratio = 5.0;
  r = RunExperiment(e, {});
  const EstimatorResult& outliers = r.points[0].estimators[0];
  const double p = 0.1, k = 5.0;
  const double kappa = 3 * (1 - p + p * std::pow(k, 4)) / std::pow(1 - p + p * k * k, 2) - 3;
  const double predicted =
      estimate::PredictedStd(estimate::Model::FromPattern(e.patterns[0]), Estimator::kFast).theta *
      0.1 * std::sqrt(1 - p + p * k * k);
  EXPECT_NEAR(outliers.predicted_theta_rad, predicted, 1e-12);
  EXPECT_NEAR(outliers.theta.std, predicted, 4 * predicted / 2 * std::sqrt((2 + kappa) / n));
  // Anisotropic: sigma_y = 3 sigma_x; with random headings the per-axis variance averages to
  // sigma^2 (1 + 9) / 2.
  e.noise = NoiseModel{};
  e.noise.sigma_y_ratio = 3.0;
  r = RunExperiment(e, {});
  const EstimatorResult& aniso = r.points[0].estimators[0];
  EXPECT_NEAR(aniso.predicted_theta_rad / predicted, std::sqrt(5.0) / std::sqrt(1 - p + p * k * k),
              1e-12);
  EXPECT_NEAR(aniso.theta.std, aniso.predicted_theta_rad,
              4 * aniso.predicted_theta_rad / std::sqrt(2.0 * (n - 1)));
}

TEST(Runner, BatchedNewtonMatchesTheReferenceEstimatorAndReplayReproducesTrials) {
  // The batch kernel's ML (sums form, vectorised) against estimate::MaximumLikelihood on the
  // replayed patches of the same trials.
  Experiment e = SmallExperiment({"butterfly", "triangle"}, {3.0}, 3000);
  for (int pi = 0; pi < 2; ++pi) {
    const estimate::Model model = estimate::Model::FromPattern(e.patterns[pi]);
    const PointSetup setup = MakePointSetup(e, model, pi, 0);
    std::vector<double> buffers[4][3];
    std::vector<uint8_t> iterations(kBatchSize), termination(kBatchSize);
    BatchOutput out;
    for (Estimator est : e.estimators) {
      auto& b = buffers[static_cast<int>(est)];
      for (auto& v : b) v.resize(kBatchSize);
      out.errors[static_cast<int>(est)] = {b[0].data(), b[1].data(), b[2].data()};
    }
    out.ml_iterations = iterations.data();
    out.ml_termination = termination.data();
    const uint64_t first = 2 * kBatchSize;
    RunBatch(setup, first, kBatchSize, out);
    for (int k = 0; k < kBatchSize; k += 37) {
      Pose2 truth;
      std::array<Vec2, kMaxPatches> v;
      GenerateTrial(setup, first + k, &truth, v.data());
      const Pose2 fast = estimate::Fast(model, v.data());
      estimate::Summary summary;
      const Pose2 ml = estimate::MaximumLikelihood(model, v.data(), fast, e.ml_options, &summary);
      const Pose2 lsq = estimate::LeastSquares(model, v.data());
      const int f = static_cast<int>(Estimator::kFast), m = static_cast<int>(Estimator::kMl),
                l = static_cast<int>(Estimator::kLsq);
      EXPECT_NEAR(buffers[f][0][k], fast.x_mm - truth.x_mm, 1e-9);
      EXPECT_NEAR(buffers[f][2][k], WrapAngle(fast.theta_rad - truth.theta_rad), 1e-12);
      EXPECT_NEAR(buffers[m][0][k], ml.x_mm - truth.x_mm, 1e-9);
      EXPECT_NEAR(buffers[m][1][k], ml.y_mm - truth.y_mm, 1e-9);
      EXPECT_NEAR(buffers[m][2][k], WrapAngle(ml.theta_rad - truth.theta_rad), 1e-11);
      EXPECT_NEAR(buffers[l][2][k], WrapAngle(lsq.theta_rad - truth.theta_rad), 1e-11);
      EXPECT_EQ(termination[k], static_cast<uint8_t>(estimate::Termination::kConverged));
      EXPECT_NEAR(iterations[k], summary.iterations, 1);
    }
  }
}

TEST(Runner, NoiseFreeTrialsHaveZeroErrorAndTheFieldIsCovered) {
  Experiment e = SmallExperiment({"ssl-standard"}, {0.0}, 2000);
  const RunResult r = RunExperiment(e, {});
  for (const EstimatorResult& est : r.points[0].estimators) {
    EXPECT_LT(est.position_std_mm, 1e-9);
    EXPECT_LT(est.theta.std, 1e-12);
    EXPECT_FALSE(est.vs_fast.computed);  // no tests on rounding noise
  }
  const estimate::Model model = estimate::Model::FromPattern(e.patterns[0]);
  const PointSetup setup = MakePointSetup(e, model, 0, 0);
  double max_x = 0, max_y = 0, max_t = 0;
  for (uint64_t t = 0; t < 2000; t += 7) {
    Pose2 truth;
    std::array<Vec2, kMaxPatches> v;
    GenerateTrial(setup, t, &truth, v.data());
    max_x = std::max(max_x, std::abs(truth.x_mm));
    max_y = std::max(max_y, std::abs(truth.y_mm));
    max_t = std::max(max_t, std::abs(truth.theta_rad));
  }
  EXPECT_LE(max_x, 1400.0);
  EXPECT_GT(max_x, 1300.0);
  EXPECT_LE(max_y, 1150.0);
  EXPECT_GT(max_y, 1050.0);
  EXPECT_GT(max_t, 3.0);
}

TEST(Runner, FastVsMlTestsSeparateIdenticalEstimatorsFromRealDifferences) {
  // On Triangle the fast estimator is the least-squares optimum (its summed pair vectors are the
  // Procrustes sums), so fast and ml differ by rounding only: no test may find a difference.
  // On Butterfly ml is measurably better in |theta| (about 0.5% in std): a paired test on
  // 20,000 trials sees it, while the unpaired KS test on the error distributions does not.
  Experiment e = SmallExperiment({"triangle", "butterfly"}, {1.0}, 20000);
  e.estimators = {Estimator::kFast, Estimator::kMl};
  const RunResult r = RunExperiment(e, {});
  const Comparison& triangle = r.points[0].estimators[1].vs_fast;
  ASSERT_TRUE(triangle.computed);
  EXPECT_EQ(triangle.wilcoxon_theta.p_value, 1.0);
  EXPECT_EQ(triangle.wilcoxon_position.p_value, 1.0);
  EXPECT_GT(triangle.ks_theta.p_value, 0.999);
  const Comparison& butterfly = r.points[1].estimators[1].vs_fast;
  EXPECT_LT(butterfly.wilcoxon_theta.p_value, 1e-4);
  EXPECT_GT(butterfly.ks_theta.p_value, 0.05);
  EXPECT_FALSE(r.points[0].estimators[0].vs_fast.computed);  // fast is the reference
}

TEST(Runner, APointOfMoreThanOneBlockFoldsItsBlocksInTrialOrder) {
  // Two blocks (kStatisticsBlockTrials + 3000 trials). The reference is independent of the
  // runner's blocks: every trial's errors from the batch kernel into whole arrays, and the
  // two-pass statistics of the whole sample.
  Experiment e = SmallExperiment({"butterfly"}, {2.0}, kStatisticsBlockTrials + 3000);
  e.estimators = {Estimator::kFast, Estimator::kMl};
  e.ml_options.max_iterations = 2;  // some trials do not converge, in both blocks
  RunOptions options;
  options.threads = 2;
  const RunResult result = RunExperiment(e, options);
  ASSERT_EQ(result.points.size(), 1U);
  EXPECT_EQ(result.total_trials, e.trials);

  const size_t n = static_cast<size_t>(e.trials);
  const estimate::Model model = estimate::Model::FromPattern(e.patterns[0]);
  const PointSetup setup = MakePointSetup(e, model, 0, 0);
  std::vector<double> errors[2][3];
  for (auto& estimator : errors) {
    for (auto& v : estimator) v.resize(n);
  }
  std::vector<uint8_t> iterations(n), termination(n);
  for (size_t first = 0; first < n; first += kBatchSize) {
    BatchOutput out;
    for (int k = 0; k < 2; ++k) {
      out.errors[static_cast<int>(e.estimators[k])] = {
          errors[k][0].data() + first, errors[k][1].data() + first, errors[k][2].data() + first};
    }
    out.ml_iterations = iterations.data() + first;
    out.ml_termination = termination.data() + first;
    RunBatch(setup, first, static_cast<int>(std::min<size_t>(kBatchSize, n - first)), out);
  }
  for (int k = 0; k < 2; ++k) {
    const EstimatorResult& r = result.points[0].estimators[k];
    const double* axes[3] = {&r.x.std, &r.y.std, &r.theta.std};
    const double* means[3] = {&r.x.mean, &r.y.mean, &r.theta.mean};
    for (int a = 0; a < 3; ++a) {
      const double std = stats::SampleStd(errors[k][a]);
      EXPECT_NEAR(*axes[a], std, 1e-12 * std) << k << " " << a;
      EXPECT_NEAR(*means[a], stats::Mean(errors[k][a]), 1e-12 * std) << k << " " << a;
    }
    double sum_sq = 0.0;
    for (size_t t = 0; t < n; ++t) {
      sum_sq += errors[k][0][t] * errors[k][0][t] + errors[k][1][t] * errors[k][1][t];
    }
    EXPECT_NEAR(r.radial_rms_mm, std::sqrt(sum_sq / static_cast<double>(n)), 1e-12);
  }
  // ml counters over both blocks, the first non-converged trial as a trial of the point.
  const EstimatorResult& ml = result.points[0].estimators[1];
  int64_t nonconverged = 0, first_nonconverged = -1, steps = 0, in_second_block = 0;
  for (size_t t = 0; t < n; ++t) {
    steps += iterations[t];
    if (termination[t] == static_cast<uint8_t>(estimate::Termination::kConverged)) continue;
    if (first_nonconverged < 0) first_nonconverged = static_cast<int64_t>(t);
    ++nonconverged;
    in_second_block += static_cast<int64_t>(t) >= kStatisticsBlockTrials ? 1 : 0;
  }
  EXPECT_GT(in_second_block, 0);
  EXPECT_EQ(ml.nonconverged, nonconverged);
  EXPECT_EQ(ml.first_nonconverged_trial, first_nonconverged);
  EXPECT_EQ(ml.mean_iterations, static_cast<double>(steps) / static_cast<double>(n));
  // The KS and Wilcoxon comparison: the first block's trials, exactly.
  ASSERT_TRUE(ml.vs_fast.computed);
  EXPECT_EQ(ml.vs_fast.trials, kStatisticsBlockTrials);
  const auto head = [](const std::vector<double>& v) {
    return std::span<const double>(v).first(static_cast<size_t>(kStatisticsBlockTrials));
  };
  EXPECT_EQ(ml.vs_fast.ks_x.d, stats::KsTwoSample(head(errors[0][0]), head(errors[1][0])).d);
  EXPECT_EQ(ml.vs_fast.ks_theta.p_value,
            stats::KsTwoSample(head(errors[0][2]), head(errors[1][2])).p_value);
  // The paired Wilcoxon tests of |position error| and |theta error| on the same trials, from
  // differences computed here trial by trial (rounding below 1e-10 + 1e-12 relative is a zero;
  // x^2 + y^2 by the moments' rule, fma(x, x, y * y) where the target has FMA).
  const size_t m = static_cast<size_t>(kStatisticsBlockTrials);
  std::vector<double> d_position(m), d_theta(m);
  const auto difference = [](double a, double b) {
    const double diff = a - b;
    return std::abs(diff) <= 1e-10 + 1e-12 * std::max(std::abs(a), std::abs(b)) ? 0.0 : diff;
  };
  const auto radius = [](double x, double y) {
#ifdef __FMA__
    return std::sqrt(std::fma(x, x, y * y));
#else
    const double yy = y * y;
    return std::sqrt(x * x + yy);
#endif
  };
  for (size_t t = 0; t < m; ++t) {
    d_position[t] = difference(radius(errors[0][0][t], errors[0][1][t]),
                               radius(errors[1][0][t], errors[1][1][t]));
    d_theta[t] = difference(std::abs(errors[0][2][t]), std::abs(errors[1][2][t]));
  }
  const stats::WilcoxonResult position = stats::WilcoxonSignedRank(d_position);
  const stats::WilcoxonResult theta = stats::WilcoxonSignedRank(d_theta);
  EXPECT_EQ(ml.vs_fast.wilcoxon_position.r_plus, position.r_plus);
  EXPECT_EQ(ml.vs_fast.wilcoxon_position.n_zero, position.n_zero);
  EXPECT_EQ(ml.vs_fast.wilcoxon_position.p_value, position.p_value);
  EXPECT_EQ(ml.vs_fast.wilcoxon_theta.r_plus, theta.r_plus);
  EXPECT_EQ(ml.vs_fast.wilcoxon_theta.p_value, theta.p_value);
}

TEST(Runner, CameraNoiseModelsReportTheirOwnFirstOrderPrediction) {
  // With camera roll the pred_* columns come from noise_prediction.h (the angle gains the roll's
  // variance), not from the independent-noise formula.
  Experiment e = SmallExperiment({"butterfly"}, {1.0}, 2000);
  e.estimators = {Estimator::kFast, Estimator::kMl};
  e.noise.rotation_jitter_rad = 0.004;
  const RunResult result = RunExperiment(e, {});
  const estimate::Model model = estimate::Model::FromPattern(e.patterns[0]);
  for (const EstimatorResult& r : result.points[0].estimators) {
    const PredictedError p =
        PredictError(model, r.estimator, e.noise, 1.0, e.field_length_mm, e.field_width_mm);
    EXPECT_EQ(r.predicted_theta_rad, p.theta_rad);
    EXPECT_EQ(r.predicted_position_mm, p.position_mm);
    const double independent = estimate::PredictedStd(model, r.estimator).theta;
    EXPECT_NEAR(r.predicted_theta_rad, std::hypot(independent, 0.004), 1e-9);
  }
}

TEST(Replay, NoiseFreeTrialIsRecoveredByEveryEstimator) {
  // Point 0 is (triangle, sigma 0): every estimator must return the true pose of the trial.
  const Experiment e = SmallExperiment({"triangle", "butterfly"}, {0.0, 2.0}, 100);
  const TrialReplay r = ReplayTrial(e, ParseReplayIndex("0,42", "TRIAL"));
  EXPECT_EQ(r.pattern->name, e.patterns[0].name);
  EXPECT_EQ(r.observed.size(), static_cast<size_t>(e.patterns[0].size()));
  for (Estimator est : r.estimators) {
    const Pose2& p = r.estimates[static_cast<size_t>(est)];
    EXPECT_NEAR(p.x_mm, r.truth.x_mm, 1e-9);
    EXPECT_NEAR(p.y_mm, r.truth.y_mm, 1e-9);
    EXPECT_NEAR(WrapAngle(p.theta_rad - r.truth.theta_rad), 0.0, 1e-12);
  }
  // Point 3 is (butterfly, sigma 2): the same trial drawn twice is the same, another differs.
  const TrialReplay a = ReplayTrial(e, {3, 7, "3,7"});
  const TrialReplay b = ReplayTrial(e, {3, 7, "3,7"});
  const TrialReplay c = ReplayTrial(e, {3, 8, "3,8"});
  EXPECT_EQ(a.observed[0], b.observed[0]);
  EXPECT_NE(a.observed[0], c.observed[0]);
  EXPECT_NE(a.estimates[0].x_mm, a.truth.x_mm);
}

TEST(Replay, BadRequestsAreInputErrors) {
  const Experiment e = SmallExperiment({"triangle"}, {1.0}, 100);
  EXPECT_INPUT_ERROR(ParseReplayIndex("3;4", "TRIAL"),
                     "--replay is '3;4'; expected POINT,TRIAL (two integers >= 0)");
  EXPECT_INPUT_ERROR(ParseReplayIndex("-1,4", "FRAME"),
                     "--replay is '-1,4'; expected POINT,FRAME (two integers >= 0)");
  EXPECT_INPUT_ERROR(ReplayTrial(e, ParseReplayIndex("1,0", "TRIAL")),
                     "--replay 1,0 is out of range; expected POINT < 1 and TRIAL < 100");
  EXPECT_INPUT_ERROR(ReplayTrial(e, ParseReplayIndex("0,100", "TRIAL")),
                     "--replay 0,100 is out of range; expected POINT < 1 and TRIAL < 100");
}

}  // namespace
}  // namespace patlab::sim
