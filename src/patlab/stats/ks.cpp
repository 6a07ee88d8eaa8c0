#include "patlab/stats/ks.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/stats/ks_internal.h"
#include "patlab/stats/sort.h"
#include "patlab/stats/summary.h"

namespace patlab::stats {

double KolmogorovSurvival(double x) {
  if (!(x > 0.0)) return 1.0;
  if (x < 1.0) {
    // Small x: P(K <= x) = sqrt(2 pi)/x sum_{k>=1} exp(-(2k-1)^2 pi^2 / (8 x^2)) converges fast.
    const double w = -std::numbers::pi * std::numbers::pi / (8.0 * x * x);
    double sum = 0.0;
    for (int k = 1; k < 100; ++k) {
      const double term = std::exp(w * (2 * k - 1) * (2 * k - 1));
      sum += term;
      if (term <= 1e-18 * sum) break;
    }
    return std::clamp(1.0 - std::sqrt(2.0 * std::numbers::pi) / x * sum, 0.0, 1.0);
  }
  // Large x: P(K > x) = 2 sum_{k>=1} (-1)^(k-1) exp(-2 k^2 x^2), no cancellation for x >= 1.
  double sum = 0.0;
  for (int k = 1; k < 100; ++k) {
    const double term = std::exp(-2.0 * k * k * x * x);
    sum += (k % 2 == 1) ? term : -term;
    if (term <= 1e-18 * sum) break;
  }
  return std::clamp(2.0 * sum, 0.0, 1.0);
}

double KsExactEqualTwoSided(std::int64_t n, std::int64_t h) {
  PATLAB_CHECK(n > 0 && h >= 0 && h <= n);
  if (h == 0) return 1.0;
  // P = 2 A0 (1 - A1 (1 - A2 (1 - ...))), A_k = C(2n, n-(k+1)h)/C(2n, n-kh) in product form
  // (scipy _compute_prob_outside_square); avoids the cancellation of the plain alternating sum.
  double p = 0.0;
  for (std::int64_t k = n / h; k >= 0; --k) {
    double p1 = 1.0;
    for (std::int64_t j = 0; j < h; ++j) {
      p1 = static_cast<double>(n - k * h - j) * p1 / static_cast<double>(n + k * h + j + 1);
    }
    p = p1 * (1.0 - p);
  }
  return std::clamp(2.0 * p, 0.0, 1.0);
}

double KsExactEqualOneSided(std::int64_t n, std::int64_t h) {
  PATLAB_CHECK(n > 0 && h >= 0 && h <= n);
  double p = 1.0;
  for (std::int64_t j = 0; j < h; ++j) {
    p *= static_cast<double>(n - j) / static_cast<double>(n + j + 1);
  }
  return std::clamp(p, 0.0, 1.0);
}

double KsExactLattice(std::int64_t n1, std::int64_t n2, std::int64_t h, bool two_sided) {
  PATLAB_CHECK(n1 > 0 && n2 > 0 && h >= 0);
  if (h == 0) return 1.0;
  const std::int64_t g = std::gcd(n1, n2);
  const std::int64_t n1g = n1 / g;
  const std::int64_t n2g = n2 / g;
  // A path takes i steps of sample 1 and j of sample 2; there F1 - F2 = (i n2g - j n1g) / lcm.
  // b[j] holds B(i, j) = P(a uniformly random path to (i, j) has touched |F1 - F2| >= h/lcm)
  // (or F1 - F2 >= h/lcm one-sided). B = 1 on the boundary, else
  // B(i, j) = (i B(i-1, j) + j B(i, j-1)) / (i + j) because a fraction i/(i+j) of the paths to
  // (i, j) arrive from (i-1, j) (Viehmann 2021, eq. 5).
  auto outside = [&](std::int64_t i, std::int64_t j) {
    const std::int64_t diff = i * n2g - j * n1g;
    return two_sided ? (diff >= h || -diff >= h) : diff >= h;
  };
  std::vector<double> b(static_cast<std::size_t>(n2) + 1);
  b[0] = 0.0;
  for (std::int64_t j = 1; j <= n2; ++j) b[j] = outside(0, j) ? 1.0 : b[j - 1];
  for (std::int64_t i = 1; i <= n1; ++i) {
    const double di = static_cast<double>(i);
    b[0] = outside(i, 0) ? 1.0 : b[0];
    for (std::int64_t j = 1; j <= n2; ++j) {
      if (outside(i, j)) {
        b[j] = 1.0;
      } else {
        const double dj = static_cast<double>(j);
        b[j] = (di * b[j] + dj * b[j - 1]) / (di + dj);
      }
    }
  }
  return std::clamp(b[n2], 0.0, 1.0);
}

namespace detail {

using internal::Buffers;
using internal::CountsAtBucketEnds;
using internal::EqualWidthBuckets;
using internal::ExtremesOfSameSamples;
using internal::kWindowValues;
using internal::OrderKey;
using internal::SameSamples;
using internal::SortSmall;
using internal::ThreadBuffers;
using internal::WalkSorted;

namespace internal {

// Walks the merged order of a[0, n1) and b[0, n2), both sorted and followed by a +infinity
// sentinel, whose first elements are elements i0 and j0 of the whole samples, and compares the
// ECDFs only after every copy of a tied value, as scipy does with searchsorted(side=right). Each
// step consumes the smaller head value from one or both samples without a branch on which (that
// branch mispredicted every other element); a step ends a group of equal values when neither
// head still equals it, and only then is F1 - F2 compared, with the group's value taken at its
// first step, as an element-at-a-time walk would.
void WalkSorted(const double* a, std::size_t n1, const double* b, std::size_t n2, std::size_t i0,
                std::size_t j0, double dn1, double dn2, EcdfExtremes* e) {
  std::size_t i = 0, j = 0;
  double group_v = 0.0;
  bool group_start = true;
  while (i < n1 || j < n2) {
    const double ai = a[i], bj = b[j];
    const double v = ai <= bj ? ai : bj;
    i += ai == v ? 1 : 0;
    j += bj == v ? 1 : 0;
    group_v = group_start ? v : group_v;
    group_start = a[i] != v && b[j] != v;
    if (!group_start) continue;
    // Same operations as scipy: searchsorted(...)/n1 - searchsorted(...)/n2.
    const double diff = static_cast<double>(i0 + i) / dn1 - static_cast<double>(j0 + j) / dn2;
    if (diff > e->max_diff) e->max_diff = diff, e->max_loc = group_v;
    if (diff < e->min_diff) e->min_diff = diff, e->min_loc = group_v;
  }
}

}  // namespace internal

namespace {

// Copies [first, last) into out followed by a +infinity sentinel, sorted in SortAscending's order.
void SortedWithSentinel(const double* first, const double* last, std::vector<double>* out) {
  out->assign(first, last);
  std::sort(out->begin(), out->end(), [](double p, double q) { return OrderKey(p) < OrderKey(q); });
  out->push_back(std::numeric_limits<double>::infinity());
}

}  // namespace

namespace internal {

// Sorts v[0, n) in SortAscending's order: insertion sort for the few values of a bucket,
// std::sort beyond.
void SortSmall(double* v, std::size_t n) {
  if (n > 16) {
    std::sort(v, v + n, [](double p, double q) { return OrderKey(p) < OrderKey(q); });
    return;
  }
  for (std::size_t i = 1; i < n; ++i) {
    const double value = v[i];
    const uint64_t key = OrderKey(value);
    std::size_t k = i;
    for (; k > 0 && OrderKey(v[k - 1]) > key; --k) v[k] = v[k - 1];
    v[k] = value;
  }
}

Buffers& ThreadBuffers() {
  thread_local Buffers buffers;
  return buffers;
}

}  // namespace internal

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

}  // namespace

namespace internal {

// Samples that are the same values index by index (e.g. two estimators that agree exactly) have
// F1 = F2 after every group: the walk sees diff = i / n - i / n = 0 at every group end, and keeps
// the first, whose value is the smallest in SortAscending's order.
bool SameSamples(std::span<const double> x, std::span<const double> y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
}
EcdfExtremes ExtremesOfSameSamples(std::span<const double> x) {
  uint64_t smallest = OrderKey(x[0]);
  for (const double v : x) smallest = std::min(smallest, OrderKey(v));
  const double loc = std::bit_cast<double>(
      (smallest & (uint64_t{1} << 63)) ? (smallest & ~(uint64_t{1} << 63)) : ~smallest);
  return EcdfExtremes{0.0, 0.0, loc, loc};
}

}  // namespace internal

namespace {

// A run of consecutive buckets to walk: its values start at a0 (b0) in the buffers, and at i0
// (j0) in the merged order of the whole samples.
struct Run {
  uint32_t a0, b0, na, nb, i0, j0;
};

}  // namespace

EcdfExtremes EcdfExtremesBySorting(std::span<const double> x, std::span<const double> y) {
  Buffers& s = ThreadBuffers();
  SortedWithSentinel(x.data(), x.data() + x.size(), &s.a);
  SortedWithSentinel(y.data(), y.data() + y.size(), &s.b);
  EcdfExtremes e;
  WalkSorted(s.a.data(), x.size(), s.b.data(), y.size(), 0, 0, static_cast<double>(x.size()),
             static_cast<double>(y.size()), &e);
  return e;
}

namespace {

// EqualWidthBuckets' arithmetic on copies of its members that the loops below keep in registers
// (the struct itself, passed on, was reloaded from memory after every store of a double).
struct LocalBuckets {
  const double lo, scale;
  const int64_t last;
  uint32_t operator()(double v) const {
    return static_cast<uint32_t>(std::min(static_cast<int64_t>((v - lo) * scale), last));
  }
};

// Extract first computes the buckets of a chunk of values in a loop the compiler vectorises, then
// uses them one at a time in a second loop.
constexpr std::size_t kChunk = 256;

// Which buckets the walk must visit (their indices, in order, into s->walked). Every bucket end
// is a group end of the walk, so the largest (smallest) of the bucket-end values D_k, computed as
// the walk computes them, is a lower (upper) bound on the walk's extreme. Inside bucket k the
// walk's values lie between L_k = I_{k-1} / n1 - J_k / n2 and U_k = I_k / n1 - J_{k-1} / n2,
// computed the same way (each rounding is monotone, so the bound holds for the computed values
// exactly). A bucket with U_k < max D and L_k > min D holds no group end that reaches either
// extreme, and the walk keeps the first group end that does, so skipping such buckets leaves the
// result unchanged. Also sizes the write positions and clears the window's bits.
void PlanWalk(std::size_t buckets, double dn1, double dn2, Buffers* s) {
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
  // A byte a bucket (1: walk it) in a loop that vectorises, then their indices, 8 flags at a time.
  s->walk.resize((buckets + 7) / 8 * 8);
  uint8_t* __restrict walk = s->walk.data();
  // Bucket 0: the counts before it are 0 (0 / n = 0.0).
  walk[0] = (e1[0] != 0 || e2[0] != 0) && (f1[0] >= max_end || -f2[0] <= min_end) ? 1 : 0;
  for (std::size_t k = 1; k < buckets; ++k) {
    const double upper = f1[k] - f2[k - 1];
    const double lower = f1[k - 1] - f2[k];
    const bool full = (e1[k] != e1[k - 1]) | (e2[k] != e2[k - 1]);
    walk[k] = full & ((upper >= max_end) | (lower <= min_end)) ? 1 : 0;
  }
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
  // Only the window's buckets' positions are read (after their bit in in_window).
  s->pos1.resize(buckets);
  s->pos2.resize(buckets);
  s->in_window.assign((buckets + 63) / 64, 0);
}

// The window that starts at walked bucket s->walked[first]: it ends before the walked bucket whose
// values would take either sample past kWindowValues (but holds at least one bucket). Sets the
// write positions of its buckets (s->pos1, s->pos2) and their bits in s->in_window, and returns
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
    s->in_window[k / 64] |= uint64_t{1} << (k % 64);
    a += i1 - i0, b += j1 - j0;
    runs->back().na += i1 - i0, runs->back().nb += j1 - j0;
    run_i = i1, run_j = j1;
  }
  if (in_run) a += 1, b += 1;
  if (s->a.size() < a) s->a.resize(a);
  if (s->b.size() < b) s->b.resize(b);
  return w;
}

