// Internals of detect::Detector shared by its source files: detector_build.cpp (the models,
// precomputed once), detector_stages.cpp (stages 2-6 around one key candidate), detector.cpp
// (the frame: stages 1, 7 and 8) and detector_explain.cpp (Detect's explain records). Not part
// of the public API: include detector.h instead.
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "patlab/detect/detector.h"

namespace patlab::detect::internal {

constexpr int kMaxLabels = 64;
constexpr int kMaxGathered = 64;    // neighbours collected before the max_neighbours cut
constexpr int kMaxNeighbours = 16;  // DetectorOptions::max_neighbours at most
constexpr int kFixedAny = -2;       // circular position holds an ID slot, not a fixed colour

// A pseudo-angle of d in [-2, 2], strictly increasing with atan2(d.y, d.x) over (-pi, pi] and
// with the same cut (y = -0 with x < 0 is -pi, -2 here): y / (|x| + |y|) on the right half, 2 or
// -2 minus it on the left. Stage 3 sorts by it with a division instead of atan2 (~20% of a
// frame's detection time before), and falls back to atan2 for near-ties. NaN for d = 0. Both
// halves are computed and one selected: a branch on the side of x is mispredicted half the time.
inline double PseudoAngle(const Vec2& d) {
  const double x = d.x(), y = d.y();
  const double r = y / (std::fabs(x) + std::fabs(y));
  const double left = std::copysign(2.0, y) - r;  // -2 - r when y is negative (-0 too)
  return x >= 0.0 ? r : left;
}

// Indices of kDetectStageNames.
enum Stage {
  kCandidates,
  kNeighbours,
  kRadialSort,
  kFitRotations,
  kIdentify,
  kMissingPatch,
  kConflicts,
  kPose,
  kNumStages
};

// One pattern as the hot path needs it, precomputed by Detector::Impl::Build.
struct PatternRuntime {
  int m = 0;   // patches
  int mk = 0;  // non-key patches, in circular order
  int key_index = 0;
  std::array<int, kMaxPatches> circ_patch{};  // patch index at circular position j
  // Model positions centred on the centroid of the patches fitted. Index [0] of the arrays is
  // the full fit; [1 + k] the fit without circular position k.
  std::array<Vec2, kMaxPatches + 1> key_centred{};
  std::array<std::array<Vec2, kMaxPatches>, kMaxPatches + 1> circ_centred{};
  std::array<double, kMaxPatches + 1> sq{};
  // Per variant v of the arrays above (full fit, r = mk; or without circular position k = v - 1,
  // r = mk - 1): the circular positions in the order the r chosen neighbours meet them, twice
  // over, so that rotation `shift` matches the i-th neighbour (i, shift < r) with circular
  // position ring[v][i + shift] = (i + shift) mod mk, or (k + 1 + (i + shift) mod r) mod mk;
  // and the centred model points in that order (ring_centred[v][i] = circ_centred[v][ring[v][i]]).
  std::array<std::array<int, 2 * kMaxPatches>, kMaxPatches + 1> ring{};
  std::array<std::array<Vec2, 2 * kMaxPatches>, kMaxPatches + 1> ring_centred{};
  double e_max_full = 0.0, e_max_missing = 0.0;
  int dof_full = 0, dof_missing = 0;
  bool can_fit_missing = false;
  std::array<int, kMaxPatches> fixed_label{};  // per circular position; kFixedAny: ID slot
  std::array<int, kMaxPatches> slot_weight{};  // per circular position: code weight of its slot
  std::array<int8_t, kMaxLabels> codebook_colour{};  // palette label -> codebook colour, or -1
  int num_codebook_colours = 0;
  std::vector<int> code_to_id;  // dense: base-n code of the slot colours -> ID or -1
  uint64_t neighbour_mask = 0;
  double key_area_min = 0.0, key_area_max = 0.0;
  double nb_area_min = 0.0, nb_area_max = 0.0;
  double ring_min_mm = 0.0, ring_max_mm = 0.0;  // model distances of non-key patches from key
  double reach_min2 = 0.0, reach_max2 = 0.0, reach_max_mm = 0.0;
  estimate::Model model;
  std::array<estimate::Model, kMaxPatches> missing_model{};  // by missing patch index
};

// A pattern found around one key blob, before stage 7 settles conflicts.
struct Candidate {
  double score = 0.0;  // E / tolerance; lower is better
  double e = 0.0;
  int pattern = 0;
  int key_blob = 0;
  int id = -1;
  DetectionStatus status = DetectionStatus::kOk;
  int missing_patch = -1;
  int num_blobs = 0;  // blobs explained (patches found)
  int explain = -1;   // index of its KeyExplanation when Detect explains
  std::array<int, kMaxPatches> blob{};
};

// Stages 2-3 around one key: the neighbours kept, in angular order once stage 3 ran.
// Stage 2 writes one slot past the last neighbour it keeps.
struct Neighbours {
  int n = 0;
  std::array<int, kMaxGathered + 1> blob;  // blob indices
  std::array<Vec2, kMaxGathered + 1> position_mm;
  std::array<int, kMaxGathered + 1> label;
};

// detector_build.cpp: rt's key_centred, circ_centred, sq, ring and ring_centred, from the
// pattern and rt's key_index, mk and circ_patch.
void BuildCentredModels(const Pattern& pattern, PatternRuntime* rt);

// Stage 3 (detector_stages.cpp): nb's first n neighbours (blob, position, label) reordered by
// the angle of position - key_mm, atan2's order over (-pi, pi], ties by blob index.
void RadialSort(const Vec2& key_mm, Neighbours* nb);

// Stage timing. The code paths are templates on kOn, so an untimed Detect contains no clock read
// and no timing branch in its inner loops.
using Clock = std::chrono::steady_clock;

inline long Nanoseconds(Clock::time_point from, Clock::time_point to) {
  return static_cast<long>(std::chrono::duration_cast<std::chrono::nanoseconds>(to - from).count());
}

// Lap() returns the nanoseconds since construction or the previous Lap; 0 when kOn is false.
template <bool kOn>
class StageClock {
 public:
  long Lap() { return 0; }
};
template <>
class StageClock<true> {
 public:
  long Lap() {
    const Clock::time_point now = Clock::now();
    const long ns = Nanoseconds(last_, now);
    last_ = now;
    return ns;
  }

