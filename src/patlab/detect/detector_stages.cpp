// Stages 2-6 of the detector (detector.h) around one key candidate: neighbours, radial sort, fit
// rotations, identify, and the missing-patch refit. This is the hot path: everything here works
// on fixed-size arrays on the stack and allocates nothing.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>

#include "patlab/detect/detector_internal.h"

namespace patlab::detect {

using internal::Candidate;
using internal::kFixedAny;
using internal::kMaxGathered;
using internal::kMaxLabels;
using internal::kMaxNeighbours;
using internal::Neighbours;
using internal::PatternRuntime;
using internal::ScopedTime;
using internal::StageClock;

namespace {

// One choice of r neighbours (indices into Neighbours, in angular order) with the key, centred on
// their centroid.
struct Choice {
  int r = 0;
  std::array<int, kMaxNeighbours> pick;
  std::array<Vec2, kMaxNeighbours> w;  // centred neighbour positions
  Vec2 wk;                             // centred key position
  double sw = 0.0;                     // sum of squared centred norms
};

// What stage 5 made of one rotation's colours.
struct RotationColours {
  bool fixed_ok = true;  // fixed patches have their colour
  bool has_id = false;   // the ID slots' colours are a codebook ID (id may still be -1: see below)
  int id = -1;
};

// The result of every rotation of one choice of neighbours.
struct SubsetVerdict {
  double min_e = 1e300;  // smallest E of every rotation tried (for KeyExplanation)
  int ok = 0;            // rotations passing geometry and fixed colours
  int valid = 0;         // ... whose colours are an ID
  double best_ok_e = 1e300;
  int best_ok_shift = 0, best_ok_skip = -1;
  double valid_e = 1e300;
  int valid_shift = 0, valid_skip = -1, valid_id = -1;
};

// Minimum sum-squared error of the rigid fit of model points q (centred) to observed points w
// (centred): E = sum|q|^2 + sum|w|^2 - 2 sqrt(A^2 + B^2), A = sum q.w, B = sum q x w
// (2-D Procrustes, Umeyama 1991); no trigonometry.
inline double FitError(double sq, double sw, double a, double b) {
  return std::max(0.0, sq + sw - 2.0 * std::sqrt(a * a + b * b));
}

// The next choice of r out of n in lexicographic order; false after the last.
inline bool NextCombination(int r, int n, std::array<int, kMaxNeighbours>* pick) {
  int i = r - 1;
  while (i >= 0 && (*pick)[i] == n - r + i) --i;
  if (i < 0) return false;
  ++(*pick)[i];
  for (int j = i + 1; j < r; ++j) (*pick)[j] = (*pick)[j - 1] + 1;
  return true;
}

// Observed centroid and centred points of the choice in `pick`.
inline void CentreChoice(const Vec2& key_mm, const Neighbours& nb, Choice* ch) {
  Vec2 centroid = key_mm;
  for (int i = 0; i < ch->r; ++i) centroid += nb.position_mm[ch->pick[i]];
  centroid /= (ch->r + 1);
  ch->wk = key_mm - centroid;
  ch->sw = ch->wk.squaredNorm();
  for (int i = 0; i < ch->r; ++i) {
    ch->w[i] = nb.position_mm[ch->pick[i]] - centroid;
    ch->sw += ch->w[i].squaredNorm();
  }
}

// Stage 4: E of the rigid fit of the choice to model variant vi under rotation `shift`; a0 and
// b0 are the key's terms of A and B, the same for every rotation (FitRotations).
inline double RotationError(const PatternRuntime& rt, const Choice& ch, int vi, int shift,
                            double a0, double b0) {
  const Vec2* q = &rt.ring_centred[vi][shift];
  double a = a0, b = b0;
  for (int i = 0; i < ch.r; ++i) {
    a += q[i].dot(ch.w[i]);
    b += q[i].x() * ch.w[i].y() - q[i].y() * ch.w[i].x();
  }
  return FitError(rt.sq[vi], ch.sw, a, b);
}

// Stage 5 with the ID slot at circular position `skip` missing: its colour is unknown, so the ID
// is known only if exactly one completion of `code` is in the codebook.
inline RotationColours CompleteMissingSlot(const PatternRuntime& rt, int code, int skip) {
  RotationColours out;
  int found = 0;
  for (int c = 0; c < rt.num_codebook_colours; ++c) {
    const int cid = rt.code_to_id[code + c * rt.slot_weight[skip]];
    if (cid >= 0) {
      out.id = cid;
      ++found;
    }
  }
  out.has_id = found > 0;
  if (found > 1) out.id = -1;
  return out;
}

// Stage 5 for one rotation that passed geometry: fixed patches must match; ID slots form the
// code, looked up in the codebook.
inline RotationColours IdentifyRotation(const PatternRuntime& rt, const Choice& ch,
                                        const Neighbours& nb, int skip, int shift) {
  int code = 0;
  bool code_ok = true;
  const int* ring = &rt.ring[skip + 1][shift];
  for (int i = 0; i < ch.r; ++i) {
    const int c = ring[i];
    const int label = nb.label[ch.pick[i]];
    if (rt.fixed_label[c] != kFixedAny) {
      if (label != rt.fixed_label[c]) return {.fixed_ok = false};
    } else {
      const int cb = rt.codebook_colour[label];
      if (cb < 0) {
        code_ok = false;
      } else {
        code += cb * rt.slot_weight[c];
      }
    }
  }
  if (!code_ok) return {};
  if (skip >= 0 && rt.fixed_label[skip] == kFixedAny) return CompleteMissingSlot(rt, code, skip);
  const int id = rt.code_to_id[code];
  return {.has_id = id >= 0, .id = id};
}

inline void Record(double e, int shift, int skip, const RotationColours& colours,
                   SubsetVerdict* v) {
  ++v->ok;
  if (e < v->best_ok_e) {
    v->best_ok_e = e;
    v->best_ok_shift = shift;
    v->best_ok_skip = skip;
  }
  if (colours.has_id) {
    ++v->valid;
    if (e < v->valid_e) {
      v->valid_e = e;
      v->valid_shift = shift;
      v->valid_skip = skip;
      v->valid_id = colours.id;
    }
  }
}

// Stages 4 and 5 for every rotation of one choice (and, for a missing-patch fit, every circular
// position left out); stage 5 runs only on rotations passing geometry and is timed apart.
template <bool kTiming>
inline SubsetVerdict FitRotations(const PatternRuntime& rt, const Choice& ch, const Neighbours& nb,
                                  bool missing, double e_max, long* identify_ns,
                                  DetectStats* stats) {
  SubsetVerdict v;
  const int variants = missing ? rt.mk : 1;
  long passed = 0;
  for (int variant = 0; variant < variants; ++variant) {
    const int skip = missing ? variant : -1;
    const Vec2& qk = rt.key_centred[skip + 1];
    const double a0 = qk.dot(ch.wk), b0 = qk.x() * ch.wk.y() - qk.y() * ch.wk.x();
    // Every rotation's E first, then stage 5 on those passing in shift order: the branch is on
    // whether any passed, not on which.
    std::array<double, kMaxPatches> e;
    uint32_t pass = 0;
    for (int shift = 0; shift < ch.r; ++shift) {
      e[shift] = RotationError(rt, ch, skip + 1, shift, a0, b0);
      v.min_e = std::min(v.min_e, e[shift]);
      pass |= static_cast<uint32_t>(!(e[shift] > e_max)) << shift;
    }
    for (; pass != 0; pass &= pass - 1) {
      const int shift = std::countr_zero(pass);
      ++passed;
      ScopedTime<kTiming> identify_time(identify_ns);
      const RotationColours colours = IdentifyRotation(rt, ch, nb, skip, shift);
      if (colours.fixed_ok) Record(e[shift], shift, skip, colours, &v);
    }
  }
  stats->correspondences += static_cast<long>(variants) * ch.r;
  stats->geometry_passed += passed;
  return v;
}

// Stage 5 verdict on one choice whose rotations passed geometry and fixed colours (v.ok > 0):
// exactly one rotation with an ID -> a candidate; otherwise two or more rotations -> an
// ambiguous candidate; a single rotation whose colours are no ID -> none.
inline bool JudgeChoice(const PatternRuntime& rt, int p, int key, const Neighbours& nb,
                        const Choice& ch, const SubsetVerdict& v, bool missing, double e_max,
                        DetectStats* stats, Candidate* c) {
  const bool single = v.valid == 1;
  const bool amb = !single && v.ok >= 2;
  if (v.ok == 1 && v.valid == 0) ++stats->colour_rejected;
  if (!single && !amb) return false;
  c->pattern = p;
  c->key_blob = key;
  c->e = single ? v.valid_e : v.best_ok_e;
  c->score = c->e / e_max;
  c->id = single ? v.valid_id : -1;
  const int shift = single ? v.valid_shift : v.best_ok_shift;
  const int skip = single ? v.valid_skip : v.best_ok_skip;
  c->status = amb ? DetectionStatus::kAmbiguous
                  : (missing ? DetectionStatus::kMissingPatch : DetectionStatus::kOk);
  c->missing_patch = skip >= 0 ? rt.circ_patch[skip] : -1;
  c->blob.fill(-1);
  c->blob[rt.key_index] = key;
  c->num_blobs = ch.r + 1;
  const int* ring = &rt.ring[skip + 1][shift];
  for (int i = 0; i < ch.r; ++i) c->blob[rt.circ_patch[ring[i]]] = nb.blob[ch.pick[i]];
  return true;
}

// Whether neighbour a comes before b: by atan2 of its offset from the key, ties by blob index.
// Pseudo-angles further apart than kPseudoAngleSlack order the angles as atan2 does (the slack
// is orders of magnitude above the rounding of either), so atan2 itself, whose order defines
// the result, is only evaluated for the rare near-ties.
struct RadialOrder {
  static constexpr double kPseudoAngleSlack = 1e-9;
  const std::array<double, kMaxNeighbours>& pseudo;
  const std::array<Vec2, kMaxNeighbours>& offset;
  bool operator()(int a, int b, int blob_a, int blob_b) const {
    const double pa = pseudo[a], pb = pseudo[b];
    if (std::fabs(pa - pb) > kPseudoAngleSlack) return pa < pb;  // false for NaN
    const double ta = std::atan2(offset[a].y(), offset[a].x());
    const double tb = std::atan2(offset[b].y(), offset[b].x());
    return ta < tb || (ta == tb && blob_a < blob_b);
  }
};

// Stage 2's cut: keeps the max_nb neighbours closest to the model's ring (distance outside the
// ring, from the squared distances d2 to the key), ties by blob index.
void KeepNearestToRing(const PatternRuntime& rt, int max_nb,
                       const std::array<double, kMaxGathered + 1>& d2, Neighbours* nb) {
  std::array<double, kMaxGathered> ring_dev;
  for (int i = 0; i < nb->n; ++i) {
    const double d = std::sqrt(d2[i]);
    ring_dev[i] = d < rt.ring_min_mm ? rt.ring_min_mm - d : std::max(0.0, d - rt.ring_max_mm);
  }
  std::array<int, kMaxGathered> order;
  for (int i = 0; i < nb->n; ++i) order[i] = i;
  std::partial_sort(
      order.begin(), order.begin() + max_nb, order.begin() + nb->n, [&](int a, int b) {
        return std::tie(ring_dev[a], nb->blob[a]) < std::tie(ring_dev[b], nb->blob[b]);
      });
  const Neighbours all = *nb;
  for (int i = 0; i < max_nb; ++i) {
    nb->blob[i] = all.blob[order[i]];
    nb->position_mm[i] = all.position_mm[order[i]];
    nb->label[i] = all.label[order[i]];
  }
  nb->n = max_nb;
}

}  // namespace

// Stage 3: the neighbours by angle about the key, ties by blob index. Each neighbour's place is
// the number of neighbours before it (n <= 16: at most 120 comparisons, without the mispredicted
// branches of a comparison sort). RadialOrder is a strict total order, so these places are a
// permutation and the result is the sorted order; should they not be (a pseudo-angle ordering a
// pair against atan2), an insertion sort with the same comparisons decides, as it always did.
void internal::RadialSort(const Vec2& key_mm, Neighbours* nb) {
  const int n = nb->n;
  std::array<double, kMaxNeighbours> pseudo;
  std::array<Vec2, kMaxNeighbours> offset;
  std::array<int, kMaxNeighbours> place{};
  for (int i = 0; i < n; ++i) {
    offset[i] = nb->position_mm[i] - key_mm;
    pseudo[i] = internal::PseudoAngle(offset[i]);
  }
  const RadialOrder before{pseudo, offset};
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const bool i_first = before(i, j, nb->blob[i], nb->blob[j]);
      place[j] += static_cast<int>(i_first);
      place[i] += static_cast<int>(!i_first);
    }
  }
  uint32_t seen = 0;
  for (int i = 0; i < n; ++i) seen |= uint32_t{1} << place[i];
  if (seen != (uint32_t{1} << n) - 1) {  // not a permutation: insertion sort
    for (int i = 0; i < n; ++i) place[i] = i;
    for (int i = 1; i < n; ++i) {
      const int s = place[i];
      int j = i - 1;
      for (; j >= 0 && before(s, place[j], nb->blob[s], nb->blob[place[j]]); --j) {
        place[j + 1] = place[j];
      }
      place[j + 1] = s;
    }
    std::array<int, kMaxNeighbours> at;  // place[position] holds the index; invert it
    for (int i = 0; i < n; ++i) at[place[i]] = i;
    place = at;
  }
  // Fixed-size copies (a few vector moves; a copy of n elements became a slow `rep movs`).
  std::array<int, kMaxNeighbours> blob, label;
  std::array<Vec2, kMaxNeighbours> position;
  std::memcpy(blob.data(), nb->blob.data(), sizeof(blob));
  std::memcpy(label.data(), nb->label.data(), sizeof(label));
  std::memcpy(static_cast<void*>(position.data()), nb->position_mm.data(), sizeof(position));
  for (int i = 0; i < n; ++i) {
    nb->blob[place[i]] = blob[i];
    nb->position_mm[place[i]] = position[i];
    nb->label[place[i]] = label[i];
  }
}

