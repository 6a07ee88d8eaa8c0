// The KS walk of pairs that differ by rounding (detail::EcdfExtremesByPairs, declared in ks.h).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/stats/ks.h"
#include "patlab/stats/ks_internal.h"
#include "patlab/stats/sort.h"
#include "patlab/stats/summary.h"

namespace patlab::stats::detail {

using internal::ApartInKeyOrder;
using internal::Buffers;
using internal::CopyDifferingStarts;
using internal::ExtremesByBucketsIn;
using internal::ExtremesIfSameSamples;
using internal::ExtremesOfPairsByBuckets;
using internal::kKeyBits;
using internal::kKeyPasses;
using internal::kStartsSlack;
using internal::kStartsWindow;
using internal::kWindowValues;
using internal::SortSmall;
using internal::SortStartsByKey;
using internal::StartKey;
using internal::ThreadBuffers;
using internal::WalkSorted;

// ---- Pairs that differ by rounding (n1 = n2) --------------------------------------------------
//
// Pairing x[k] with y[k] (two estimators' errors in the same trial), c(t) = #{x <= t} - #{y <= t}
// is a sum over the pairs that differ: +1 on [x, y) when x < y ("up"), -1 on [y, x) when y < x
// ("down"). When those intervals are pairwise disjoint (no start within reach of another
// interval), no t is inside two of them, so c is -1, 0 or 1 at every group end; with at least one
// up and one down pair, c = 1 and c = -1 are both reached. For n1 = n2 = n the walk's value at a
// group end with counts (i, j) is fl(fl(i/n) - fl(j/n)), within 3 * 2^-53 of (i - j) / n, so the
// computed values are ordered by c: the maximum is among the group ends with c = 1, where the
// value is v(i) = fl(i/n) - fl((i - 1)/n), and the minimum among those with c = -1, where it is
// fl(i/n) - fl((i + 1)/n) = -v(i + 1). So if G = max over i of v(i) is reached at all, the
// maximum is G, first reached at the first group end with c = 1 and v(i) = G, whose i is at least
// i_G = the smallest i with v(i) = G: at or after the i_G-th smallest x. Walking the merged order
// exactly (WalkSorted) from the coarse bin holding that x until the walk has reached G gives that
// group end; the minimum likewise. Estimators that agree to rounding (fast and ML on Simple,
// Linear, Triangle: most pairs equal, the others a few ulps apart) are this case: a summary pass
// (vectorised), one pass that copies the starts and counts the coarse bins, a sort of the starts
// by a 22-bit key (two radix passes; StartsApart and ApartInKeyOrder prove that the check in key
// order is the check in value order), and a walk of a few hundred values found by a prefiltered
// pass, instead of a walk of every bucket. Anything else (intervals that touch or overlap, no up
// or no down pair, G not reached) goes to EcdfExtremesByBuckets, as do samples that really
// differ; samples equal index by index (a memcmp first) need only the finiteness check.
//
// Cost (tests/bench/stats_bench.cpp, BM_KsFig5Rounding, 100,000 pairs, 30% a few ulps apart; CPU
// time, the smallest of 4-5 runs alternating with the previous version, load 4-5 on 2 cores):
// 0.35 ms from 0.98-1.02 ms; the same values in two arrays 0.035 ms from 0.18 ms. On a faster
// machine (docs/performance.md), the starts copied 8 at a time and the region's near
// pairs found from a mask: 0.204 ms from 0.273 ms.

namespace {

// The coarse bins of the region walk: few enough to stay in the first-level cache.
constexpr std::size_t kRegionBins = 4096;

// The coarse bins: kRegionBins of equal width between lo and hi, non-decreasing in the value
// (each rounding is monotone) so that equal values share a bin. Position is the value in bin
// widths from lo, whose integer part (at most `last`) is the bin.
struct RegionBins {
  double lo, scale;
  int64_t last;
  double Position(double v) const { return (v - lo) * scale; }
  uint32_t operator()(double v) const {
    return static_cast<uint32_t>(std::min(static_cast<int64_t>(Position(v)), last));
  }
};

// The counts of x and of y per coarse bin, turned into the counts at every bin's end (end1, end2).
// Most pairs have both values in one bin: y's counts are x's plus, for each pair whose values'
// bins differ, one in y's bin and minus one in x's (wrapping uint32 arithmetic, exact once
// summed), so the scattered increments are x's and a few. With `starts` (room for the pairs that
// differ + kStartsSlack values), the same pass copies the starts of the pairs that differ into it
// (CopyDifferingStarts) and returns their number.
std::size_t CoarseCounts(std::span<const double> x, std::span<const double> y, RegionBins bin_of,
                         Buffers* s, double* starts) {
  s->end1.assign(kRegionBins, 0);
  s->end2.assign(kRegionBins, 0);
  uint32_t* e1 = s->end1.data();
  uint32_t* e2 = s->end2.data();
  constexpr std::size_t kChunk = 256;
  std::array<uint32_t, kChunk> bx, by;
  const std::size_t n = x.size();
  std::size_t m = 0;
  for (std::size_t k0 = 0; k0 < n; k0 += kChunk) {
    const std::size_t c = std::min(kChunk, n - k0);
    for (std::size_t l = 0; l < c; ++l) bx[l] = bin_of(x[k0 + l]), by[l] = bin_of(y[k0 + l]);
    for (std::size_t l = 0; l < c; ++l) {
      ++e1[bx[l]];
      if (bx[l] != by[l]) ++e2[by[l]], --e2[bx[l]];
    }
    if (starts != nullptr) m = CopyDifferingStarts(x.data() + k0, y.data() + k0, c, starts, m);
  }
  e2[0] += e1[0];
  for (std::size_t k = 1; k < kRegionBins; ++k) {
    e2[k] += e1[k] + e2[k - 1];
    e1[k] += e1[k - 1];
  }
  return m;
}

// v(i) = fl(i/n) - fl((i - 1)/n) for i in [1, n]: its largest value and the smallest i that
// reaches it, for the last n asked (fig5 asks for the same n at every point).
std::pair<double, std::size_t> LargestStep(std::size_t n) {
  thread_local std::size_t cached_n = 0;
  thread_local std::pair<double, std::size_t> cached;
  if (n == cached_n) return cached;
  const double dn = static_cast<double>(n);
  double best = -1.0, previous = 0.0;
  std::size_t at = 0;
  for (std::size_t i = 1; i <= n; ++i) {
    const double q = static_cast<double>(i) / dn;
    const double v = q - previous;
    previous = q;
    if (v > best) best = v, at = i;
  }
  cached_n = n, cached = {best, at};
  return cached;
}

// What one pass over the pairs tells: the range of all values, the pairs that go up and down,
// and the widest interval. The same pass checks that every value is finite (RequireFinite's
// InputError otherwise).
struct PairSummary {
  double lo = 0.0, hi = 0.0, widest = 0.0;
  std::size_t up = 0, down = 0;
};
PairSummary SummarisePairs(std::span<const double> x, std::span<const double> y) {
  // Eight independent lanes (k mod 8 for the first n - n mod 8 pairs, then the rest in lane 0),
  // combined at the end, so that the compiler keeps each in a vector register: minimum and maximum
  // of the values and of the widths (exact whatever the order for finite values, which are the only
  // ones used: the sign of a zero lo or hi may differ, but neither the bins nor the range depend on
  // it), the counts up and down, and a sum of a - a + b - b, which stays 0 while every value is
  // finite and becomes NaN at the first that is not.
  constexpr std::size_t kLanes = 8;
  const std::size_t n = x.size();
  const double* xs = x.data();
  const double* ys = y.data();
  double lo[kLanes], hi[kLanes], widest[kLanes], nonfinite[kLanes];
  int64_t up[kLanes], down[kLanes];
  for (std::size_t l = 0; l < kLanes; ++l) {
    lo[l] = hi[l] = xs[0], widest[l] = nonfinite[l] = 0.0, up[l] = down[l] = 0;
  }
  const auto add = [&](std::size_t l, double a, double b) {
    nonfinite[l] += (a - a) + (b - b);
    lo[l] = std::min(lo[l], std::min(a, b));
    hi[l] = std::max(hi[l], std::max(a, b));
    widest[l] = std::max(widest[l], std::fabs(a - b));
    up[l] += a < b ? 1 : 0;
    down[l] += b < a ? 1 : 0;
  };
  std::size_t k = 0;
  for (; k + kLanes <= n; k += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) add(l, xs[k + l], ys[k + l]);
  }
  for (; k < n; ++k) add(0, xs[k], ys[k]);
  PairSummary p{lo[0], hi[0], widest[0], 0, 0};
  double bad = 0.0;
  for (std::size_t l = 0; l < kLanes; ++l) {
    p.lo = std::min(p.lo, lo[l]), p.hi = std::max(p.hi, hi[l]);
    p.widest = std::max(p.widest, widest[l]);
    p.up += static_cast<std::size_t>(up[l]), p.down += static_cast<std::size_t>(down[l]);
    bad += nonfinite[l];
  }
  if (!(bad == 0.0)) {
    RequireFinite(x, "sample 1");
    RequireFinite(y, "sample 2");
  }
  return p;
}

// A look at a few pairs before the summary pass: kSampleBlocks blocks of kSampleBlock consecutive
// pairs spread over the samples (whole cache lines, read in order). The shortcut pays only if the
// intervals [min, max) are short against the range: the summary pass gives up unless
// widest * (up + down) < range / 64, and widest * (up + down) is at least their total length. The
// sampled pairs' total length, scaled to all the pairs, estimates that total; if the estimate
// reaches the sampled span itself (64 times the limit, against a range that may be wider than the
// span), the shortcut is as good as given up: samples that really differ (fig5's fast and ML on
// Butterfly and SSL-standard: every pair differs, the total some 100 times the span) go to the
// bucket walk at once, which takes the range in its counting pass and needs only the sampled span
// as a guess of it. Estimators that agree to rounding (a few ulps apart: a total some 10^-12 of
// the span) take the summary pass as before. Both paths give the walk's own result bit for bit
// (the shortcut falls back to the bucket walk whenever its conditions fail), so this estimate
// decides only which exact path runs, never a result.
constexpr std::size_t kSampleBlocks = 8, kSampleBlock = 32;
struct PairsLook {
  bool give_up = false;       // the shortcut would not pay
  double lo = 0.0, hi = 0.0;  // the sampled span
};
PairsLook LookAtPairs(std::span<const double> x, std::span<const double> y) {
  const std::size_t n = x.size();
  PairsLook look;
  constexpr std::size_t kSampled = kSampleBlocks * kSampleBlock;
  if (n < kSampled) return look;
  double lo = x[0], hi = x[0], length = 0.0;
  for (std::size_t b = 0; b < kSampleBlocks; ++b) {
    const std::size_t first = b * (n / kSampleBlocks);
    for (std::size_t k = first; k < first + kSampleBlock; ++k) {
      const double a = x[k], c = y[k];
      lo = std::min(lo, std::min(a, c));
      hi = std::max(hi, std::max(a, c));
      length += std::fabs(a - c);
    }
  }
  look.lo = lo, look.hi = hi;
  // false for NaN (the summary pass then reports it) and when the sampled pairs are all equal
  look.give_up =
      length > 0.0 && length * (static_cast<double>(n) / static_cast<double>(kSampled)) >= hi - lo;
  return look;
}

// The starts of the intervals (the smaller value of each pair that differs) with bins in
// [first_bin, last_bin) of `bin_of` (all of them: 0 and ~0), copied without a branch into *out,
// which holds at least the copied values + 1 (`capacity`, counted before).
template <class BinOf>
std::size_t CopyStarts(std::span<const double> x, std::span<const double> y, BinOf bin_of,
                       uint32_t first_bin, uint32_t bins, double* out) {
  std::size_t m = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double start = std::min(x[k], y[k]);
    out[m] = start;
    m += x[k] != y[k] && bin_of(start) - first_bin < bins ? 1 : 0;  // unsigned: below wraps
  }
  return m;
}

