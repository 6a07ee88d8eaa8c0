// The Monte-Carlo kernel's versions (baseline x86-64, AVX2, AVX-512: batch.h) give the same bits,
// and GenerateTrial reproduces the inputs every version ran on.
#include "patlab/sim/batch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <string>
#include <vector>

#include "../test_util.h"
#include "point_setup.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;

// Every output of `batches` batches (the last one partial) of one point, as bytes.
std::vector<uint8_t> RunAll(KernelIsa isa, const PointSetup& setup, int batches) {
  const int trials = batches * kBatchSize - 37;
  std::vector<double> buffers[4][3];
  std::vector<uint8_t> iterations(trials), termination(trials);
  for (auto& b : buffers) {
    for (auto& v : b) v.assign(trials, 0.0);
  }
  for (int b = 0; b < batches; ++b) {
    const int first = b * kBatchSize;
    BatchOutput out;
    for (int e = 0; e < 4; ++e) {
      if (!setup.run[e]) continue;
      out.errors[e] = {buffers[e][0].data() + first, buffers[e][1].data() + first,
                       buffers[e][2].data() + first};
    }
    out.ml_iterations = iterations.data() + first;
    out.ml_termination = termination.data() + first;
    RunBatchWith(isa, setup, static_cast<uint64_t>(first), std::min(kBatchSize, trials - first),
                 out);
  }
  // Appended with std::copy rather than insert: GCC 12 at -O2 mistakes the latter's memmove for
  // one past the end (-Warray-bounds).
  std::vector<uint8_t> bytes(iterations.begin(), iterations.end());
  std::copy(termination.begin(), termination.end(), std::back_inserter(bytes));
  for (auto& b : buffers) {
    for (auto& v : b) {
      const auto* p = reinterpret_cast<const uint8_t*>(v.data());
      bytes.insert(bytes.end(), p, p + v.size() * sizeof(double));
    }
  }
  return bytes;
}

struct Case {
  std::string name;
  NoiseModel noise;
  double sigma_mm;
};

std::vector<Case> Cases() {
  std::vector<Case> cases;
  cases.push_back({"isotropic", {}, 2.0});
  cases.push_back({"noise-free", {}, 0.0});
  NoiseModel aniso;
  aniso.sigma_y_ratio = 2.5;
  aniso.common_sigma_ratio = 0.5;
  cases.push_back({"anisotropic+common", aniso, 1.0});
  NoiseModel outliers;
  outliers.outlier_probability = 0.05;
  outliers.outlier_sigma_ratio = 8.0;
  cases.push_back({"outliers", outliers, 3.0});
  NoiseModel camera;
  camera.correlation_length_mm = 50.0;
  camera.rotation_jitter_rad = 0.002;
  camera.scale_jitter_ppm = 300.0;
  camera.key_shift_x_mm = 0.3;
  camera.id_shift_x_mm = -0.2;
  cases.push_back({"camera", camera, 1.5});
  return cases;
}

TEST(Batch, EveryKernelVersionGivesTheBitsOfTheBaseline) {
  const std::vector<KernelIsa> isas = SupportedKernelIsas();
  ASSERT_FALSE(isas.empty());
  EXPECT_EQ(isas.front(), KernelIsa::kBaseline);
  if (isas.size() == 1) {
    GTEST_LOG_(INFO) << "only the baseline kernel on this CPU or build";
  }
  for (const char* pattern : {"butterfly", "triangle", "simple"}) {
    const estimate::Model model = estimate::Model::FromPattern(testing::ShippedPattern(pattern));
    for (const Case& c : Cases()) {
      SCOPED_TRACE(std::string(pattern) + " " + c.name);
      PointSetup setup = testing::FieldPoint(model, c.sigma_mm,
                                             0x5EEDull + static_cast<uint64_t>(c.sigma_mm * 100));
      setup.noise = c.noise;
      for (Estimator e : estimate::kAllEstimators) setup.run[static_cast<int>(e)] = true;
      const std::vector<uint8_t> baseline = RunAll(KernelIsa::kBaseline, setup, 3);
      for (KernelIsa isa : isas) {
        EXPECT_EQ(RunAll(isa, setup, 3), baseline) << "kernel version " << static_cast<int>(isa);
      }
    }
  }
}

TEST(Batch, GenerateTrialReplaysTheTrialsOfTheWidestKernel) {
  // The scalar fast estimator on GenerateTrial's inputs gives the errors the widest kernel wrote
  // for the same trials (to rounding: another implementation of the same estimator; a trial
  // from another batch or lane would be off by millimetres).
  const estimate::Model model = estimate::Model::FromPattern(testing::ShippedPattern("triangle"));
  PointSetup setup = testing::FieldPoint(model, 1.0, 99);
  setup.run[static_cast<int>(Estimator::kFast)] = true;
  std::vector<double> x(kBatchSize), y(kBatchSize), t(kBatchSize);
  BatchOutput out;
  out.errors[static_cast<int>(Estimator::kFast)] = {x.data(), y.data(), t.data()};
  RunBatch(setup, kBatchSize, kBatchSize, out);
  for (int k : {0, 1, 7, 500, kBatchSize - 1}) {
    Pose2 truth;
    std::vector<Vec2> observed(model.num_patches);
    GenerateTrial(setup, kBatchSize + k, &truth, observed.data());
    const Pose2 fast = estimate::Fast(model, observed.data());
    EXPECT_NEAR(fast.x_mm - truth.x_mm, x[k], 1e-9) << k;
    EXPECT_NEAR(fast.y_mm - truth.y_mm, y[k], 1e-9) << k;
  }
}

}  // namespace
}  // namespace patlab::sim