 private:
  Clock::time_point last_ = Clock::now();
};

// Adds the time from construction to destruction to *total_ns; nothing when kOn is false.
template <bool kOn>
class ScopedTime {
 public:
  explicit ScopedTime(long* /*total_ns*/) {}
};
template <>
class ScopedTime<true> {
 public:
  explicit ScopedTime(long* total_ns) : total_ns_(total_ns), start_(Clock::now()) {}
  ~ScopedTime() { *total_ns_ += Nanoseconds(start_, Clock::now()); }
  ScopedTime(const ScopedTime&) = delete;
  ScopedTime& operator=(const ScopedTime&) = delete;

 private:
  long* total_ns_;
  Clock::time_point start_;
};

}  // namespace patlab::detect::internal

namespace patlab::detect {

struct Detector::Impl {
  using PatternRuntime = internal::PatternRuntime;
  using Candidate = internal::Candidate;
  using Neighbours = internal::Neighbours;

  DetectorConfig config;
  std::vector<PatternRuntime> runtimes;
  std::array<std::vector<int>, internal::kMaxLabels> patterns_by_key_label;
  double max_reach_mm = 0.0;
  uint64_t key_label_mask = 0;  // the labels with a pattern in patterns_by_key_label

  // Patterns whose stage-2 filters (neighbour colours, neighbour area range) are those of an
  // earlier pattern share that pattern's NeighbourList: neighbour_list_of[p] indexes
  // neighbour_lists.
  std::vector<int> neighbour_list_of;