// The values of x and of y with bins in [first_bin, first_bin + bins), in their order, into a and
// b, which hold at least the copied values + 1 (counted before). The region holds a few hundred of
// the 2n values: a block of 8 pairs is tested at once (a loop the compiler vectorises) and copied
// (without a branch on each value) only if one of its values is in the region.
std::pair<std::size_t, std::size_t> CopyRegion(std::span<const double> x, std::span<const double> y,
                                               RegionBins bin_of, uint32_t first_bin, uint32_t bins,
                                               double* a, double* b) {
  const auto in = [&](double v) -> std::size_t {
    return bin_of(v) - first_bin < bins ? 1 : 0;  // unsigned: bins below first wrap to large
  };
  std::size_t na = 0, nb = 0;
  const auto copy = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to; ++k) {
      a[na] = x[k];
      b[nb] = y[k];
      na += in(x[k]);
      nb += in(y[k]);
    }
  };
  // A value whose bin is in the region has its position in [first_bin, first_bin + bins) (the
  // bin is its integer part, or `last` if larger), at most bins / 2 from the middle. A chunk of
  // pairs at a time, a loop the compiler vectorises takes each pair's distance from the middle,
  // and only those within bins / 2 + 1 (a bin's slack: some outside may pass, none inside is
  // missed) are tested and copied, in order.
  const double middle = static_cast<double>(first_bin) + 0.5 * static_cast<double>(bins);
  const double reach = 0.5 * static_cast<double>(bins) + 1.0;
  constexpr std::size_t kChunk = 256;
  std::array<double, kChunk> distance;
  const std::size_t n = x.size();
  std::size_t k = 0;
  for (; k + kChunk <= n; k += kChunk) {
    for (std::size_t l = 0; l < kChunk; ++l) {
      distance[l] = std::min(std::fabs(bin_of.Position(x[k + l]) - middle),
                             std::fabs(bin_of.Position(y[k + l]) - middle));
    }
    // The few near ones, found 64 at a time from a mask (a loop that vectorises to compares)
    // instead of a branch on each pair, in order.
    for (std::size_t l0 = 0; l0 < kChunk; l0 += 64) {
      uint64_t near = 0;
      for (std::size_t l = 0; l < 64; ++l) {
        near |= static_cast<uint64_t>(distance[l0 + l] < reach) << l;
      }
      for (; near != 0; near &= near - 1) {
        const std::size_t at = k + l0 + static_cast<std::size_t>(std::countr_zero(near));
        copy(at, at + 1);
      }
    }
  }
  copy(k, n);
  return {na, nb};
}

