// Per-stage timing of the detector (DetectStats::collect_timing): filled only when asked for,
// each stage non-negative, the stages partitioning the call, and no change to what is detected.
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "patlab/detect/detector.h"
#include "patlab/sim/scene.h"
#include "patlab/detect/settings.h"

namespace patlab::detect {
namespace {

struct Frame {
  Detector detector;
  sim::Scene scene;
};

// Ten robots and a ball with false blobs, as the allocation test and detect_bench use.
Frame ShippedFrame() {
  Detector detector(
      LoadDetectorSettings(std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml"));
  sim::SceneOptions options;
  options.false_blob_rate_per_m2 = 1.0;
  RandomStream rng(8, 0, 0);
  sim::Scene scene = sim::GenerateScene(detector, options, sim::PatchNoise{0.5, {}}, rng);
  return {std::move(detector), std::move(scene)};
}

std::vector<long> Stages(const DetectStageTimes& t) {
  return {t.key_candidates_ns, t.neighbours_ns, t.radial_sort_ns, t.correspondences_ns,
          t.colours_ns,        t.conflicts_ns,  t.pose_ns};
}

TEST(DetectorTiming, NotRequestedLeavesEveryTimeZero) {
  Frame f = ShippedFrame();
  std::vector<Detection> detections;
  DetectStats stats;
  stats.time.total_ns = 123;  // overwritten: times are zero unless requested
  stats.time.pose_ns = 45;
  f.detector.Detect(f.scene.blobs, &detections, &stats);
  ASSERT_EQ(detections.size(), 10u);
  EXPECT_FALSE(stats.collect_timing);
  EXPECT_EQ(stats.time.total_ns, 0);
  for (long ns : Stages(stats.time)) EXPECT_EQ(ns, 0);
}

TEST(DetectorTiming, RequestedFillsEveryStageAndTheyPartitionTheCall) {
  Frame f = ShippedFrame();
  std::vector<Detection> detections;
  DetectStats stats;
  stats.collect_timing = true;
  const auto before = std::chrono::steady_clock::now();
  f.detector.Detect(f.scene.blobs, &detections, &stats);
  const long outside_ns = static_cast<long>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                std::chrono::steady_clock::now() - before)
                                                .count());
  ASSERT_EQ(detections.size(), 10u);
  EXPECT_TRUE(stats.collect_timing);  // kept: the next call is timed too
  const DetectStageTimes& t = stats.time;
  for (long ns : Stages(t)) EXPECT_GE(ns, 0);
  EXPECT_GT(t.total_ns, 0);
  EXPECT_LE(t.total_ns, outside_ns);
  // Every stage here did work (10 robots: keys, neighbours, rotations, IDs, poses), and each
  // timed interval holds at least one clock read.
  EXPECT_GT(stats.key_candidates, 0);
  EXPECT_GT(stats.correspondences, 0);
  EXPECT_GT(t.neighbours_ns, 0);
  EXPECT_GT(t.radial_sort_ns, 0);
  EXPECT_GT(t.correspondences_ns, 0);
  EXPECT_GT(t.colours_ns, 0);
  EXPECT_GT(t.pose_ns, 0);
  // The stages partition the call, so their sum is the total (and never more).
  EXPECT_LE(t.StagesSum(), t.total_ns);
  EXPECT_EQ(t.StagesSum(), t.total_ns);
}

TEST(DetectorTiming, TimingChangesNeitherDetectionsNorCounters) {
  Frame f = ShippedFrame();
  std::vector<Detection> plain, timed;
  DetectStats plain_stats, timed_stats;
  timed_stats.collect_timing = true;
  f.detector.Detect(f.scene.blobs, &plain, &plain_stats);
  f.detector.Detect(f.scene.blobs, &timed, &timed_stats);
  ASSERT_EQ(plain.size(), timed.size());
  for (size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(plain[i].id, timed[i].id);
    EXPECT_EQ(plain[i].blob, timed[i].blob);
    EXPECT_EQ(plain[i].pose.x_mm, timed[i].pose.x_mm);
    EXPECT_EQ(plain[i].pose.theta_rad, timed[i].pose.theta_rad);
  }
  EXPECT_EQ(plain_stats.key_candidates, timed_stats.key_candidates);
  EXPECT_EQ(plain_stats.neighbours, timed_stats.neighbours);
  EXPECT_EQ(plain_stats.correspondences, timed_stats.correspondences);
  EXPECT_EQ(plain_stats.geometry_passed, timed_stats.geometry_passed);
  EXPECT_EQ(plain_stats.colour_rejected, timed_stats.colour_rejected);
  EXPECT_EQ(plain_stats.conflicts, timed_stats.conflicts);
  EXPECT_EQ(plain_stats.detections, timed_stats.detections);
  // A timed call followed by an untimed one on the same Detector: no stale times.
  DetectStats again;
  f.detector.Detect(f.scene.blobs, &plain, &again);
  EXPECT_EQ(again.time.total_ns, 0);
}

TEST(DetectorTiming, SumsOverFrames) {
  DetectStats a, b;
  a.time.neighbours_ns = 5;
  a.time.total_ns = 7;
  b.time.neighbours_ns = 11;
  b.time.pose_ns = 2;
  b.time.total_ns = 13;
  a += b;
  EXPECT_EQ(a.time.neighbours_ns, 16);
  EXPECT_EQ(a.time.pose_ns, 2);
  EXPECT_EQ(a.time.total_ns, 20);
  EXPECT_EQ(a.time.StagesSum(), 18);
}

}  // namespace
}  // namespace patlab::detect
