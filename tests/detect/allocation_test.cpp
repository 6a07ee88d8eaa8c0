// The detector's hot path does not allocate once its buffers have grown (docs/architecture.md rule
// 7): global operator new is counted while a frame is detected a second time.
#include <gtest/gtest.h>

#include "../allocation_counter.h"

#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/sim/scene.h"

namespace patlab::detect {
namespace {

TEST(DetectorAllocation, SecondDetectOfAFrameDoesNotAllocate) {
  Detector detector(
      formats::LoadDetectorSettings(std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml"));
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

TEST(DetectorAllocation, SecondTimedDetectDoesNotAllocate) {
  // A TimeProfile gets its stage entries on the first frame; later frames only add to them.
  Detector detector(
      formats::LoadDetectorSettings(std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml"));
  sim::SceneOptions options;
  RandomStream rng(8, 0, 0);
  const sim::Scene scene = sim::GenerateScene(detector, options, sim::PatchNoise{0.5, {}}, rng);
  std::vector<Detection> detections;
  DetectStats stats;
  TimeProfile profile(/*enabled=*/true);
  detector.Detect(scene.blobs, &detections, &stats, &profile);
  const long before = testing::AllocationCount();
  detector.Detect(scene.blobs, &detections, &stats, &profile);
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_EQ(profile.entries().size(), kDetectStageNames.size());
  EXPECT_EQ(profile.entries().front().count, 2);
}

}  // namespace
}  // namespace patlab::detect
