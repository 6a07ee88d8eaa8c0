// The detector's fast paths against the plain computations they replace: stage 2's
// bucketed, pre-filtered search against a brute-force scan of every blob; stage 3's placement by
// counting against a sort by atan2; the rotation tables of stage 4 against modular arithmetic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <tuple>
#include <vector>

#include "patlab/detect/detector_internal.h"
#include "patlab/formats/detector_settings.h"
#include "test_util.h"

namespace patlab::detect {
namespace {

using testing::kPalette;
using testing::LoadPattern;
using testing::MakeConfig;
using testing::MakeDetectorPattern;

// Stage 2 by brute force: for a key blob of pattern p, the blobs (not the key) of a neighbour
// colour and area whose squared distance lies within the ring's reach, capped at max_neighbours.
int BruteForceNeighbours(const DetectorConfig& config, int p, const std::vector<Blob>& blobs,
                         int key) {
  const Pattern& pattern = config.patterns[p].pattern;
  const DetectorOptions& o = config.options;
  const Vec2 key_model = pattern.patches[pattern.key_index].position_mm;
  double ring_min = 1e300, ring_max = 0.0, area_min = 1e300, area_max = 0.0;
  std::vector<std::string> colours = config.patterns[p].codebook.colours;
  for (int i = 0; i < pattern.size(); ++i) {
    if (i == pattern.key_index) continue;
    const Patch& patch = pattern.patches[i];
    const double r = (patch.position_mm - key_model).norm();
    ring_min = std::min(ring_min, r);
    ring_max = std::max(ring_max, r);
    area_min = std::min(area_min, o.area_ratio_min * patch.Area());
    area_max = std::max(area_max, o.area_ratio_max * patch.Area());
    if (patch.role == PatchRole::kFixed) colours.push_back(patch.colour);
  }
  const double inner = std::max(0.0, ring_min - o.reach_margin_mm);
  const double outer = ring_max + o.reach_margin_mm;
  int count = 0;
  for (int j = 0; j < static_cast<int>(blobs.size()); ++j) {
    const Blob& b = blobs[j];
    if (j == key || b.colour < 0 || b.colour >= static_cast<int>(kPalette.size())) continue;
    if (std::find(colours.begin(), colours.end(), kPalette[b.colour]) == colours.end()) continue;
    if (b.area_mm2 < area_min || b.area_mm2 > area_max) continue;
    const double d2 = (b.position_mm - blobs[key].position_mm).squaredNorm();
    if (d2 >= inner * inner && d2 <= outer * outer) ++count;
  }
  return std::min(count, o.max_neighbours);
}

// Random scenes: clusters of blobs of every colour around random centres (so that keys have
// many neighbours, within and beyond reach), spread over a field of the given width, with every
// blob's x optionally equal (one bucket).
std::vector<Blob> RandomScene(RandomStream* rng, double width_mm, bool same_x) {
  std::vector<Blob> blobs;
  const int clusters = 1 + static_cast<int>(rng->Below(12));
  for (int c = 0; c < clusters; ++c) {
    const Vec2 centre(rng->Uniform(-width_mm, width_mm), rng->Uniform(-2000, 2000));
    const int n = 1 + static_cast<int>(rng->Below(50));
    for (int i = 0; i < n; ++i) {
      const double r = rng->Uniform(10.0, 30.0);
      Vec2 at = centre + Vec2(rng->Uniform(-120, 120), rng->Uniform(-120, 120));
      if (same_x) at.x() = 17.0;
      blobs.push_back(
          {at, static_cast<int>(rng->Below(kPalette.size())), std::numbers::pi * r * r});
    }
  }
  return blobs;
}

TEST(DetectorFastPath, NeighbourSearchEqualsBruteForceOnRandomScenes) {
  // Two patterns with different neighbour colours (two search lists) and one sharing the first
  // one's filters (a shared list).
  DetectorPattern ssl = MakeDetectorPattern(LoadPattern("ssl-standard"), {"pink", "green"});
  DetectorPattern butterfly = MakeDetectorPattern(LoadPattern("butterfly"), {"cyan", "red"});
  DetectorPattern ssl_again = ssl;
  ssl_again.key_colours = {"orange"};
  DetectorOptions options;
  options.max_neighbours = 6;
  const DetectorConfig config = MakeConfig({ssl, butterfly, ssl_again}, options);
  Detector detector(config);
  std::vector<Detection> detections;
  std::vector<KeyExplanation> explain;
  long keys = 0, with_neighbours = 0, capped = 0;
  for (int f = 0; f < 600; ++f) {
    RandomStream rng(12, 4, f);
    const double width = f % 3 == 0 ? 200.0 : (f % 3 == 1 ? 3000.0 : 1e6);
    const std::vector<Blob> blobs = RandomScene(&rng, width, f % 10 == 0);
    detector.Detect(blobs, &detections, nullptr, nullptr, &explain);
    for (const KeyExplanation& e : explain) {
      if (e.outcome == KeyOutcome::kKeyArea) continue;
      ++keys;
      const int expected = BruteForceNeighbours(config, e.pattern, blobs, e.key_blob);
      ASSERT_EQ(e.neighbours, expected)
          << "frame " << f << " pattern " << e.pattern << " key " << e.key_blob;
      with_neighbours += expected > 0;
      capped += expected == options.max_neighbours;
    }
  }
  // The scenes exercise the search: many keys, most with neighbours, some over the cap.
  EXPECT_GT(keys, 3000);
  EXPECT_GT(with_neighbours, keys / 2);
  EXPECT_GT(capped, 100);
  std::printf("%ld keys, %ld with neighbours, %ld at the cap\n", keys, with_neighbours, capped);
}

// Stage 3's order, by definition: atan2 of the offset, ties by blob index.
std::vector<int> SortedByAtan2(const Vec2& key, const std::vector<Vec2>& at,
                               const std::vector<int>& blob) {
  std::vector<int> order(at.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double ta = std::atan2(at[a].y() - key.y(), at[a].x() - key.x());
    const double tb = std::atan2(at[b].y() - key.y(), at[b].x() - key.x());
    return std::tie(ta, blob[a]) < std::tie(tb, blob[b]);
  });
  std::vector<int> blobs;
  for (int i : order) blobs.push_back(blob[i]);
  return blobs;
}

TEST(DetectorFastPath, RadialSortIsAtan2OrderWithTiesByBlobIndex) {
  // Offsets on the axes (both signs of zero), the quadrant diagonals, the cut at -pi / pi, exact
  // repeats of one direction at other distances (atan2 ties), and random directions.
  const Vec2 key(100.0, -50.0);
  const std::vector<Vec2> special = {
      {1, 0},  {-1, 0.0}, {-1, -0.0}, {0.0, 1}, {-0.0, 1}, {0.0, -1},  {-0.0, -1}, {1, 1},
      {-1, 1}, {-1, -1},  {1, -1},    {2, 2},   {-3, 0.0}, {-2, -0.0}, {5, 1e-12}, {-5, -1e-12}};
  RandomStream rng(12, 5, 0);
  int trials = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const int n = 1 + static_cast<int>(rng.Below(internal::kMaxNeighbours));
    std::vector<Vec2> at;
    std::vector<int> blob;
    for (int i = 0; i < n; ++i) {
      Vec2 d;
      const int kind = static_cast<int>(rng.Below(3));
      if (kind == 0) {
        d = special[rng.Below(special.size())] * (1.0 + static_cast<double>(rng.Below(3)));
      } else if (kind == 1 && i > 0) {
        d = (at[rng.Below(i)] - key) * 2.0;  // the same direction as an earlier one, farther
      } else {
        const double a = rng.Uniform(-std::numbers::pi, std::numbers::pi);
        d = Vec2(std::cos(a), std::sin(a)) * rng.Uniform(40.0, 90.0);
      }
      at.push_back(key + d);
      blob.push_back(static_cast<int>(rng.Below(1000)) * 16 + i);  // distinct, in random order
    }
    internal::Neighbours nb;
    nb.n = n;
    for (int i = 0; i < n; ++i) {
      nb.blob[i] = blob[i];
      nb.position_mm[i] = at[i];
      nb.label[i] = blob[i] % 7;
    }
    internal::RadialSort(key, &nb);
    const std::vector<int> expected = SortedByAtan2(key, at, blob);
    for (int i = 0; i < n; ++i) {
      ASSERT_EQ(nb.blob[i], expected[i]) << "trial " << trial << " position " << i;
      const int original =
          static_cast<int>(std::find(blob.begin(), blob.end(), nb.blob[i]) - blob.begin());
      ASSERT_EQ(nb.position_mm[i], at[original]);  // positions and colours travel with blobs
      ASSERT_EQ(nb.label[i], blob[original] % 7);
    }
    ++trials;
  }
  EXPECT_EQ(trials, 20000);
}