// Stage 2's search structure of pattern p in this frame, built on first use: the blobs passing
// p's neighbour colour and area filters, counting-sorted by x bucket (ascending blob index within
// a bucket, the order the search visits them in).
const Detector::Impl::NeighbourList& Detector::Impl::NeighbourListOf(int p,
                                                                     std::span<const Blob> blobs) {
  NeighbourList& list = neighbour_lists[neighbour_list_of[p]];
  if (list.frame == frame_number) return list;
  list.frame = frame_number;
  const PatternRuntime& rt = runtimes[p];
  const int n = static_cast<int>(blobs.size());
  // A counting sort of every blob by group: group 0 holds the blobs left out (filters failed, or
  // not Usable), group 1 + b bucket b. Every blob is written somewhere, so neither loop branches
  // on the blob.
  list.start.assign(num_buckets + 2, 0);
  list.position_mm.resize(blobs.size());
  list.blob.resize(blobs.size());
  list.label.resize(blobs.size());
  list_bucket.resize(blobs.size());
  for (int i = 0; i < n; ++i) {
    const Blob& blob = blobs[i];
    const bool colour_ok = (static_cast<unsigned>(blob.colour) < unsigned{kMaxLabels}) &
                           (((rt.neighbour_mask >> (blob.colour & (kMaxLabels - 1))) & 1) != 0);
    const bool area_ok = (blob.area_mm2 >= rt.nb_area_min) & (blob.area_mm2 <= rt.nb_area_max);
    const int group = (colour_ok & area_ok) ? blob_bucket[i] + 1 : 0;  // 0 too when not Usable
    list_bucket[i] = group;
    ++list.start[group + 1];
  }
  for (int g = 0; g <= num_buckets; ++g) list.start[g + 1] += list.start[g];
  bucket_fill.assign(list.start.begin(), list.start.end() - 1);
  for (int i = 0; i < n; ++i) {
    const int slot = bucket_fill[list_bucket[i]]++;
    list.position_mm[slot] = blobs[i].position_mm;
    list.blob[slot] = i;
    list.label[slot] = blobs[i].colour;
  }
  return list;
}