bool StartsApart(std::span<const double> x, std::span<const double> y, std::size_t intervals,
                 double widest, RegionBins bin_of, StartKey key, Buffers* s) {
  std::vector<uint32_t>& count = s->pos1;  // per coarse bin, then the windows' ends
  if (intervals <= kStartsWindow) {
    count.assign(1, static_cast<uint32_t>(intervals));
  } else {
    count.assign(kRegionBins, 0);
    for (std::size_t k = 0; k < x.size(); ++k) {
      count[bin_of(std::min(x[k], y[k]))] += x[k] != y[k] ? 1 : 0;
    }
  }
  const bool whole = count.size() == 1;
  double previous = -std::numeric_limits<double>::infinity();
  for (std::size_t first = 0; first < count.size();) {
    std::size_t last = first, m = 0;
    while (last < count.size() && m + count[last] <= kStartsWindow) m += count[last++];
    if (last == first) return false;  // one bin holds more than a window
    s->a.resize(std::max(s->a.size(), m + kStartsSlack));
    s->b.resize(std::max(s->b.size(), m + 1));
    // All the starts in one window (fig5's samples): copied by the pass that counts the coarse
    // bins, which the region walk needs after.
    const std::size_t got = whole ? CoarseCounts(x, y, bin_of, s, s->a.data())
                                  : CopyStarts(x, y, bin_of, static_cast<uint32_t>(first),
                                               static_cast<uint32_t>(last - first), s->a.data());
    PATLAB_CHECK(got == m);
    double* starts = s->a.data();
    SortStartsByKey(starts, s->b.data(), m, key);
    if (!ApartInKeyOrder(starts, m, key, widest, &previous)) return false;
    first = last;
  }
  return true;
}

}  // namespace