TEST(DetectorFastPath, RotationTablesAreTheModularCircularPositions) {
  std::vector<internal::PatternRuntime> runtimes;
  for (const char* name : {"ssl-standard", "butterfly", "triangle", "simple"}) {
    const Pattern pattern = LoadPattern(name);
    internal::PatternRuntime rt;
    rt.m = pattern.size();
    rt.mk = rt.m - 1;
    rt.key_index = pattern.key_index;
    const Symmetry symmetry = FindSymmetry(pattern, 10.0);
    for (int j = 0; j < rt.mk; ++j) rt.circ_patch[j] = symmetry.circular_order[j];
    internal::BuildCentredModels(pattern, &rt);
    runtimes.push_back(rt);
  }
  for (const internal::PatternRuntime& rt : runtimes) {
    for (int variant = 0; variant <= rt.mk; ++variant) {
      const int skip = variant - 1;
      const int r = skip < 0 ? rt.mk : rt.mk - 1;
      for (int shift = 0; shift < r; ++shift) {
        for (int i = 0; i < r; ++i) {
          // The matching of chosen neighbour i under rotation `shift` (detector.h, stage 4).
          const int expected =
              skip < 0 ? (i + shift) % rt.mk : (skip + 1 + (i + shift) % r) % rt.mk;
          ASSERT_EQ(rt.ring[variant][i + shift], expected) << variant << " " << shift << " " << i;
          ASSERT_EQ(rt.ring_centred[variant][i + shift], rt.circ_centred[variant][expected]);
        }
      }
    }
  }
}

}  // namespace
}  // namespace patlab::detect
