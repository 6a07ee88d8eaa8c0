// The camera-level noise models (sim/noise.h): each one's Monte-Carlo std against its first-order
// prediction (sim/noise_prediction.h), with a tolerance of 4 standard errors of the sample std
// computed from the sample's own fourth moment (docs/architecture.md rule 10) plus the
// prediction's second-order term, bounded separately below; the correlation of the correlated
// model against exp(-d / L); the streams of the older models untouched.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../expect_error.h"
#include "../test_util.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/noise_prediction.h"
#include "patlab/sim/point_key.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;

constexpr int kBatches = 96;  // 98,304 trials per case
constexpr double kLength = 2800.0, kWidth = 2300.0;

// Sample std and its standard error sqrt((m4 - s^4) / N) / (2 s) of one error column.
struct SampleStd {
  double std = 0.0;
  double se = 0.0;
};

double Mean(const std::vector<double>& a) {
  double s = 0.0;
  for (double v : a) s += v;
  return a.empty() ? 0.0 : s / static_cast<double>(a.size());
}

// Pools a and b (x and y, each about its own mean) as the results' std_pos does; b may be empty.
SampleStd Measure(const std::vector<double>& a, const std::vector<double>& b) {
  double m2 = 0.0, m4 = 0.0;
  for (const std::vector<double>* column : {&a, &b}) {
    const double mean = Mean(*column);
    for (double v : *column) {
      const double d = (v - mean) * (v - mean);
      m2 += d;
      m4 += d * d;
    }
  }
  const double count = static_cast<double>(a.size() + b.size());
  m2 /= count;
  m4 /= count;
  SampleStd r;
  r.std = std::sqrt(m2);
  r.se = std::sqrt((m4 - m2 * m2) / count) / (2.0 * r.std);
  return r;
}

struct Errors {
  std::vector<double> x, y, theta;
};

// Every trial of the point through RunBatch, errors of `estimator`.
Errors Simulate(const estimate::Model& model, const NoiseModel& noise, double sigma_mm,
                Estimator estimator, uint64_t seed) {
  PointSetup setup;
  setup.model = &model;
  setup.noise = noise;
  setup.sigma_mm = sigma_mm;
  setup.field_length_mm = kLength;
  setup.field_width_mm = kWidth;
  setup.seed = seed;
  setup.run[static_cast<int>(Estimator::kFast)] = true;
  setup.run[static_cast<int>(estimator)] = true;
  const int trials = kBatches * kBatchSize;
  std::vector<double> buffers[4][3];
  std::vector<uint8_t> iterations(trials), termination(trials);
  for (auto& b : buffers) {
    for (auto& v : b) v.resize(trials);
  }
  for (int b = 0; b < kBatches; ++b) {
    BatchOutput out;
    for (int e = 0; e < 4; ++e) {
      out.errors[e] = {buffers[e][0].data() + b * kBatchSize, buffers[e][1].data() + b * kBatchSize,
                       buffers[e][2].data() + b * kBatchSize};
    }
    out.ml_iterations = iterations.data() + b * kBatchSize;
    out.ml_termination = termination.data() + b * kBatchSize;
    RunBatch(setup, static_cast<uint64_t>(b) * kBatchSize, kBatchSize, out);
  }
  auto& chosen = buffers[static_cast<int>(estimator)];
  return {chosen[0], chosen[1], chosen[2]};
}

void ExpectPredicted(const NoiseModel& noise, double sigma_mm, uint64_t seed) {
  const estimate::Model model = estimate::Model::FromPattern(testing::ShippedPattern("butterfly"));
  for (Estimator e : {Estimator::kFast, Estimator::kMl}) {
    SCOPED_TRACE(std::string(noise.Describe()) + (e == Estimator::kFast ? " fast" : " ml"));
    const Errors errors = Simulate(model, noise, sigma_mm, e, seed);
    const PredictedError predicted = PredictError(model, e, noise, sigma_mm, kLength, kWidth);
    const SampleStd pos = Measure(errors.x, errors.y);
    const SampleStd theta = Measure(errors.theta, {});
    EXPECT_NEAR(pos.std, predicted.position_mm, 4.0 * pos.se);
    EXPECT_NEAR(theta.std, predicted.theta_rad, 4.0 * theta.se);
  }
}