EcdfExtremes EcdfExtremesByPairs(std::span<const double> x, std::span<const double> y) {
  PATLAB_CHECK(x.size() == y.size() && !x.empty());
  // The same values index by index (fig5's x and y on Linear and Triangle): a memcmp a block at a
  // time, which stops at the first block that differs for the others, with the finiteness check
  // of one of them in the same pass (the values are the same bits, so the first non-finite value
  // of x is the first of either sample and its message is the one the check of both gives:
  // "sample 1 ...").
  if (EcdfExtremes same; ExtremesIfSameSamples(x, y, &same)) return same;
  const PairsLook look = LookAtPairs(x, y);
  if (look.give_up) {
    // The bucket walk over a guess of the range: the sampled span widened by a quarter of it on
    // each side (values beyond it go to the end buckets; fig5's samples have none).
    const double margin = 0.25 * (look.hi - look.lo);
    return ExtremesOfPairsByBuckets(x, y, look.lo - margin, look.hi + margin);
  }
  const PairSummary p = SummarisePairs(x, y);
  const std::size_t n = x.size();
  const double range = p.hi - p.lo;
  // The shortcut needs both directions, and pays only if the intervals are far apart on the
  // average: their total length a small part of the range (else the starts' check fails anyway).
  const double scale = static_cast<double>(kRegionBins) / range;
  if (p.up == 0 || p.down == 0 || !(range > 0.0) || !std::isfinite(range) ||
      !std::isfinite(scale) || !(p.widest * static_cast<double>(p.up + p.down) < range / 64.0)) {
    return ExtremesByBucketsIn(x, y, p.lo, p.hi);
  }
  Buffers& s = ThreadBuffers();
  const RegionBins bin_of{p.lo, scale, static_cast<int64_t>(kRegionBins) - 1};
  // 2^22 cells over the range (each start minus lo is at most the range, so its product with the
  // scale stays below 2^22 (1 + 2^-51); the clamp is there for safety); a range too small for
  // that scale to be finite (below 2^-1002) takes the coarse bins' finite one.
  constexpr double kKeyCells = static_cast<double>(uint32_t{1} << (kKeyBits * kKeyPasses));
  const double key_scale = std::isfinite(kKeyCells / range) ? kKeyCells / range : scale;
  const StartKey key{p.lo, key_scale};
  if (!StartsApart(x, y, p.up + p.down, p.widest, bin_of, key, &s)) {
    return ExtremesByBucketsIn(x, y, p.lo, p.hi);
  }
  if (p.up + p.down > kStartsWindow) CoarseCounts(x, y, bin_of, &s, nullptr);  // else done
  // The first bin whose values can hold a group end with v(i) = G or with the minimum's
  // -v(i + 1) = -G: i >= i_G - 1, so at or after the bin of the (i_G - 1)-th smallest x.
  const auto [largest, first_i] = LargestStep(n);
  const std::size_t need = first_i - 1;
  std::size_t first = 0;
  while (first + 1 < kRegionBins && s.end1[first] < need) ++first;
  // Walk from there, a growing region at a time (at first about kFirstRegion values of x), until
  // both extremes are reached.
  const double dn = static_cast<double>(n);
  const uint32_t i0 = first == 0 ? 0 : s.end1[first - 1], j0 = first == 0 ? 0 : s.end2[first - 1];
  constexpr uint32_t kFirstRegion = 512;
  for (uint32_t target = kFirstRegion;; target *= 4) {
    std::size_t last = first + 1;
    while (last < kRegionBins && s.end1[last - 1] - i0 < target) ++last;
    // The region's values, copied without a branch on whether each one is in it into buffers of
    // their counts + 1, at most a window's (else the buckets' walk, whose memory is bounded).
    const uint32_t count_a = s.end1[last - 1] - i0, count_b = s.end2[last - 1] - j0;
    if (count_a >= kWindowValues || count_b >= kWindowValues) {
      return ExtremesByBucketsIn(x, y, p.lo, p.hi);
    }
    s.a.resize(std::max<std::size_t>(s.a.size(), count_a + 1));
    s.b.resize(std::max<std::size_t>(s.b.size(), count_b + 1));
    const auto [na, nb] = CopyRegion(x, y, bin_of, static_cast<uint32_t>(first),
                                     static_cast<uint32_t>(last - first), s.a.data(), s.b.data());
    PATLAB_CHECK(na == count_a && nb == count_b);
    SortSmall(s.a.data(), na);
    SortSmall(s.b.data(), nb);
    s.a[na] = s.b[nb] = std::numeric_limits<double>::infinity();
    EcdfExtremes e;
    WalkSorted(s.a.data(), na, s.b.data(), nb, i0, j0, dn, dn, &e);
    if (e.max_diff == largest && e.min_diff == -largest) return e;
    if (last == kRegionBins) return ExtremesByBucketsIn(x, y, p.lo, p.hi);
  }
}

}  // namespace patlab::stats::detail