// Stage 2: neighbours in the ring around the key (x-bucketed search over the blobs passing the
// pattern's colour and area filters).
void Detector::Impl::FindNeighbours(int p, int key, std::span<const Blob> blobs, Neighbours* nb) {
  const PatternRuntime& rt = runtimes[p];
  const NeighbourList& list = NeighbourListOf(p, blobs);
  const Vec2 k = blobs[key].position_mm;
  std::array<double, kMaxGathered + 1> d2s;
  auto bucket_of = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x - bucket_min_x) / bucket_width_mm)), 0,
                      num_buckets - 1);
  };
  const int first = bucket_of(k.x() - rt.reach_max_mm), last = bucket_of(k.x() + rt.reach_max_mm);
  // Branch-free: every blob scanned is written at nb->n, which advances when it is within reach
  // and room is left (the arrays have one spare slot).
  const int end = list.start[last + 2];
  int count = 0;
  long cut = 0;
  for (int t = list.start[first + 1]; t < end; ++t) {
    const double d2 = (list.position_mm[t] - k).squaredNorm();
    const int j = list.blob[t];
    const bool within = (d2 >= rt.reach_min2) & (d2 <= rt.reach_max2) & (j != key);
    d2s[count] = d2;
    nb->position_mm[count] = list.position_mm[t];
    nb->label[count] = list.label[t];
    nb->blob[count] = j;
    const bool room = count < kMaxGathered;
    cut += static_cast<long>(within & !room);
    count += static_cast<int>(within & room);
  }
  nb->n = count;
  stats.neighbours_cut += cut;
  stats.neighbours += nb->n;
  const int max_nb = config.options.max_neighbours;
  if (nb->n > max_nb) {
    stats.neighbours_cut += nb->n - max_nb;
    KeepNearestToRing(rt, max_nb, d2s, nb);
  }
}

