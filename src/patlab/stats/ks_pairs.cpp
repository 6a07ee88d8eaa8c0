// The KS walk of pairs that differ by rounding (detail::EcdfExtremesByPairs, declared in ks.h).
#include <algorithm>
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

using internal::Buffers;
using internal::CountsAtBucketEnds;
using internal::EqualWidthBuckets;
using internal::ExtremesByBucketsIn;
using internal::ExtremesOfSameSamples;
using internal::kWindowValues;
using internal::SameSamples;
using internal::SortSmall;
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
// Linear, Triangle: most pairs equal, the others a few ulps apart) are this case: one sort of the
// starts to check them, two coarse histograms and a walk of a few hundred values, instead of a
// walk of every bucket. Anything else (intervals that touch or overlap, no up or no down pair,
// G not reached) goes to EcdfExtremesByBuckets, as do samples that really differ.

namespace {

// The coarse bins of the region walk: few enough to stay in the first-level cache.
constexpr std::size_t kRegionBins = 4096;

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
  PairSummary p;
  double lo = x[0], hi = x[0], widest = 0.0;
  std::size_t up = 0, down = 0;
  unsigned bad = 0;
  constexpr double kMax = std::numeric_limits<double>::max();
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double a = x[k], b = y[k];
    bad |= std::fabs(a) <= kMax && std::fabs(b) <= kMax ? 0U : 1U;
    lo = std::min(lo, std::min(a, b));
    hi = std::max(hi, std::max(a, b));
    widest = std::max(widest, std::fabs(a - b));
    up += a < b ? 1 : 0;
    down += b < a ? 1 : 0;
  }
  if (bad != 0) {
    RequireFinite(x, "sample 1");
    RequireFinite(y, "sample 2");
  }
  p.lo = lo, p.hi = hi, p.widest = widest, p.up = up, p.down = down;
  return p;
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

// True when no interval's start lies within 2 * widest of another's: then every interval ends
// before the next one starts (a rounded width can be one rounding short of the true one; the
// factor 2 covers it). The starts are sorted and compared a window of coarse bins at a time, each
// window holding at most kStartsWindow starts (fig5's samples: one window), so that the buffers
// stay bounded (docs/hardening.md, "Bounded memory"); false also if one bin alone holds more.
// At most this many starts are sorted at a time (two buffers of 512 KB a thread): fig5's samples
// (at most 39,000 starts) take one window, and the buffers stop growing with the trials at about
// 260,000 trials a point, so that the memory per trial below the statistics block stays the
// samples' (scripts/bytes_per_trial.sh with PATTERN=simple: 29.4 B a trial and estimator from
// 600,000 to 10^6 trials with 2^17, 24.0 B with 2^16).
constexpr std::size_t kStartsWindow = std::size_t{1} << 16;

template <class BinOf>
bool StartsApart(std::span<const double> x, std::span<const double> y, std::size_t intervals,
                 double widest, BinOf bin_of, Buffers* s) {
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
    s->a.resize(m + 1);
    s->b.resize(m + 1);
    const std::size_t got = whole ? CopyStarts(
                                        x, y, [](double) { return uint32_t{0}; }, 0, 1, s->a.data())
                                  : CopyStarts(x, y, bin_of, static_cast<uint32_t>(first),
                                               static_cast<uint32_t>(last - first), s->a.data());
    PATLAB_CHECK(got == m);
    const std::span<double> starts(s->a.data(), m);
    SortAscending(starts, std::span<double>(s->b.data(), m));
    for (const double start : starts) {
      if (!(start - previous > 2.0 * widest)) return false;
      previous = start;
    }
    first = last;
  }
  return true;
}

}  // namespace

EcdfExtremes EcdfExtremesByPairs(std::span<const double> x, std::span<const double> y) {
  PATLAB_CHECK(x.size() == y.size() && !x.empty());
  const PairSummary p = SummarisePairs(x, y);
  if (SameSamples(x, y)) return ExtremesOfSameSamples(x);
  const std::size_t n = x.size();
  const double range = p.hi - p.lo;
  // The shortcut needs both directions, and pays only if the intervals are far apart on the
  // average: their total length a small part of the range (else the starts' check fails anyway).
  const double scale = static_cast<double>(kRegionBins) / range;
  if (p.up == 0 || p.down == 0 || !(range > 0.0) || !std::isfinite(scale) ||
      !(p.widest * static_cast<double>(p.up + p.down) < range / 64.0)) {
    return ExtremesByBucketsIn(x, y, p.lo, p.hi);
  }
  Buffers& s = ThreadBuffers();
  const EqualWidthBuckets bin_of{p.lo, scale, static_cast<int64_t>(kRegionBins) - 1};
  if (!StartsApart(x, y, p.up + p.down, p.widest, bin_of, &s)) {
    return ExtremesByBucketsIn(x, y, p.lo, p.hi);
  }
  CountsAtBucketEnds(x, kRegionBins, bin_of, &s.end1);
  CountsAtBucketEnds(y, kRegionBins, bin_of, &s.end2);
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
    std::size_t na = 0, nb = 0;
    const auto lo_bin = static_cast<uint32_t>(first), bins = static_cast<uint32_t>(last - first);
    for (std::size_t k = 0; k < n; ++k) {
      const double a = x[k], b = y[k];
      s.a[na] = a;
      s.b[nb] = b;
      na += bin_of(a) - lo_bin < bins ? 1 : 0;  // unsigned: bins below first wrap to large
      nb += bin_of(b) - lo_bin < bins ? 1 : 0;
    }
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
