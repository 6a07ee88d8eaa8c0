// The Monte-Carlo inner loop and the estimators do not allocate (docs/architecture.md rule 7):
// global operator new is counted while a batch of trials runs and while every estimator runs.
#include <gtest/gtest.h>

#include "../allocation_counter.h"

#include <vector>

#include "../test_util.h"
#include "patlab/estimate/bounds.h"
#include "patlab/sim/batch.h"
#include "point_setup.h"

namespace patlab::sim {
namespace {

using estimate::Estimator;

TEST(Allocation, CounterSeesAllocations) {
  const long before = testing::AllocationCount();
  std::vector<double> v(100);
  EXPECT_GT(testing::AllocationCount() - before, 0);
}

TEST(Allocation, BatchOfTrialsDoesNotAllocate) {
  const estimate::Model model = estimate::Model::FromPattern(testing::ShippedPattern("butterfly"));
  PointSetup setup = testing::FieldPoint(model, 2.0, 0);
  setup.noise.common_sigma_ratio = 0.5;
  setup.noise.outlier_probability = 0.05;
  // The camera-level models too: the correlation factor is computed per batch on the stack.
  setup.noise.correlation_length_mm = 50.0;
  setup.noise.rotation_jitter_rad = 0.002;
  setup.noise.scale_jitter_ppm = 300.0;
  setup.noise.key_shift_x_mm = 0.3;
  for (Estimator e : estimate::kAllEstimators) setup.run[static_cast<int>(e)] = true;
  std::vector<double> buffers[4][3];
  std::vector<uint8_t> iterations(kBatchSize), termination(kBatchSize);
  BatchOutput out;
  for (Estimator e : estimate::kAllEstimators) {
    auto& b = buffers[static_cast<int>(e)];
    for (auto& v : b) v.resize(kBatchSize);
    out.errors[static_cast<int>(e)] = {b[0].data(), b[1].data(), b[2].data()};
  }
  out.ml_iterations = iterations.data();
  out.ml_termination = termination.data();
  const long before = testing::AllocationCount();
  for (uint64_t b = 0; b < 4; ++b) RunBatch(setup, b * kBatchSize, kBatchSize, out);
  EXPECT_EQ(testing::AllocationCount() - before, 0);
}

TEST(Allocation, EstimatorsDoNotAllocate) {
  const estimate::Model model = estimate::Model::FromPattern(testing::ShippedPattern("triangle"));
  std::array<Vec2, kMaxPatches> v{};
  for (int i = 0; i < model.num_patches; ++i) v[i] = Pose2{1, 2, 0.3}.Apply(model.model_mm[i]);
  v[1] += Vec2(0.7, -0.2);
  const long before = testing::AllocationCount();
  const Pose2 fast = estimate::Fast(model, v.data());
  estimate::Summary summary;
  estimate::MaximumLikelihood(model, v.data(), fast, estimate::Options{}, &summary);
  estimate::LeastSquares(model, v.data());
  estimate::KeyPatch(model, v.data());
  estimate::CramerRaoBound(model);
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_EQ(summary.termination, estimate::Termination::kConverged);
}

}  // namespace
}  // namespace patlab::sim
