// Detector::Detect's explain output: one frame of blobs holding one key candidate per outcome.
#include <gtest/gtest.h>

#include <algorithm>

#include "patlab/detect/detector.h"
#include "patlab/formats/codebook_file.h"
#include "test_util.h"

namespace patlab::detect {
namespace {

using namespace testing;  // NOLINT: test helpers

DetectorPattern SslWithHalfTheIds() {
  DetectorPattern dp;
  dp.pattern = LoadPattern("ssl-standard");
  dp.codebook = formats::LoadCodebookFile(
      std::string(PATLAB_SOURCE_DIR) + "/patterns/ssl-standard.codebook.toml", dp.pattern,
      FindSymmetry(dp.pattern, 10.0));
  dp.key_colours = {"blue", "yellow"};
  return dp;
}

const KeyExplanation& ExplanationOf(const std::vector<KeyExplanation>& all, int key_blob) {
  const auto it = std::find_if(all.begin(), all.end(),
                               [&](const KeyExplanation& e) { return e.key_blob == key_blob; });
  EXPECT_NE(it, all.end()) << key_blob;
  return *it;
}

struct Frame {
  std::vector<Blob> blobs;
  int detected = 0, few = 0, geometry = 0, colours = 0, conflict = 0, winner = 0, key_area = 0;
};

// Robots of the SSL codebook, 1 m apart: (0) complete; (1) two of its four dots; (2) one dot moved
// 25 mm along the ring, so no rotation fits; (3) the colouring of an ID the codebook lacks; (4) a
// complete robot with a second blue key 1 mm beside its key, whose candidate loses its dots to the
// exact one; (5) a blue blob five times the key's area.
Frame MakeFrame(const DetectorPattern& full) {
  Frame f;
  auto key_of = [&](size_t first) {
    for (size_t i = first; i < f.blobs.size(); ++i) {
      if (f.blobs[i].colour == kBlue) return static_cast<int>(i);
    }
    return -1;
  };
  size_t first = f.blobs.size();
  AddRobot(full.pattern, full.codebook, 0, kBlue, Pose2{0, 0, 0.3}, &f.blobs);
  f.detected = key_of(first);
  first = f.blobs.size();
  AddRobot(full.pattern, full.codebook, 1, kBlue, Pose2{1000, 0, 0.3}, &f.blobs);
  f.blobs.erase(f.blobs.end() - 2, f.blobs.end());  // two dots gone
  f.few = key_of(first);
  first = f.blobs.size();
  AddRobot(full.pattern, full.codebook, 2, kBlue, Pose2{2000, 0, 0.3}, &f.blobs);
  f.geometry = key_of(first);
  Blob& moved = f.blobs[first == static_cast<size_t>(f.geometry) ? first + 1 : first];
  const Vec2 radial = (moved.position_mm - f.blobs[f.geometry].position_mm).normalized();
  moved.position_mm += 25.0 * Vec2(-radial.y(), radial.x());
  first = f.blobs.size();
  AddRobot(full.pattern, full.codebook, 12, kBlue, Pose2{3000, 0, 0.3}, &f.blobs);
  f.colours = key_of(first);
  first = f.blobs.size();
  AddRobot(full.pattern, full.codebook, 3, kBlue, Pose2{4000, 0, 0.3}, &f.blobs);
  f.winner = key_of(first);
  f.conflict = static_cast<int>(f.blobs.size());
  Blob twin = f.blobs[static_cast<size_t>(f.winner)];
  twin.position_mm += Vec2(1.0, 0.0);
  f.blobs.push_back(twin);
  f.key_area = static_cast<int>(f.blobs.size());
  f.blobs.push_back({Vec2(5000, 0), kBlue, 5.0 * twin.area_mm2});
  return f;
}

TEST(DetectorExplain, EveryKeyCandidateGetsItsOutcome) {
  const DetectorPattern full = SslWithHalfTheIds();
  DetectorPattern half = full;
  half.codebook.entries.resize(8);  // IDs 0..7: ID 12's colouring is no ID
  Detector detector(MakeConfig({half}));
  const Frame f = MakeFrame(full);
  std::vector<Detection> detections;
  std::vector<KeyExplanation> explain;
  DetectStats stats;
  detector.Detect(f.blobs, &detections, &stats, nullptr, &explain);
  ASSERT_EQ(detections.size(), 2u);
  ASSERT_EQ(explain.size(), 7u);  // every blue blob, in blob order

  const KeyExplanation& ok = ExplanationOf(explain, f.detected);
  EXPECT_EQ(ok.outcome, KeyOutcome::kDetected);
  ASSERT_GE(ok.detection, 0);
  EXPECT_EQ(detections[static_cast<size_t>(ok.detection)].id, 0);
  EXPECT_EQ(ok.neighbours, 4);
  EXPECT_EQ(ok.needed, 4);
  EXPECT_LT(ok.best_e_mm2, 1e-6);
  EXPECT_DOUBLE_EQ(ok.tolerance_mm2, detector.ResidualTolerance(0));

  const KeyExplanation& few = ExplanationOf(explain, f.few);
  EXPECT_EQ(few.outcome, KeyOutcome::kFewNeighbours);
  EXPECT_EQ(few.neighbours, 2);
  EXPECT_EQ(few.rotations, 0);

  const KeyExplanation& geometry = ExplanationOf(explain, f.geometry);
  EXPECT_EQ(geometry.outcome, KeyOutcome::kGeometry);
  EXPECT_EQ(geometry.neighbours, 4);
  EXPECT_EQ(geometry.rotations, 4);  // one choice of 4 neighbours, 4 rotations
  EXPECT_EQ(geometry.geometry_passed, 0);
  EXPECT_GT(geometry.best_e_mm2, geometry.tolerance_mm2);

  const KeyExplanation& colours = ExplanationOf(explain, f.colours);
  EXPECT_EQ(colours.outcome, KeyOutcome::kColours);
  EXPECT_EQ(colours.geometry_passed, 1);

  const KeyExplanation& winner = ExplanationOf(explain, f.winner);
  EXPECT_EQ(winner.outcome, KeyOutcome::kDetected);
  EXPECT_EQ(detections[static_cast<size_t>(winner.detection)].id, 3);
  const KeyExplanation& lost = ExplanationOf(explain, f.conflict);
  EXPECT_EQ(lost.outcome, KeyOutcome::kConflict);
  EXPECT_EQ(lost.lost_to_key, f.winner);
  EXPECT_EQ(lost.lost_to_pattern, 0);

  EXPECT_EQ(ExplanationOf(explain, f.key_area).outcome, KeyOutcome::kKeyArea);
}

TEST(DetectorExplain, ExplainingChangesNoDetection) {
  const DetectorPattern full = SslWithHalfTheIds();
  Detector detector(MakeConfig({full}));
  const Frame f = MakeFrame(full);
  std::vector<Detection> plain, explained;
  std::vector<KeyExplanation> explain = {KeyExplanation{}};  // cleared by Detect
  DetectStats plain_stats, explained_stats;
  detector.Detect(f.blobs, &plain, &plain_stats);
  detector.Detect(f.blobs, &explained, &explained_stats, nullptr, &explain);
  ASSERT_EQ(plain.size(), explained.size());
  for (size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(plain[i].id, explained[i].id);
    EXPECT_EQ(plain[i].pose.x_mm, explained[i].pose.x_mm);
  }
  EXPECT_EQ(plain_stats.correspondences, explained_stats.correspondences);
  // With every ID in the codebook, robot 3 (ID 12) is a detection too.
  EXPECT_EQ(ExplanationOf(explain, f.colours).outcome, KeyOutcome::kDetected);
  EXPECT_EQ(explain.size(), 7u);
}

}  // namespace
}  // namespace patlab::detect