// At most this many ranges of buckets cover the window's walked buckets for the first test in
// Extract (a few compares that vectorise; the walked buckets of fig5's samples that differ are a
// few dozen in a few runs, around the two extremes).
constexpr std::size_t kCoverRanges = 4;
struct Cover {
  uint32_t first[kCoverRanges] = {}, size[kCoverRanges] = {};  // size 0: an unused range
};

// At most kCoverRanges ranges that hold the buckets walked[first, last) (increasing, at least one)
// and the fewest other buckets: the span from the first to the last, split at the widest
// kCoverRanges - 1 gaps between consecutive walked buckets (one pass, however many runs).
Cover CoverOf(const uint32_t* walked, std::size_t first, std::size_t last) {
  constexpr std::size_t kSplits = kCoverRanges - 1;
  // (gap, w): the buckets between walked[w] and walked[w + 1]; widest first, gap 0 = no split
  std::array<std::pair<uint32_t, std::size_t>, kSplits> widest{};
  for (std::size_t w = first; w + 1 < last; ++w) {
    const uint32_t gap = walked[w + 1] - walked[w] - 1;
    if (gap <= widest[kSplits - 1].first) continue;
    std::size_t at = kSplits - 1;
    for (; at > 0 && widest[at - 1].first < gap; --at) widest[at] = widest[at - 1];
    widest[at] = {gap, w};
  }
  std::sort(widest.begin(), widest.end(),
            [](const auto& p, const auto& q) { return p.second < q.second; });
  Cover c;
  uint32_t start = walked[first];
  std::size_t r = 0;
  for (const auto& [gap, w] : widest) {
    if (gap == 0) continue;
    c.first[r] = start, c.size[r] = walked[w] - start + 1;
    ++r, start = walked[w + 1];
  }
  c.first[r] = start, c.size[r] = walked[last - 1] - start + 1;
  return c;
}

