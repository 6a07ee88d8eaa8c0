// The detector's hot path does not allocate once its buffers have grown (docs/architecture.md rule 7):
// global operator new is counted while a frame is detected a second time.
#include <gtest/gtest.h>

#include "../allocation_counter.h"

#include "patlab/sim/scene.h"
#include "patlab/detect/settings.h"

namespace patlab::detect {
namespace {

TEST(DetectorAllocation, SecondDetectOfAFrameDoesNotAllocate) {
  Detector detector(
      LoadDetectorSettings(std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml"));
  sim::SceneOptions options;
  options.false_blob_rate_per_m2 = 1.0;
  RandomStream rng(8, 0, 0);
  const sim::Scene scene = sim::GenerateScene(detector, options, sim::PatchNoise{0.5, {}}, rng);
  std::vector<Detection> detections;
  DetectStats stats;
  const long start = testing::AllocationCount();
  detector.Detect(scene.blobs, &detections, &stats);  // grows the buffers
  EXPECT_GT(testing::AllocationCount() - start, 0);   // the counter sees allocations
  ASSERT_EQ(detections.size(), 10u);
  const long before = testing::AllocationCount();
  detector.Detect(scene.blobs, &detections, &stats);
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_EQ(detections.size(), 10u);
}

}  // namespace
}  // namespace patlab::detect