// Stages 4 and 5 (or, with `missing`, stage 6) over every choice of r neighbours (in angular
// order, so the circular order is kept): the best candidate with an ID, else the best ambiguous
// one. False when there is neither.
template <bool kTiming>
bool Detector::Impl::FitAndIdentify(int p, int key, const Vec2& key_mm, const Neighbours& nb,
                                    bool missing, long* identify_ns, Candidate* best) {
  const PatternRuntime& rt = runtimes[p];
  Choice ch;
  ch.r = missing ? rt.mk - 1 : rt.mk;
  if (nb.n < ch.r) return false;
  const double e_max = missing ? rt.e_max_missing : rt.e_max_full;
  for (int i = 0; i < ch.r; ++i) ch.pick[i] = i;
  bool found_valid = false, have_ambiguous = false;
  Candidate ambiguous;
  do {
    CentreChoice(key_mm, nb, &ch);
    const SubsetVerdict v = FitRotations<kTiming>(rt, ch, nb, missing, e_max, identify_ns, &stats);
    if (!missing && v.min_e < key_best_e) {
      key_best_e = v.min_e;
      if (explain != nullptr) {
        key_best_pick = ch.pick;
        key_best_r = ch.r;
      }
    }
    if (v.ok == 0) continue;  // nothing passed geometry and fixed colours: nothing to decide
    ScopedTime<kTiming> identify_time(identify_ns);
    Candidate c;
    if (!JudgeChoice(rt, p, key, nb, ch, v, missing, e_max, &stats, &c)) continue;
    if (c.status != DetectionStatus::kAmbiguous) {
      if (!found_valid || c.e < best->e) *best = c;
      found_valid = true;
    } else if (!have_ambiguous || c.e < ambiguous.e) {
      ambiguous = c;
      have_ambiguous = true;
    }
  } while (NextCombination(ch.r, nb.n, &ch.pick));
  if (found_valid) return true;
  if (have_ambiguous) *best = ambiguous;
  return have_ambiguous;
}

