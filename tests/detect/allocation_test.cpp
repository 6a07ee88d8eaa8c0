// The detector's hot path does not allocate once its buffers have grown (DESIGN.md rule 7):
// global operator new is counted while a frame is detected a second time.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "detect/scene.h"
#include "detect/settings.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace patlab::detect {
namespace {

TEST(DetectorAllocation, SecondDetectOfAFrameDoesNotAllocate) {
  Detector detector(
      LoadDetectorSettings(std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml"));
  SceneOptions options;
  options.false_blob_rate_per_m2 = 1.0;
  RandomStream rng(8, 0, 0);
  const Scene scene = GenerateScene(detector, options, PatchNoise{0.5, {}}, rng);
  std::vector<Detection> detections;
  DetectStats stats;
  const long start = g_allocations.load();
  detector.Detect(scene.blobs, &detections, &stats);  // grows the buffers
  EXPECT_GT(g_allocations.load() - start, 0);         // the counter sees allocations
  ASSERT_EQ(detections.size(), 10u);
  const long before = g_allocations.load();
  detector.Detect(scene.blobs, &detections, &stats);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_EQ(detections.size(), 10u);
}

}  // namespace
}  // namespace patlab::detect
