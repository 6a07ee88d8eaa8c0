// Internals of the KS walk shared by its source files: ks.cpp (the walk by sorting, KsTwoSample),
// ks_buckets.cpp (the walk by buckets), ks_pairs.cpp and ks_pairs_starts.cpp (the walk of pairs
// that differ by rounding); ks_distribution.cpp holds the p-values. Not part of the public API:
// include ks.h instead.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "patlab/stats/ks.h"

namespace patlab::stats::detail::internal {

// The order of SortAscending as unsigned integers (-0.0 before +0.0).
inline uint64_t OrderKey(double v) {
  const uint64_t u = std::bit_cast<uint64_t>(v);
  constexpr uint64_t kSign = uint64_t{1} << 63;
  return (u & kSign) ? ~u : (u | kSign);
}

// This thread's buffers, grown to the largest samples seen and then reused: fresh arrays cost
// more in page faults than the work on them. Only serial code uses them. The per-bucket arrays
// are O(buckets) (at most kMaxBuckets); a and b hold the values of one window of the buckets that
// must be walked (at most kWindowValues each, below).
struct Buffers {
  std::vector<double> a, b;          // candidate buckets' values in bucket order (or sorted)
  std::vector<uint32_t> end1, end2;  // counts, then the ECDF counts at each bucket's end
  std::vector<uint32_t> pos1, pos2;  // write position of a bucket of the window (in_window)
  std::vector<uint8_t> walk;         // 1 for the buckets the walk must visit
  std::vector<uint32_t> walked;      // their indices, in order
  std::vector<uint8_t> in_window;    // a byte a bucket: 1 for the walked buckets of this window
  std::vector<double> f1, f2;        // ECDF at each bucket end: end1[k] / n1, end2[k] / n2
};
// This thread's Buffers (only serial code uses them).
Buffers& ThreadBuffers();

// The walked buckets' values are copied out, sorted and walked a window of consecutive buckets
// at a time, each window holding at most this many values of each sample (unless one bucket
// alone holds more), so that the buffers a and b stay bounded (256 KB) whatever the sample size:
// one more pass over the samples per window (docs/hardening.md, "Bounded memory"). The walked
// values of fig5's samples that differ (10^5 values, a few percent walked) fit in one or two
// windows; a walk of every bucket (samples that differ by rounding, when the paired shortcut does
// not apply) takes one pass per 2^14 values. Small, so that the buffers are full-sized long before
// the statistics block and the memory per trial below it stays the samples'
// (scripts/bytes_per_trial.sh: 28 B a trial and estimator with 2^18, 24.6 B with 2^14).
constexpr std::size_t kWindowValues = std::size_t{1} << 14;

// Equal-width buckets from lo: bucket k holds the values whose position (v - lo) * scale, clamped
// to [0, last] before its truncation, lies in [k, k + 1). Non-decreasing in v (each rounding is
// monotone, and so are the clamps and the truncation), so bucket k holds values <= those of k + 1
// and equal values share a bucket (-0.0 and +0.0 too: v - lo is the same for both unless lo is a
// zero, where both positions truncate to 0). Values outside [lo, lo + (last + 1) / scale) go to
// the end buckets, a NaN to bucket 0: defined for any input, and the walk stays exact whatever
// the buckets' widths (its bounds only need the order). The clamps compile to a max and a min.
struct EqualWidthBuckets {
  double lo, scale, last;
  uint32_t operator()(double v) const {
    double p = (v - lo) * scale;
    p = p > 0.0 ? p : 0.0;
    p = p < last ? p : last;
    return static_cast<uint32_t>(static_cast<int32_t>(p));
  }
};

// Counts per bucket, turned into the ECDF counts at every bucket end. The buckets of a chunk of
// values are computed first, in a loop that vectorises, then counted one at a time; the running
// sum stays in a register (a sum through memory waits for every store).
template <class BucketOf>
void CountsAtBucketEnds(std::span<const double> x, std::size_t buckets, BucketOf bucket_of,
                        std::vector<uint32_t>* end) {
  end->assign(buckets, 0);
  uint32_t* e = end->data();
  constexpr std::size_t kChunk = 256;
  alignas(64) uint32_t k[kChunk];
  for (std::size_t first = 0; first < x.size(); first += kChunk) {
    const std::size_t n = std::min(kChunk, x.size() - first);
    const double* v = x.data() + first;
    for (std::size_t i = 0; i < n; ++i) k[i] = bucket_of(v[i]);
    for (std::size_t i = 0; i < n; ++i) ++e[k[i]];
  }
  uint32_t sum = 0;
  for (std::size_t b = 0; b < buckets; ++b) sum += e[b], e[b] = sum;
}

// Walks the merged order of a[0, n1) and b[0, n2), both sorted and followed by a +infinity
// sentinel, whose first elements are elements i0 and j0 of the whole samples (definition in
// ks.cpp).
void WalkSorted(const double* a, std::size_t n1, const double* b, std::size_t n2, std::size_t i0,
                std::size_t j0, double dn1, double dn2, EcdfExtremes* e);

// Sorts v[0, n) in SortAscending's order (a bucket's few values).
void SortSmall(double* v, std::size_t n);

// Samples equal index by index, and their extremes (F1 = F2 at every group end).
bool SameSamples(std::span<const double> x, std::span<const double> y);
EcdfExtremes ExtremesOfSameSamples(std::span<const double> x);
// Both in one pass, with RequireFinite's check of x ("sample 1", its InputError) when they are the
// same: a block at a time is compared and, if equal, scanned while it is in the first-level cache
// (the same bits as SameSamples, RequireFinite and ExtremesOfSameSamples one after the other);
// false at the first block that differs (samples that differ do so near their start).
bool ExtremesIfSameSamples(std::span<const double> x, std::span<const double> y, EcdfExtremes* e);

// The paired walk's starts (ks_pairs_starts.cpp): min(x[k], y[k]) of the pairs k < c that differ
// (x[k] != y[k]), appended in order at starts[m] without a branch on the pair; returns the new
// count. starts has room for the pairs that differ + kStartsSlack values: with AVX-512, 8 values
// are stored at a time (the differing ones compressed to the front) at the current end, so up to
// kStartsSlack - 1 past the last start are written (and ignored).
constexpr std::size_t kStartsSlack = 8;
std::size_t CopyDifferingStarts(const double* x, const double* y, std::size_t c, double* starts,
                                std::size_t m);

// True when no interval's start lies within 2 * widest of another's: then every interval ends
// before the next one starts (a rounded width can be one rounding short of the true one; the
// factor 2 covers it). The starts are sorted (by key) and compared a window of coarse bins at a
// time, each window holding at most kStartsWindow starts (fig5's samples: mostly one window), so
// that the buffers stay bounded (docs/hardening.md, "Bounded memory"); false also if one bin alone
// holds more. At most this many starts are sorted at a time (two buffers of 512 KB a thread, the
// sort by key needs no more): fig5's samples (25,000-39,000 starts on most tests) take one
// window, and the buffers stop growing with the trials at about
// 260,000 trials a point, so that the memory per trial below the statistics block stays the
// samples' (scripts/bytes_per_trial.sh with PATTERN=simple: 29.4 B a trial and estimator from
// 600,000 to 10^6 trials with 2^17, 24.0 B with 2^16).
constexpr std::size_t kStartsWindow = std::size_t{1} << 16;

// A key of 22 bits non-decreasing in the start (each rounding is monotone, and so is the clamp):
// the whole range [lo, lo + range] in 2^22 equal cells, so that two starts share a key only if
// they are within about range / 2^22 of each other.
constexpr int kKeyBits = 11, kKeyPasses = 2;
struct StartKey {
  double lo, scale;
  uint32_t operator()(double v) const {
    constexpr double kLargest = static_cast<double>((uint32_t{1} << (kKeyBits * kKeyPasses)) - 1);
    return static_cast<uint32_t>(static_cast<int64_t>(std::min((v - lo) * scale, kLargest)));
  }
};

// Sorts the starts v[0, m) by their keys (scratch w[0, m)); ks_pairs_starts.cpp says how.
void SortStartsByKey(double* v, double* w, std::size_t m, StartKey key);

// True when the starts v[0, m), sorted by key, are each more than 2 * widest above the one
// before (the first above *previous, which becomes the last start); ks_pairs_starts.cpp.
bool ApartInKeyOrder(double* v, std::size_t m, StartKey key, double widest, double* previous);

// EcdfExtremesByBuckets for samples that are not the same, all of whose values lie in [lo, hi].
EcdfExtremes ExtremesByBucketsIn(std::span<const double> x, std::span<const double> y, double lo,
                                 double hi);

// The same for samples of equal size that are not the same, of unknown range and finiteness: lo and
// hi are a guess of the range (from a sample of the pairs). One pass over the pairs counts both
// samples into buckets over the guessed range (values outside it in the end buckets) and finds
// the range and whether every value is finite (RequireFinite's InputError otherwise, "sample 1"
// checked first). If the end buckets hold many values (a poor guess), the counts are taken again
// over the range found (ExtremesByBucketsIn).
EcdfExtremes ExtremesOfPairsByBuckets(std::span<const double> x, std::span<const double> y,
                                      double lo, double hi);

}  // namespace patlab::stats::detail::internal