template <bool kTiming>
void Detector::Impl::EvaluateKey(int p, int key, std::span<const Blob> blobs) {
  StageClock<kTiming> clock;
  const PatternRuntime& rt = runtimes[p];
  DetectStats before;
  if (explain != nullptr) before = stats;
  key_best_e = std::numeric_limits<double>::infinity();
  key_best_r = 0;
  Neighbours nb;
  FindNeighbours(p, key, blobs, &nb);
  stage_ns[internal::kNeighbours] += clock.Lap();
  const bool try_missing = rt.can_fit_missing && nb.n >= rt.mk - 1;
  if (nb.n < rt.mk && !try_missing) {
    if (explain != nullptr) ExplainKey(p, key, blobs[key].position_mm, nb, before, false);
    return;
  }

  const Vec2 key_mm = blobs[key].position_mm;
  internal::RadialSort(key_mm, &nb);
  stage_ns[internal::kRadialSort] += clock.Lap();

  Candidate best;
  bool found = FitAndIdentify<kTiming>(p, key, key_mm, nb, /*missing=*/false,
                                       &stage_ns[internal::kIdentify], &best);
  stage_ns[internal::kFitRotations] += clock.Lap();
  if (!found && try_missing) {
    long identify_in_missing_ns = 0;  // charged to stage 6 as a whole
    found = FitAndIdentify<kTiming>(p, key, key_mm, nb, /*missing=*/true, &identify_in_missing_ns,
                                    &best);
    stage_ns[internal::kMissingPatch] += clock.Lap();
  }
  if (found) candidates.push_back(best);
  if (explain != nullptr) ExplainKey(p, key, key_mm, nb, before, found);
}

template void Detector::Impl::EvaluateKey<false>(int, int, std::span<const Blob>);
template void Detector::Impl::EvaluateKey<true>(int, int, std::span<const Blob>);

}  // namespace patlab::detect