TEST(CameraNoise, RotationJitterMovesTheAngleByItsStdAndThePositionByItsLever) {
  NoiseModel noise;
  noise.rotation_jitter_rad = 0.004;
  ExpectPredicted(noise, 0.5, 11);
}

TEST(CameraNoise, ScaleJitterMovesOnlyThePosition) {
  NoiseModel noise;
  noise.scale_jitter_ppm = 400.0;
  ExpectPredicted(noise, 0.5, 12);
}

TEST(CameraNoise, CorrelatedNoiseMatchesTheCorrelatedJacobian) {
  NoiseModel noise;
  noise.correlation_length_mm = 60.0;
  ExpectPredicted(noise, 1.0, 13);
}

TEST(CameraNoise, ColourBiasSpreadsOverHeading) {
  NoiseModel noise;
  noise.key_shift_x_mm = 0.4;
  noise.id_shift_x_mm = -0.3;
  ExpectPredicted(noise, 0.5, 14);
}

TEST(CameraNoise, AllModelsTogetherAddInVariance) {
  NoiseModel noise;
  noise.common_sigma_ratio = 0.3;
  noise.rotation_jitter_rad = 0.002;
  noise.scale_jitter_ppm = 200.0;
  noise.correlation_length_mm = 40.0;
  noise.key_shift_x_mm = 0.2;
  ExpectPredicted(noise, 0.5, 15);
}

// Sample correlation of patch 1's and patch 2's x errors (the two front ID patches, 109.5 mm
// apart) against exp(-d / L), from the replayed trials; standard error (1 - rho^2) / sqrt(N).
TEST(CameraNoise, CorrelationDecaysWithPatchDistance) {
  const estimate::Model model = estimate::Model::FromPattern(testing::ShippedPattern("butterfly"));
  PointSetup setup;
  setup.model = &model;
  setup.noise.correlation_length_mm = 80.0;
  setup.sigma_mm = 1.0;
  setup.field_length_mm = kLength;
  setup.field_width_mm = kWidth;
  setup.seed = 16;
  const int n = 4096;
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (int t = 0; t < n; ++t) {
    Pose2 truth;
    std::array<Vec2, kMaxPatches> observed;
    GenerateTrial(setup, static_cast<uint64_t>(t) * 7, &truth, observed.data());
    const double a = observed[1].x() - truth.Apply(model.model_mm[1]).x();
    const double b = observed[2].x() - truth.Apply(model.model_mm[2]).x();
    sxy += a * b;
    sxx += a * a;
    syy += b * b;
  }
  const double rho = sxy / std::sqrt(sxx * syy);
  const double expected = std::exp(-(model.model_mm[1] - model.model_mm[2]).norm() / 80.0);
  EXPECT_NEAR(rho, expected, 4.0 * (1.0 - expected * expected) / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sxx / n), 1.0, 4.0 / std::sqrt(2.0 * n));  // each patch keeps sigma
}

// The older models' points keep their streams: the camera fields join the key only when on.
TEST(CameraNoise, OlderModelsKeepTheirStreamKeys) {
  const Pattern pattern = testing::ShippedPattern("butterfly");
  NoiseModel old_model;
  old_model.common_sigma_ratio = 0.5;
  NoiseModel with_camera = old_model;
  with_camera.rotation_jitter_rad = 0.001;
  EXPECT_NE(KnownPointKey(2003, pattern, old_model, 1.0),
            KnownPointKey(2003, pattern, with_camera, 1.0));
  with_camera.rotation_jitter_rad = 0.0;
  EXPECT_EQ(KnownPointKey(2003, pattern, old_model, 1.0),
            KnownPointKey(2003, pattern, with_camera, 1.0));
}

TEST(CameraNoise, ValidationNamesTheFieldAndTheRange) {
  NoiseModel noise;
  noise.scale_jitter_ppm = -1.0;
  EXPECT_INPUT_ERROR(Validate(noise),
                     "scale_jitter_ppm is -1; expected a number in [0, 100000] (ppm)");
  noise = NoiseModel{};
  noise.key_shift_x_mm = 101.0;
  EXPECT_INPUT_ERROR(Validate(noise),
                     "key_shift_x_mm is 101; expected a number in [-100, 100] (mm)");
}

}  // namespace
}  // namespace patlab::sim