// Copies the values of the window's buckets (a bit each in `in_window`) to their write positions
// (pos becomes each bucket's end), a sample at a time. A chunk's buckets and whether each lies in
// the cover are computed in a loop that vectorises; only the values in the cover (a few percent)
// are looked at one by one.
void Extract(std::span<const double> x, const EqualWidthBuckets& of, const Cover& cover,
             const uint64_t* __restrict in_window, uint32_t* __restrict pos,
             double* __restrict out) {
  const LocalBuckets bucket{of.lo, of.scale, of.last};
  alignas(64) uint32_t k[kChunk];
  alignas(64) uint8_t hit[kChunk];
  const Cover c = cover;
  for (std::size_t first = 0; first < x.size(); first += kChunk) {
    const std::size_t n = std::min(kChunk, x.size() - first);
    const double* __restrict v = x.data() + first;
    for (std::size_t i = 0; i < n; ++i) {
      const uint32_t kk = bucket(v[i]);
      k[i] = kk;
      uint8_t h = 0;
      for (std::size_t r = 0; r < kCoverRanges; ++r) h |= kk - c.first[r] < c.size[r] ? 1 : 0;
      hit[i] = h;
    }
    for (std::size_t i = n; i < (n + 7) / 8 * 8; ++i) hit[i] = 0;
    for (std::size_t i8 = 0; i8 < n; i8 += 8) {
      uint64_t word;
      std::memcpy(&word, hit + i8, 8);
      if (word == 0) continue;
      for (std::size_t i = i8; i < i8 + 8 && i < n; ++i) {
        if ((in_window[k[i] / 64] >> (k[i] % 64) & 1) == 0) continue;
        const uint32_t p = pos[k[i]];
        out[p] = v[i];
        pos[k[i]] = p + 1;
      }
    }
  }
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

// Walks, in order, the buckets listed in s->walked (s->end1, s->end2 and the positions set up by
// PlanWalk), a window at a time.
void WalkMarked(std::span<const double> x, std::span<const double> y, const EqualWidthBuckets& of,
                Buffers* s, EcdfExtremes* e) {
  thread_local std::vector<Run> runs;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double dn1 = static_cast<double>(x.size()), dn2 = static_cast<double>(y.size());
  for (std::size_t first = 0; first < s->walked.size();) {
    const std::size_t last = PlanWindow(first, s, &runs);
    const Cover cover = CoverOf(s->walked.data(), first, last);
    Extract(x, of, cover, s->in_window.data(), s->pos1.data(), s->a.data());
    Extract(y, of, cover, s->in_window.data(), s->pos2.data(), s->b.data());
    for (std::size_t w = first; w < last; ++w) s->in_window[s->walked[w] / 64] = 0;
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

}  // namespace

namespace internal {

EcdfExtremes ExtremesByBucketsIn(std::span<const double> x, std::span<const double> y, double lo,
                                 double hi) {
  // Values a bucket: more make the per-bucket arrays smaller and their passes shorter, fewer make
  // each bucket's bounds tighter (fewer walked). The walk visits the buckets whose bound comes
  // within their size of the extreme, which grows as sqrt(n1 + n2) for samples that differ, so the
  // size grows with it: sqrt(n1 + n2) / 48, 2 to 16 (9 for fig5's 100,000 + 100,000 values).
  // Measured (fig5's statistics, one thread): 100,000 trials a point, 2 a bucket 2.0 ms a test,
  // 8 0.61 s in all, 16 0.68 s; 20,000 trials, 4 0.13 s, 8 0.14 s, 16 0.17 s.
  const double total = static_cast<double>(x.size() + y.size());
  const auto per_bucket = static_cast<std::size_t>(std::clamp(std::sqrt(total) / 48.0, 2.0, 16.0));
  const std::size_t buckets =
      std::clamp<std::size_t>((x.size() + y.size()) / per_bucket, std::size_t{1}, kMaxBuckets);
  const double dn1 = static_cast<double>(x.size()), dn2 = static_cast<double>(y.size());
  const double scale = static_cast<double>(buckets) / (hi - lo);
  if (!(hi > lo) || !std::isfinite(scale) || !std::isfinite(hi - lo)) {
    return EcdfExtremesBySorting(x, y);
  }
  const EqualWidthBuckets bucket_of{lo, scale, static_cast<int64_t>(buckets) - 1};
  Buffers& s = ThreadBuffers();
  CountsAtBucketEnds(x, buckets, bucket_of, &s.end1);
  CountsAtBucketEnds(y, buckets, bucket_of, &s.end2);
  PlanWalk(buckets, dn1, dn2, &s);
  EcdfExtremes e;
  WalkMarked(x, y, bucket_of, &s, &e);
  return e;
}

}  // namespace internal

EcdfExtremes EcdfExtremesByBuckets(std::span<const double> x, std::span<const double> y) {
  if (SameSamples(x, y)) return ExtremesOfSameSamples(x);
  const auto [x_lo, x_hi] = MinMax(x);
  const auto [y_lo, y_hi] = MinMax(y);
  return internal::ExtremesByBucketsIn(x, y, std::min(x_lo, y_lo), std::max(x_hi, y_hi));
}

}  // namespace detail

namespace {

// Samples this large go through the buckets (two passes and a few small sorts); smaller ones
// are sorted whole.
constexpr std::size_t kKsBucketMinSize = 4096;

}  // namespace

KsResult KsTwoSample(std::span<const double> x, std::span<const double> y,
                     const KsOptions& options) {
  if (x.empty() || y.empty()) {
    throw InputError("the KS test needs two non-empty samples, got " + std::to_string(x.size()) +
                     " and " + std::to_string(y.size()) +
                     " values; expected at least one value in each");
  }
  const std::size_t n1 = x.size();
  const std::size_t n2 = y.size();
  // The paired walk checks the values as it reads them; the others are checked first.
  const bool pairs = n1 == n2 && n1 + n2 >= kKsBucketMinSize;
  if (!pairs) {
    detail::RequireFinite(x, "sample 1");
    detail::RequireFinite(y, "sample 2");
  }
  const detail::EcdfExtremes e = pairs                        ? detail::EcdfExtremesByPairs(x, y)
                                 : n1 + n2 < kKsBucketMinSize ? detail::EcdfExtremesBySorting(x, y)
                                                              : detail::EcdfExtremesByBuckets(x, y);
  const double dn1 = static_cast<double>(n1);
  const double dn2 = static_cast<double>(n2);
  const double max_diff = e.max_diff, min_diff = e.min_diff;
  const double max_loc = e.max_loc, min_loc = e.min_loc;
  const double min_s = std::clamp(-min_diff, 0.0, 1.0);

  KsResult result;
  result.n1 = n1;
  result.n2 = n2;
  const Alternative alt = options.alternative;
  if (alt == Alternative::kLess || (alt == Alternative::kTwoSided && min_s > max_diff)) {
    result.d = min_s, result.sign = -1, result.location = min_loc;
  } else {
    result.d = max_diff, result.sign = 1, result.location = max_loc;
  }

  KsMethod method = options.method;
  if (method == KsMethod::kAuto) {
    method = std::max(n1, n2) <= kKsMaxAutoExactN ? KsMethod::kExact : KsMethod::kAsymptotic;
  }
  const std::int64_t g = std::gcd(static_cast<std::int64_t>(n1), static_cast<std::int64_t>(n2));
  if (method == KsMethod::kExact) {
    const std::int64_t lcm = static_cast<std::int64_t>(n1) / g * static_cast<std::int64_t>(n2);
    const auto h = static_cast<std::int64_t>(std::nearbyint(result.d * static_cast<double>(lcm)));
    result.d = static_cast<double>(h) / static_cast<double>(lcm);
    const bool two_sided = alt == Alternative::kTwoSided;
    if (n1 == n2) {
      const auto n = static_cast<std::int64_t>(n1);
      result.p_value = two_sided ? KsExactEqualTwoSided(n, h) : KsExactEqualOneSided(n, h);
    } else if (static_cast<std::uint64_t>(n1) * n2 <= kKsMaxExactLatticeSteps) {
      result.p_value = KsExactLattice(static_cast<std::int64_t>(n1), static_cast<std::int64_t>(n2),
                                      h, two_sided);
    } else {
      method = KsMethod::kAsymptotic;
    }
  }
  if (method == KsMethod::kAsymptotic) {
    const double m = std::max(dn1, dn2);
    const double n = std::min(dn1, dn2);
    const double en = m * n / (m + n);
    const double z = std::sqrt(en) * result.d;
    if (alt == Alternative::kTwoSided) {
      result.p_value = KolmogorovSurvival(z);
    } else {
      // Hodges (1958) eq. 5.3, as scipy; m is the larger sample.
      result.p_value =
          std::exp(-2.0 * z * z - 2.0 * z * (m + 2.0 * n) / std::sqrt(m * n * (m + n)) / 3.0);
    }
  }
  result.method_used = method;
  result.p_value = std::clamp(result.p_value, 0.0, 1.0);
  result.d_scaled = std::sqrt(dn1 * dn2 / (dn1 + dn2)) * result.d;
  return result;
}

}  // namespace patlab::stats
