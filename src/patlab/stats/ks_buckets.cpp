// The KS walk by buckets (EcdfExtremesByBuckets): the values counted into equal-width buckets,
// the buckets that can hold an extreme of F1 - F2 found from the counts alone, and only those
// walked, a window of them at a time.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/stats/ks.h"
#include "patlab/stats/ks_internal.h"
#include "patlab/stats/summary.h"

namespace patlab::stats {
namespace detail {

using internal::Buffers;
using internal::CountsAtBucketEnds;
using internal::EqualWidthBuckets;
using internal::ExtremesOfSameSamples;
using internal::kWindowValues;
using internal::SameSamples;
using internal::SortSmall;
using internal::ThreadBuffers;
using internal::WalkSorted;

namespace {

// At most this many buckets (about 1 MB of per-bucket arrays a thread): reached at about 250,000
// values a sample, so that they stop growing with the trials well below the statistics block
// (scripts/bytes_per_trial.sh: 28 B a trial and estimator from 500,000 to 10^6 trials with 2^17,
// as the arrays grew; 24.6 B with 2^15); larger samples put more values in a bucket.
constexpr std::size_t kMaxBuckets = std::size_t{1} << 15;

// The smallest and the largest value (finite), in a loop the compiler vectorises.
std::pair<double, double> MinMax(std::span<const double> x) {
  double lo = x[0], hi = x[0];
  for (const double v : x) {
    lo = v < lo ? v : lo;
    hi = v > hi ? v : hi;
  }
  return {lo, hi};
}

// A run of consecutive buckets to walk: its values start at a0 (b0) in the buffers, and at i0
// (j0) in the merged order of the whole samples.
struct Run {
  uint32_t a0, b0, na, nb, i0, j0;
};

// Extract first computes the buckets of a chunk of values in a loop the compiler vectorises, then
// uses them one at a time in a second loop.
constexpr std::size_t kChunk = 256;

// Which buckets the walk must visit: a byte a bucket, 1 for those, into s->walk. Every bucket end
// is a group end of the walk, so the largest (smallest) of the bucket-end values D_k, computed as
// the walk computes them, is a lower (upper) bound on the walk's extreme. Inside bucket k the
// walk's values lie between L_k = I_{k-1} / n1 - J_k / n2 and U_k = I_k / n1 - J_{k-1} / n2,
// computed the same way (each rounding is monotone, so the bound holds for the computed values
// exactly). A bucket with U_k < max D and L_k > min D holds no group end that reaches either
// extreme, and the walk keeps the first group end that does, so skipping such buckets leaves the
// result unchanged (and walking more buckets than needed changes nothing either: their group ends
// are the walk's own values, none beyond the extremes, none equal to one before its first
// occurrence).
void MarkBucketsByRatios(std::size_t buckets, double dn1, double dn2, Buffers* s) {
  // f1[k] = I_k / n1 and f2[k] = J_k / n2, each division done once (a loop that vectorises);
  // every bound below is a difference of two of them, the walk's own arithmetic.
  s->f1.resize(buckets);
  s->f2.resize(buckets);
  double* __restrict f1 = s->f1.data();
  double* __restrict f2 = s->f2.data();
  const uint32_t* __restrict e1 = s->end1.data();
  const uint32_t* __restrict e2 = s->end2.data();
  for (std::size_t k = 0; k < buckets; ++k) f1[k] = static_cast<double>(e1[k]) / dn1;
  for (std::size_t k = 0; k < buckets; ++k) f2[k] = static_cast<double>(e2[k]) / dn2;
  // The largest and smallest D_k, in kLanes independent lanes (a loop that vectorises; D is never
  // NaN or -0.0, so the lanes' order does not matter).
  constexpr std::size_t kLanes = 8;
  double max_lane[kLanes], min_lane[kLanes];
  std::fill_n(max_lane, kLanes, -1.0);
  std::fill_n(min_lane, kLanes, 1.0);
  std::size_t k = 0;
  for (; k + kLanes <= buckets; k += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) {
      const double d = f1[k + l] - f2[k + l];
      max_lane[l] = d > max_lane[l] ? d : max_lane[l];
      min_lane[l] = d < min_lane[l] ? d : min_lane[l];
    }
  }
  for (; k < buckets; ++k) {
    const double d = f1[k] - f2[k];
    max_lane[0] = d > max_lane[0] ? d : max_lane[0];
    min_lane[0] = d < min_lane[0] ? d : min_lane[0];
  }
  const double max_end = *std::max_element(max_lane, max_lane + kLanes);
  const double min_end = *std::min_element(min_lane, min_lane + kLanes);
  uint8_t* __restrict walk = s->walk.data();
  // Bucket 0: the counts before it are 0 (0 / n = 0.0).
  walk[0] = (e1[0] != 0 || e2[0] != 0) && (f1[0] >= max_end || -f2[0] <= min_end) ? 1 : 0;
  for (std::size_t k = 1; k < buckets; ++k) {
    const double upper = f1[k] - f2[k - 1];
    const double lower = f1[k - 1] - f2[k];
    const bool full = (e1[k] != e1[k - 1]) | (e2[k] != e2[k - 1]);
    walk[k] = full & ((upper >= max_end) | (lower <= min_end)) ? 1 : 0;
  }
}

// The same for samples of equal size n < 2^50, on the integer c = i - j instead of the ratios. The
// walk's value at counts (i, j) is w = fl(fl(i / n) - fl(j / n)); with u = 2^-53 and i, j in
// [0, n], fl(i / n) and fl(j / n) are each within u of i / n and j / n (relative error u, values
// at most 1) and their difference is at most 1 in size, so |w - c / n| <= 3u. Two group ends with
// c < c' then have w' - w >= 1 / n - 6u > 0: the walk's values are strictly ordered by c across
// different c. Let C be the largest c at a bucket end: its bucket end's w is a walk value. Inside
// bucket k every group end has c <= I_k - J_{k-1}; if that is below C, all its values are below
// that bucket end's w, so none reaches the maximum; if not, the bucket is walked (a few more than
// the ratios' test, which also skips some with I_k - J_{k-1} = C: harmless, see above). The
// minimum likewise with I_{k-1} - J_k and the smallest c at a bucket end. No division: the counts
// alone, in a loop that vectorises.
void MarkBucketsByCounts(std::size_t buckets, Buffers* s) {
  const uint32_t* __restrict e1 = s->end1.data();
  const uint32_t* __restrict e2 = s->end2.data();
  // c at every bucket end, the largest and the smallest (integers: any order of the lanes).
  int64_t c_max = 0, c_min = 0;  // c at the start, i = j = 0, is no bucket end; any end does
  c_max = c_min = static_cast<int64_t>(e1[0]) - static_cast<int64_t>(e2[0]);
  for (std::size_t k = 1; k < buckets; ++k) {
    const int64_t c = static_cast<int64_t>(e1[k]) - static_cast<int64_t>(e2[k]);
    c_max = std::max(c_max, c);
    c_min = std::min(c_min, c);
  }
  uint8_t* __restrict walk = s->walk.data();
  // Bucket 0: the counts before it are 0.
  walk[0] = (e1[0] != 0 || e2[0] != 0) &&
                    (static_cast<int64_t>(e1[0]) >= c_max || -static_cast<int64_t>(e2[0]) <= c_min)
                ? 1
                : 0;
  for (std::size_t k = 1; k < buckets; ++k) {
    const int64_t upper = static_cast<int64_t>(e1[k]) - static_cast<int64_t>(e2[k - 1]);
    const int64_t lower = static_cast<int64_t>(e1[k - 1]) - static_cast<int64_t>(e2[k]);
    const bool full = (e1[k] != e1[k - 1]) | (e2[k] != e2[k - 1]);
    walk[k] = full & ((upper >= c_max) | (lower <= c_min)) ? 1 : 0;
  }
}

// Which buckets the walk must visit (their indices, in order, into s->walked): by the counts for
// samples of equal size, else by the ratios, and with walk_ends the end buckets if they hold any
// value. Also sizes the write positions and clears the window's marks.
void PlanWalk(std::size_t buckets, std::size_t n1, std::size_t n2, bool walk_ends, Buffers* s) {
  s->walk.resize((buckets + 7) / 8 * 8);
  uint8_t* __restrict walk = s->walk.data();
  if (n1 == n2 && n1 < (std::size_t{1} << 50)) {
    MarkBucketsByCounts(buckets, s);
  } else {
    MarkBucketsByRatios(buckets, static_cast<double>(n1), static_cast<double>(n2), s);
  }
  if (walk_ends) {  // the end buckets too if they hold values (walking more is harmless)
    const uint32_t* e1 = s->end1.data();
    const uint32_t* e2 = s->end2.data();
    walk[0] |= e1[0] != 0 || e2[0] != 0 ? 1 : 0;
    const std::size_t last = buckets - 1;
    if (last > 0) walk[last] |= e1[last] != e1[last - 1] || e2[last] != e2[last - 1] ? 1 : 0;
  }
  // Their indices, 8 flags at a time.
  std::fill(walk + buckets, walk + s->walk.size(), uint8_t{0});
  s->walked.clear();
  for (std::size_t k8 = 0; k8 < buckets; k8 += 8) {
    uint64_t word;
    std::memcpy(&word, walk + k8, 8);
    if (word == 0) continue;
    for (std::size_t k = k8; k < k8 + 8; ++k) {
      if (walk[k] != 0) s->walked.push_back(static_cast<uint32_t>(k));
    }
  }
  // Only the window's buckets' positions are read (after their mark in in_window).
  s->pos1.resize(buckets);
  s->pos2.resize(buckets);
  s->in_window.assign(buckets, 0);
}

// The window that starts at walked bucket s->walked[first]: it ends before the walked bucket whose
// values would take either sample past kWindowValues (but holds at least one bucket). Sets the
// write positions of its buckets (s->pos1, s->pos2) and their marks in s->in_window, and returns
// its runs of consecutive walked buckets (only empty buckets between them) and its end in
// s->walked.
std::size_t PlanWindow(std::size_t first, Buffers* s, std::vector<Run>* runs) {
  runs->clear();
  const uint32_t* e1 = s->end1.data();
  const uint32_t* e2 = s->end2.data();
  const uint32_t* walked = s->walked.data();
  uint32_t a = 0, b = 0;
  uint32_t run_i = 0, run_j = 0;  // the counts at the end of the current run
  bool in_run = false;
  std::size_t w = first;
  for (; w < s->walked.size(); ++w) {
    const uint32_t k = walked[w];
    const uint32_t i0 = k == 0 ? 0 : e1[k - 1], j0 = k == 0 ? 0 : e2[k - 1];
    const uint32_t i1 = e1[k], j1 = e2[k];
    if (in_run && (i0 != run_i || j0 != run_j)) {
      a += 1, b += 1;  // the sentinel slots after the run
      in_run = false;
    }
    // +1: the sentinel slot after the run
    if (w > first && (a + (i1 - i0) + 1 > kWindowValues || b + (j1 - j0) + 1 > kWindowValues)) {
      break;
    }
    if (!in_run) {
      runs->push_back(Run{a, b, 0, 0, i0, j0});
      in_run = true;
    }
    s->pos1[k] = a, s->pos2[k] = b;
    s->in_window[k] = 1;
    a += i1 - i0, b += j1 - j0;
    runs->back().na += i1 - i0, runs->back().nb += j1 - j0;
    run_i = i1, run_j = j1;
  }
  if (in_run) a += 1, b += 1;
  if (s->a.size() < a) s->a.resize(a);
  if (s->b.size() < b) s->b.resize(b);
  return w;
}

// Copies the values of the window's buckets (a mark each in `in_window`) to their write positions
// (pos becomes each bucket's end), a sample at a time. A chunk's buckets are computed in a loop
// that vectorises, their marks gathered 8 to a word (byte loads from a table of one byte a bucket,
// which stays in the first-level cache), and only the values whose mark is set (a few percent)
// are copied, one at a time. Returns the number copied.
std::size_t Extract(std::span<const double> x, EqualWidthBuckets of,
                    const uint8_t* __restrict in_window, uint32_t* __restrict pos,
                    double* __restrict out) {
  const EqualWidthBuckets bucket = of;
  std::size_t copied = 0;
  alignas(64) uint32_t k[kChunk];
  for (std::size_t first = 0; first < x.size(); first += kChunk) {
    const std::size_t n = std::min(kChunk, x.size() - first);
    const double* __restrict v = x.data() + first;
    for (std::size_t i = 0; i < n; ++i) k[i] = bucket(v[i]);
    for (std::size_t i = n; i < (n + 7) / 8 * 8; ++i) k[i] = k[0];  // marks ignored below
    for (std::size_t i8 = 0; i8 < n; i8 += 8) {
      uint64_t word = 0;
      for (std::size_t i = 0; i < 8; ++i) {
        word |= static_cast<uint64_t>(in_window[k[i8 + i]]) << (8 * i);
      }
      while (word != 0) {
        const std::size_t i = i8 + static_cast<std::size_t>(std::countr_zero(word)) / 8;
        word &= word - 1;
        if (i >= n) break;
        const uint32_t p = pos[k[i]];
        out[p] = v[i];
        pos[k[i]] = p + 1;
        ++copied;
      }
    }
  }
  return copied;
}

// Sorts the values of the walked buckets s->walked[first, last) of one sample in place: bucket k's
// values end at pos[k] and number end[k] - end[k - 1].
void SortBuckets(const uint32_t* walked, std::size_t first, std::size_t last, uint32_t* pos,
                 const uint32_t* end, double* v) {
  for (std::size_t w = first; w < last; ++w) {
    const uint32_t k = walked[w];
    const uint32_t count = end[k] - (k == 0 ? 0 : end[k - 1]);
    if (count > 1) SortSmall(v + (pos[k] - count), count);
  }
}

// True when the values of the walked buckets s->walked[first, last) of one sample (as SortBuckets
// finds them) are all finite.
bool AllFinite(const uint32_t* walked, std::size_t first, std::size_t last, const uint32_t* pos,
               const uint32_t* end, const double* v) {
  for (std::size_t w = first; w < last; ++w) {
    const uint32_t k = walked[w];
    const uint32_t count = end[k] - (k == 0 ? 0 : end[k - 1]);
    for (uint32_t i = pos[k] - count; i < pos[k]; ++i) {
      if (!std::isfinite(v[i])) return false;
    }
  }
  return true;
}

// Walks, in order, the buckets listed in s->walked (s->end1, s->end2 and the positions set up by
// PlanWalk), a window at a time. With check_finite, the walked values are checked before they
// are sorted (RequireFinite's InputError if one is not finite).
void WalkMarked(std::span<const double> x, std::span<const double> y, EqualWidthBuckets of,
                bool check_finite, Buffers* s, EcdfExtremes* e) {
  thread_local std::vector<Run> runs;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double dn1 = static_cast<double>(x.size()), dn2 = static_cast<double>(y.size());
  for (std::size_t first = 0; first < s->walked.size();) {
    const std::size_t last = PlanWindow(first, s, &runs);
    // Every value of the window's buckets, as counted: the sorts below take each bucket's values
    // as the count before its end position, so a value not copied would make them read outside
    // the bucket. The buckets are the counting pass's own function of the same values, so this
    // holds unless the code is wrong; checked, so that it fails as an internal error, not as a
    // crash or a silently wrong statistic.
    std::size_t want1 = 0, want2 = 0;
    for (const Run& r : runs) want1 += r.na, want2 += r.nb;
    const std::size_t got1 = Extract(x, of, s->in_window.data(), s->pos1.data(), s->a.data());
    const std::size_t got2 = Extract(y, of, s->in_window.data(), s->pos2.data(), s->b.data());
    PATLAB_CHECK(got1 == want1 && got2 == want2);
    for (std::size_t w = first; w < last; ++w) s->in_window[s->walked[w]] = 0;
    if (check_finite &&
        !(AllFinite(s->walked.data(), first, last, s->pos1.data(), s->end1.data(), s->a.data()) &&
          AllFinite(s->walked.data(), first, last, s->pos2.data(), s->end2.data(), s->b.data()))) {
      RequireFinite(x, "sample 1");  // throws (at the first non-finite value, as the others do)
      RequireFinite(y, "sample 2");
    }
    SortBuckets(s->walked.data(), first, last, s->pos1.data(), s->end1.data(), s->a.data());
    SortBuckets(s->walked.data(), first, last, s->pos2.data(), s->end2.data(), s->b.data());
    for (const Run& r : runs) {
      s->a[r.a0 + r.na] = kInf;
      s->b[r.b0 + r.nb] = kInf;
      WalkSorted(&s->a[r.a0], r.na, &s->b[r.b0], r.nb, r.i0, r.j0, dn1, dn2, e);
    }
    first = last;
  }
}

// Values a bucket: more make the per-bucket arrays smaller and their passes shorter, fewer make
// each bucket's bounds tighter (fewer walked). The walk visits the buckets whose bound comes
// within their size of the extreme, which grows as sqrt(n1 + n2) for samples that differ, so the
// size grows with it: sqrt(n1 + n2) / 72, 2 to 16 (6 for fig5's 100,000 + 100,000 values, which
// reaches the 2^15 buckets' cap). Measured (fig5's statistics, one thread): 100,000 trials a
// point, 2 a bucket 2.0 ms a test, 8 0.61 s in all, 16 0.68 s; 20,000 trials, 4 0.13 s, 8 0.14 s,
// 16 0.17 s. Since the plan is by the integer counts and Extract a look-up, the per-bucket passes
// cost less: on fig5's 96 tests of samples that really differ, 2^15 buckets take 0.237 ms a test
// against 0.272 ms with sqrt / 48 (22,222 buckets; a timing harness, sum of per-test bests).
std::size_t BucketCount(std::size_t n1, std::size_t n2) {
  const double total = static_cast<double>(n1 + n2);
  const auto per_bucket = static_cast<std::size_t>(std::clamp(std::sqrt(total) / 72.0, 2.0, 16.0));
  return std::clamp<std::size_t>((n1 + n2) / per_bucket, std::size_t{1}, kMaxBuckets);
}

// Counts per bucket of x and of y, samples of equal size, turned into the ECDF counts at every
// bucket end (s->end1, s->end2), in one pass over the pairs: a chunk's buckets are computed in a
// loop that vectorises, then counted one at a time.
void CountPairsAtBucketEnds(std::span<const double> x, std::span<const double> y,
                            std::size_t buckets, EqualWidthBuckets of, Buffers* s) {
  s->end1.assign(buckets, 0);
  s->end2.assign(buckets, 0);
  uint32_t* __restrict e1 = s->end1.data();
  uint32_t* __restrict e2 = s->end2.data();
  const EqualWidthBuckets bucket = of;
  alignas(64) uint32_t bx[kChunk], by[kChunk];
  for (std::size_t first = 0; first < x.size(); first += kChunk) {
    const std::size_t n = std::min(kChunk, x.size() - first);
    const double* __restrict xs = x.data() + first;
    const double* __restrict ys = y.data() + first;
    for (std::size_t i = 0; i < n; ++i) bx[i] = bucket(xs[i]), by[i] = bucket(ys[i]);
    for (std::size_t i = 0; i < n; ++i) ++e1[bx[i]], ++e2[by[i]];
  }
  uint32_t sum1 = 0, sum2 = 0;
  for (std::size_t b = 0; b < buckets; ++b) {
    sum1 += e1[b], e1[b] = sum1;
    sum2 += e2[b], e2[b] = sum2;
  }
}

}  // namespace

namespace internal {

EcdfExtremes ExtremesByBucketsIn(std::span<const double> x, std::span<const double> y, double lo,
                                 double hi) {
  const std::size_t buckets = BucketCount(x.size(), y.size());
  const double scale = static_cast<double>(buckets) / (hi - lo);
  if (!(hi > lo) || !std::isfinite(scale) || !std::isfinite(hi - lo)) {
    return EcdfExtremesBySorting(x, y);
  }
  const EqualWidthBuckets bucket_of{lo, scale, static_cast<double>(buckets - 1)};
  Buffers& s = ThreadBuffers();
  CountsAtBucketEnds(x, buckets, bucket_of, &s.end1);
  CountsAtBucketEnds(y, buckets, bucket_of, &s.end2);
  PlanWalk(buckets, x.size(), y.size(), false, &s);
  EcdfExtremes e;
  WalkMarked(x, y, bucket_of, false, &s, &e);
  return e;
}

EcdfExtremes ExtremesOfPairsByBuckets(std::span<const double> x, std::span<const double> y,
                                      double lo, double hi) {
  PATLAB_CHECK(x.size() == y.size() && !x.empty());
  const std::size_t n = x.size();
  const std::size_t buckets = BucketCount(n, n);
  // The guess [lo, hi] over buckets 1 to buckets - 2 (about): bucket 0 holds what lies below it
  // (and NaN, -inf), the last bucket what lies above (and +inf).
  const double scale = static_cast<double>(buckets - 2) / (hi - lo);
  const double below = lo - 1.0 / scale;
  Buffers& s = ThreadBuffers();
  if (buckets >= 3 && hi > lo && std::isfinite(hi - lo) && std::isfinite(scale) && scale > 0.0 &&
      std::isfinite(below)) {
    const EqualWidthBuckets bucket_of{below, scale, static_cast<double>(buckets - 1)};
    CountPairsAtBucketEnds(x, y, buckets, bucket_of, &s);
    // Every value beyond the guess, and every non-finite one, is in an end bucket; if both are
    // empty, every value is finite. If not, the end buckets are walked too (harmless: see
    // MarkBucketsByRatios) and their values checked as they are copied out. A poor guess (more
    // than n / 64 values of a sample in an end bucket, which would be sorted whole): the counts
    // again, over the range, below.
    const uint32_t* e1 = s.end1.data();
    const uint32_t* e2 = s.end2.data();
    const std::size_t crowded = n / 64, before_last = buckets - 2;
    const std::size_t first1 = e1[0], first2 = e2[0];
    const std::size_t last1 = n - e1[before_last], last2 = n - e2[before_last];
    if (std::max({first1, first2, last1, last2}) <= crowded) {
      const bool ends = first1 + first2 + last1 + last2 != 0;
      PlanWalk(buckets, n, n, ends, &s);
      EcdfExtremes e;
      WalkMarked(x, y, bucket_of, ends, &s, &e);
      return e;
    }
  }
  // No usable guess: the range (and finiteness) in passes of their own.
  RequireFinite(x, "sample 1");
  RequireFinite(y, "sample 2");
  const auto [x_lo, x_hi] = MinMax(x);
  const auto [y_lo, y_hi] = MinMax(y);
  return ExtremesByBucketsIn(x, y, std::min(x_lo, y_lo), std::max(x_hi, y_hi));
}

}  // namespace internal

EcdfExtremes EcdfExtremesByBuckets(std::span<const double> x, std::span<const double> y) {
  if (SameSamples(x, y)) return ExtremesOfSameSamples(x);
  const auto [x_lo, x_hi] = MinMax(x);
  const auto [y_lo, y_hi] = MinMax(y);
  return internal::ExtremesByBucketsIn(x, y, std::min(x_lo, y_lo), std::max(x_hi, y_hi));
}

}  // namespace detail

}  // namespace patlab::stats