  // Per-frame buffers, reused.
  std::vector<int> blob_bucket;  // per blob: its x bucket (buckets one reach wide), -1: not Usable
  std::vector<int> list_bucket, bucket_fill;  // NeighbourListOf's counting sort
  std::vector<int> key_blobs;  // [0, num_key_blobs): Usable blobs of a key colour, index order
  int num_key_blobs = 0;
  std::vector<int> detection_order;  // SortDetections
  std::vector<Detection> unsorted_detections;
  int num_buckets = 1;
  double bucket_min_x = 0.0, bucket_width_mm = 1.0;
  // Stage 2's search structure for one set of patterns (neighbour_list_of): the blobs passing
  // their colour and area filters, counting-sorted by x bucket (ascending blob index within a
  // bucket), with their positions side by side. Built on
  // the first key candidate of such a pattern in a frame (frame == frame_number), so a frame pays
  // nothing for patterns without keys.
  struct NeighbourList {
    long frame = -1;
    std::vector<int> start;  // bucket b holds [start[b + 1], start[b + 2]); see NeighbourListOf
    std::vector<Vec2> position_mm;
    std::vector<int> blob;
    std::vector<int> label;
  };
  std::vector<NeighbourList> neighbour_lists;
  long frame_number = 0;
  std::vector<Candidate> candidates;
  std::vector<int> candidate_order;
  std::vector<int> used;  // per blob: 1 + the candidate that took it, or 0
  DetectStats stats;
  // Detect's explain output, or nullptr; the smallest full-fit E of the key being evaluated.
  std::vector<KeyExplanation>* explain = nullptr;
  double key_best_e = 0.0;
  // Explain only: the choice of neighbours (indices into the key's Neighbours) with that E.
  std::array<int, internal::kMaxNeighbours> key_best_pick{};
  int key_best_r = 0;
  // Timed Detect only: nanoseconds per stage of this frame. Stages 2-6 are summed over the key
  // candidates; kFitRotations holds stages 4 and 5 of the full fits until Detect takes stage 5
  // (timed inside it) out.
  std::array<long, internal::kNumStages> stage_ns{};

  // detector_build.cpp: checks the configuration and precomputes the runtimes.
  void Build();
  void CheckPalette() const;
  int LabelOf(const std::string& name) const;
  PatternRuntime BuildRuntime(int p);
  void BuildCodebook(const DetectorPattern& dp, const std::string& where, PatternRuntime* rt) const;
  void BuildCircularColours(const Pattern& pattern, const std::string& where,
                            PatternRuntime* rt) const;
  void BuildTolerancesAndReach(const Pattern& pattern, PatternRuntime* rt);

  // detector.cpp: the frame.
  template <bool kTiming>
  void DetectFrame(std::span<const Blob> blobs, std::vector<Detection>* detections);
  void BucketBlobs(std::span<const Blob> blobs);  // stage 1
  template <bool kTiming>
  void FindKeyCandidates(std::span<const Blob> blobs);  // stage 1, calling EvaluateKey
  template <bool kTiming>
  void ResolveConflicts(std::span<const Blob> blobs,
                        std::vector<Detection>* detections);  // stage 7
  void EstimatePose(const Candidate& c, std::span<const Blob> blobs,
                    Detection* d) const;                            // stage 8
  void SortDetections(std::vector<Detection>* detections);          // stage 8's output order
  void LinkExplanations(const std::vector<Detection>& detections);  // explain: detection index
  // explain: the record of key `key` of pattern p after stages 2-6.
  void ExplainKey(int p, int key, const Vec2& key_mm, const Neighbours& nb,
                  const DetectStats& before, bool found);
  // explain: the nearest rotation (the full fit of key_best_pick with the smallest E) into e.
  void ExplainNearestRotation(int p, const Vec2& key_mm, const Neighbours& nb,
                              KeyExplanation* e) const;

  // detector_stages.cpp: stages 2-6 for the key blob `key` of pattern p.
  template <bool kTiming>
  void EvaluateKey(int p, int key, std::span<const Blob> blobs);
  const NeighbourList& NeighbourListOf(int p, std::span<const Blob> blobs);  // stage 2
  void FindNeighbours(int p, int key, std::span<const Blob> blobs,
                      Neighbours* nb);  // stage 2
  template <bool kTiming>
  bool FitAndIdentify(int p, int key, const Vec2& key_mm, const Neighbours& nb, bool missing,
                      long* identify_ns, Candidate* best);  // stages 4 and 5 (6: missing)
};

}  // namespace patlab::detect
