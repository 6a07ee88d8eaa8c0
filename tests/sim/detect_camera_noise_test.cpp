// The camera-level noise models in detect mode (sim/noise.h FrameCameraNoise through
// GenerateDetectFrame): whole frames of Butterflies through the detector, each model's pose std
// against its first-order prediction (sim/noise_prediction.h, the same formulas the known mode is
// checked against), within 4 standard errors of a sample std, sqrt(1 / (2 N)) relative for
// Gaussian errors (docs/architecture.md rule 10), plus the independent part's share when it is
// not predicted exactly. The detector's estimator is the paper's fast one. Robots stand inside
// the field less their radius (90 mm), so the prediction's field is 180 mm shorter each way. A
// frame's roll and scale are shared by its ten robots, so for the jitter models the standard error
// counts frames, not robots.
#include <gtest/gtest.h>

#include <cmath>

#include "../experiment_fixture.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/sim/detect_runner.h"
#include "patlab/sim/noise_prediction.h"

namespace patlab::sim {
namespace {

class DetectCameraNoise : public testing_support::ExperimentFixture {
 protected:
  void SetUp() override {
    CopyPatterns({"butterfly"});
    dir_.Write("experiments/det.toml",
               "palette = [\"blue\", \"yellow\", \"pink\", \"green\", \"orange\"]\n"
               "[[pattern]]\npattern = \"butterfly\"\nid_colours = [\"pink\", \"green\"]\n"
               "key_colours = [\"blue\", \"yellow\"]\n");
  }
  // One point at sigma 0.05 mm, 400 frames of 10 robots, with `noise` as the [noise] table.
  DetectPointResult Run(const std::string& noise) {
    const Experiment e = formats::LoadExperimentFile(
        Write("name = \"x\"\ncorrespondence = \"detect\"\npatterns = [\"butterfly\"]\n"
              "[sigma]\nvalues = [0.05]\n[detect]\nsettings = \"det.toml\"\nframes = 1500\n"
              "[noise]\n" +
              noise));
    experiment_ = e;
    RunOptions options;
    options.threads = 2;
    const DetectRunResult r = RunDetectExperiment(e, options);
    EXPECT_EQ(r.points.size(), 1u);
    EXPECT_EQ(r.points[0].correct, r.points[0].robots);
    return r.points[0];
  }
  PredictedError Predict() const {
    return PredictError(estimate::Model::FromPattern(experiment_.patterns[0]),
                        estimate::Estimator::kFast, experiment_.noise, 0.05,
                        experiment_.field_length_mm - 180.0, experiment_.field_width_mm - 180.0);
  }
  Experiment experiment_;
};

// 4 standard errors of a sample std from n Gaussian samples, relative: per robot, or per frame.
double FourSe(const DetectPointResult& r) { return 4.0 / std::sqrt(2.0 * r.correct); }
double FourSePerFrame(const DetectPointResult& r) { return 4.0 / std::sqrt(2.0 * r.frames); }

double Pooled(const DetectPointResult& r) {
  return std::sqrt((r.x.std * r.x.std + r.y.std * r.y.std) / 2.0);
}

TEST_F(DetectCameraNoise, RotationJitterTurnsEveryRobotAndMovesItAcrossTheField) {
  const DetectPointResult r = Run("rotation_jitter_rad = 0.004\n");
  const PredictedError p = Predict();
  EXPECT_NEAR(r.theta.std, p.theta_rad, FourSePerFrame(r) * p.theta_rad);
  EXPECT_NEAR(Pooled(r), p.position_mm, FourSePerFrame(r) * p.position_mm);
  // Without the model the angle error is the patch noise alone, ten times smaller.
  EXPECT_LT(Run("sigma_y_ratio = 1\n").theta.std, 0.1 * p.theta_rad);
}

TEST_F(DetectCameraNoise, ScaleJitterMovesThePositionNotTheAngle) {
  const DetectPointResult r = Run("scale_jitter_ppm = 2000\n");
  const PredictedError p = Predict();
  EXPECT_NEAR(Pooled(r), p.position_mm, FourSePerFrame(r) * p.position_mm);
  EXPECT_LT(r.theta.std, 0.001);
}

TEST_F(DetectCameraNoise, ColourEdgeBiasSpreadsWithHeading) {
  const DetectPointResult r = Run("key_shift_x_mm = 1.5\n");
  const PredictedError p = Predict();
  EXPECT_NEAR(Pooled(r), p.position_mm, FourSe(r) * p.position_mm + 0.01);
  EXPECT_NEAR(r.theta.std, p.theta_rad, FourSe(r) * p.theta_rad + 0.0005);
}

TEST_F(DetectCameraNoise, CorrelatedNoiseMovesNeighboursTogether) {
  // Sigma 0.05 is too small to see; the correlated model scales sigma's independent errors, so
  // a larger sigma through the same frames: 1 mm (still far inside the detector's tolerance).
  const Experiment e = formats::LoadExperimentFile(
      Write("name = \"x\"\ncorrespondence = \"detect\"\npatterns = [\"butterfly\"]\n"
            "[sigma]\nvalues = [0.5]\n[detect]\nsettings = \"det.toml\"\nframes = 1500\n"
            "[noise]\ncorrelation_length_mm = 100\n"));
  RunOptions options;
  options.threads = 2;
  const DetectPointResult r = RunDetectExperiment(e, options).points.at(0);
  const PredictedError p =
      PredictError(estimate::Model::FromPattern(e.patterns[0]), estimate::Estimator::kFast, e.noise,
                   0.5, e.field_length_mm - 180.0, e.field_width_mm - 180.0);
  EXPECT_NEAR(Pooled(r), p.position_mm, FourSe(r) * p.position_mm);
  EXPECT_NEAR(r.theta.std, p.theta_rad, FourSe(r) * p.theta_rad);
}

}  // namespace
}  // namespace patlab::sim
