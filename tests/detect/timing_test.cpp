// Per-stage timing of the detector (a TimeProfile passed to Detect): filled only when asked for,
// named as detector.h numbers the stages, each non-negative, the stages partitioning the call,
// and no change to what is detected.
#include <gtest/gtest.h>

#include <chrono>
#include <string_view>
#include <vector>

#include "patlab/detect/detector.h"
#include "patlab/detect/settings.h"
#include "patlab/formats/detector_settings.h"
#include "patlab/sim/scene.h"

namespace patlab::detect {
namespace {

struct DetectorAndScene {
  Detector detector;
  sim::Scene scene;
};

// Ten robots and a ball with false blobs, as the allocation test and detect_bench use.
DetectorAndScene ShippedFrame() {
  Detector detector(
      formats::LoadDetectorSettings(std::string(PATLAB_SOURCE_DIR) + "/experiments/detector.toml"));
  sim::SceneOptions options;
  options.false_blob_rate_per_m2 = 1.0;
  RandomStream rng(8, 0, 0);
  sim::Scene scene = sim::GenerateScene(detector, options, sim::PatchNoise{0.5, {}}, rng);
  return {std::move(detector), std::move(scene)};
}

// The profile's stage names, in order.
std::vector<std::string_view> Names(const TimeProfile& profile) {
  std::vector<std::string_view> names;
  for (const TimeProfile::Entry& e : profile.entries()) names.push_back(e.stage);
  return names;
}

double Seconds(const TimeProfile& profile, std::string_view stage) {
  for (const TimeProfile::Entry& e : profile.entries()) {
    if (e.stage == stage) return e.seconds;
  }
  return -1.0;
}

TEST(DetectorTiming, NotRequestedLeavesTheProfileEmpty) {
  DetectorAndScene f = ShippedFrame();
  std::vector<Detection> detections;
  DetectStats stats;
  TimeProfile disabled;  // not enabled: Detect reads no clock and adds nothing
  f.detector.Detect(f.scene.blobs, &detections, &stats, &disabled);
  ASSERT_EQ(detections.size(), 10u);
  EXPECT_FALSE(disabled.enabled());
  EXPECT_TRUE(disabled.entries().empty());
  f.detector.Detect(f.scene.blobs, &detections, &stats, nullptr);
  EXPECT_EQ(detections.size(), 10u);
}

TEST(DetectorTiming, RequestedFillsEveryStageAndTheyPartitionTheCall) {
  DetectorAndScene f = ShippedFrame();
  std::vector<Detection> detections;
  DetectStats stats;
  TimeProfile profile(/*enabled=*/true);
  const auto before = std::chrono::steady_clock::now();
  f.detector.Detect(f.scene.blobs, &detections, &stats, &profile);
  const double outside_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();
  ASSERT_EQ(detections.size(), 10u);
  // One entry per stage of the header, in its order, each stamped once.
  EXPECT_EQ(Names(profile),
            std::vector<std::string_view>(kDetectStageNames.begin(), kDetectStageNames.end()));
  for (const TimeProfile::Entry& e : profile.entries()) {
    EXPECT_GE(e.seconds, 0.0) << e.stage;
    EXPECT_EQ(e.count, 1) << e.stage;
  }
  EXPECT_GT(profile.total_seconds(), 0.0);
  // The stages partition the call, so their sum is the call's time (and never more).
  EXPECT_LE(profile.total_seconds(), outside_s);
  // Every stage here did work (10 robots: keys, neighbours, rotations, IDs, poses), and each
  // timed interval holds at least one clock read.
  EXPECT_GT(stats.key_candidates, 0);
  EXPECT_GT(stats.correspondences, 0);
  EXPECT_GT(Seconds(profile, "2 neighbours"), 0.0);
  EXPECT_GT(Seconds(profile, "3 radial sort"), 0.0);
  EXPECT_GT(Seconds(profile, "4 fit rotations"), 0.0);
  EXPECT_GT(Seconds(profile, "5 identify"), 0.0);
  EXPECT_GT(Seconds(profile, "8 pose"), 0.0);
  EXPECT_EQ(Seconds(profile, "6 missing patch"), 0.0);  // MissingPatchPolicy::kReject
}

TEST(DetectorTiming, TimingChangesNeitherDetectionsNorCounters) {
  DetectorAndScene f = ShippedFrame();
  std::vector<Detection> plain, timed;
  DetectStats plain_stats, timed_stats;
  TimeProfile profile(/*enabled=*/true);
  f.detector.Detect(f.scene.blobs, &plain, &plain_stats);
  f.detector.Detect(f.scene.blobs, &timed, &timed_stats, &profile);
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
  // A timed call followed by an untimed one on the same Detector: nothing added to the profile.
  const double timed_total = profile.total_seconds();
  DetectStats again;
  f.detector.Detect(f.scene.blobs, &plain, &again);
  EXPECT_EQ(profile.total_seconds(), timed_total);
}

TEST(DetectorTiming, SumsOverFrames) {
  DetectorAndScene f = ShippedFrame();
  std::vector<Detection> detections;
  DetectStats a, b;
  TimeProfile first(true), second(true);
  f.detector.Detect(f.scene.blobs, &detections, &a, &first);
  f.detector.Detect(f.scene.blobs, &detections, &b, &second);
  const double expected = first.total_seconds() + second.total_seconds();
  first += second;  // stage by stage, in the header's order
  EXPECT_EQ(Names(first), Names(second));
  for (const TimeProfile::Entry& e : first.entries()) EXPECT_EQ(e.count, 2) << e.stage;
  EXPECT_NEAR(first.total_seconds(), expected, 1e-12);
  const long candidates = a.key_candidates;
  a += b;
  EXPECT_EQ(a.key_candidates, 2 * candidates);
  EXPECT_EQ(a.detections, 20);
}

}  // namespace
}  // namespace patlab::detect
