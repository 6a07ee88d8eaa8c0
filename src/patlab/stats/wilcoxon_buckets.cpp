// The signed-rank sums without a full sort (detail::SignedRankSumsByBuckets): the differences'
// magnitudes mapped to buckets that keep their order, scattered, and ranked a bucket at a time,
// with ties and zeros counted as the sorted walk counts them.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/stats/sort.h"
#include "patlab/stats/summary.h"
#include "patlab/stats/wilcoxon.h"
#include "patlab/stats/wilcoxon_internal.h"

namespace patlab::stats {

using detail::internal::DifferenceScan;
using detail::internal::kInfinityBits;
using detail::internal::kSignBit;
using detail::internal::ScanDifferences;

namespace {

// At most 2^17 buckets (O(buckets) thread-local counters, docs/hardening.md "Bounded memory").
constexpr std::size_t kMaxRankBuckets = std::size_t{1} << 17;
// The coarse bins of the bucket map: 2^13 counters (see BucketMap).
constexpr unsigned kCoarseBits = 13;
constexpr std::size_t kCoarseBins = std::size_t{1} << kCoarseBits;
// The coarse bins are counted on every kSampleStride-th value.
constexpr std::size_t kSampleStride = 4;
// Bins and keys are computed kIdBlock values at a time (loops that vectorise; the table lookups
// as gathers), then counted or scattered.
constexpr std::size_t kIdBlock = 256;
// Buckets per non-zero value (within the cap): num / den.
constexpr std::uint64_t kBucketsPerValueNum = 1;
constexpr std::uint64_t kBucketsPerValueDen = 2;
// A key holds a bucket (< 2^17), the low `shift` bits of |d| and the sign bit: shift <= 46.
constexpr unsigned kMaxLowBits = 46;
// A value is ranked by comparing it with the kWindow keys either side of it in bucket order;
// buckets of up to kWindow + 1 values always fit in the window.
constexpr std::size_t kWindow = 7;
// Below this, a sum of the integers t^3 - t is exact in double whatever the order of additions.
constexpr std::uint64_t kExactTieSum = std::uint64_t{1} << 52;
// The zeros' tie term n0^3 - n0 fits in 64 bits up to here.
constexpr std::size_t kMaxZeroGroup = std::size_t{1} << 17;

inline std::uint64_t KeyAt(const double* keys, std::size_t i) {
  return std::bit_cast<std::uint64_t>(keys[i]);
}
inline std::uint64_t MagnitudeAt(const double* keys, std::size_t i) { return KeyAt(keys, i) >> 1; }

// A non-decreasing map of |d| onto about one bucket per two non-zero values, however the magnitudes
// spread (the runner's differences are heavy-tailed: on n / 2 equal-width buckets a few buckets
// near 0 held tens of values each). Two levels, both on the bits m of |d| (which order as |d|
// does):
// - coarse bin c = (m >> shift) - (smallest >> shift), with the smallest shift that puts every
//   non-zero magnitude into kCoarseBins bins (a bin is a 2^-k slice of a binade: log-like);
// - the bin's alloc[c] fine buckets, numbered from off[c] (off[c + 1] = off[c] + alloc[c]),
//   share its span linearly: bucket = off[c] + floor(low * alloc[c] / 2^shift), low = the
//   lowest `shift` bits of m. alloc[c] >= 1 for every bin up to the largest |d|'s, and follows
//   the bin's count in a sample, so that buckets hold ~2 values (a wrong share costs time only).
// Bucket 0 holds the zeros. Monotone: for m < m', either c < c', and then bucket(m) <= off[c] +
// alloc[c] - 1 < off[c'] <= bucket(m') since low < 2^shift; or c == c' and low < low', and the
// integer product and shift round down alike, so bucket(m) <= bucket(m'). Equal magnitudes get
// equal buckets, and a value of a lower bucket is smaller than every value of a higher one.
// Within a bucket all m share m >> shift (one coarse bin), so the key
//   bucket << (shift + 1) | low << 1 | (1 if d > 0)
// orders by |d| (key >> 1 by bucket, then by low), equal |d| have equal key >> 1, and the bucket
// is key >> (shift + 1): everything after the map works on keys, without the table.
struct BucketMap {
  unsigned shift = 0;
  std::uint64_t base = 0;      // smallest >> shift
  std::uint64_t low_mask = 0;  // 2^shift - 1
  std::size_t buckets = 0;     // bucket ids are 0 .. buckets - 1
  // Per coarse bin (and one more, kCoarseBins, for the zeros: 0): off[c] << 32 | alloc[c].
  std::array<std::uint64_t, kCoarseBins + 1> table{};

  std::uint64_t CoarseOf(std::uint64_t m) const {
    return m == 0 ? kCoarseBins : (m >> shift) - base;
  }
  // The key of a value whose |d| has bits m.
  std::uint64_t KeyOf(double v) const {
    const auto u = std::bit_cast<std::uint64_t>(v);
    const std::uint64_t m = u & ~kSignBit, low = m & low_mask;
    const std::uint64_t entry = table[CoarseOf(m)];
    const std::uint64_t bucket = (entry >> 32) + ((low * (entry & 0xffffffffU)) >> shift);
    return (bucket << (shift + 1)) | (low << 1) | ((u >> 63) ^ 1);
  }
  std::uint64_t BucketOfKey(std::uint64_t key) const { return key >> (shift + 1); }
};

// The map for the non-zero magnitudes of d (scan's smallest to largest): false when they span
// too many binades for kMaxLowBits low bits.
bool MakeBucketMap(std::span<const double> d, const DifferenceScan& scan, BucketMap* map) {
  unsigned shift = 0;
  while ((scan.largest >> shift) - (scan.smallest >> shift) >= kCoarseBins) ++shift;
  if (shift > kMaxLowBits) return false;
  map->shift = shift;
  map->base = scan.smallest >> shift;
  map->low_mask = (std::uint64_t{1} << shift) - 1;
  // The count of each coarse bin (the zeros' bin last) among every kSampleStride-th value (the
  // counts only share out the buckets: any alloc >= 1 per bin keeps the map monotone), kIdBlock
  // values at a time: the bins in a loop that vectorises, then the counts.
  thread_local std::array<std::uint32_t, kCoarseBins + 1> counts;
  counts.fill(0);
  std::array<std::uint32_t, kIdBlock> ids{};
  const std::size_t n = d.size(), sampled = (n + kSampleStride - 1) / kSampleStride;
  for (std::size_t i0 = 0; i0 < sampled; i0 += kIdBlock) {
    const std::size_t len = std::min(kIdBlock, sampled - i0);
    for (std::size_t i = 0; i < len; ++i) {
      ids[i] = static_cast<std::uint32_t>(
          map->CoarseOf(std::bit_cast<std::uint64_t>(d[(i0 + i) * kSampleStride]) & ~kSignBit));
    }
    for (std::size_t i = 0; i < len; ++i) ++counts[ids[i]];
  }
  // alloc[c] = max(1, count * budget / sampled non-zero) for every bin up to the largest |d|'s:
  // at most budget + kCoarseBins buckets besides bucket 0.
  const std::uint64_t sampled_nonzero = std::max<std::uint64_t>(1, sampled - counts[kCoarseBins]);
  const std::uint64_t budget =
      std::min<std::uint64_t>(kMaxRankBuckets - 1 - kCoarseBins,
                              (n - scan.n_zero) * kBucketsPerValueNum / kBucketsPerValueDen);
  const std::uint64_t top = (scan.largest >> shift) - map->base;  // < kCoarseBins
  std::uint64_t off = 1;
  for (std::size_t c = 0; c < kCoarseBins; ++c) {
    const std::uint64_t alloc =
        c > top ? 0 : std::max<std::uint64_t>(1, counts[c] * budget / sampled_nonzero);
    map->table[c] = (off << 32) | alloc;
    off += alloc;
  }
  map->table[kCoarseBins] = 0;
  map->buckets = off;
  return true;
}

// Undoes BucketMap::KeyOf on keys (in any order): the key's bucket gives its coarse bin (the
// last bin whose first bucket is not above it; bucket 0 is the zeros' bin), whose bits with the
// low bits give |d|, and the lowest bit the sign: each value exactly as it was.
void RestoreDifferences(const BucketMap& map, std::span<double> values) {
  std::array<std::uint32_t, kCoarseBins> first{};  // the first bucket of each coarse bin
  for (std::size_t c = 0; c < kCoarseBins; ++c) {
    first[c] = static_cast<std::uint32_t>(map.table[c] >> 32);
  }
  for (double& v : values) {
    const auto key = std::bit_cast<std::uint64_t>(v);
    const std::uint64_t bucket = map.BucketOfKey(key), low = (key >> 1) & map.low_mask;
    std::uint64_t m = 0;
    if (bucket != 0) {
      const auto c = static_cast<std::uint64_t>(
          std::upper_bound(first.begin(), first.end(), bucket) - first.begin() - 1);
      m = ((map.base + c) << map.shift) | low;
    }
    v = std::bit_cast<double>(m | ((key & 1) != 0 ? 0 : kSignBit));
  }
}

// Integer tallies: a value's rank0 is the number of non-zero |d| smaller than its |d|, and its
// group of t equal magnitudes shares the midrank rank0 + (t + 1) / 2, summed twice over so that
// it is an integer.
struct RankTally {
  std::uint64_t twice_r_plus = 0;  // sum over d > 0 of 2 x midrank
  std::uint64_t positives = 0;
  std::uint64_t tie_terms = 0;  // sum of t^3 - t over the groups: t^2 - 1 for each value
};

inline void AddValue(std::uint64_t key, std::uint64_t rank0, std::uint64_t group,
                     RankTally* tally) {
  const std::uint64_t positive = key & 1;
  tally->twice_r_plus += positive * (2 * rank0 + group + 1);
  tally->positives += positive;
  tally->tie_terms += group * group - 1;
}

// Ranks the values at positions [lo, hi) of the keys in bucket order (kWindow < lo,
// hi + kWindow < n) whose bucket lies inside the window of kWindow positions either side: every
// key before the window is then of a smaller magnitude, every key after it of a larger one, so
// rank0 = (start of the window) + (smaller magnitudes in it) - n_zero. The other values are left
// to TallyRest. No branch on the data: the loop vectorises across positions.
void TallyWindowed(const double* keys, std::size_t lo, std::size_t hi, std::size_t n_zero,
                   unsigned bucket_shift, RankTally* tally) {
  std::uint64_t twice = 0, positives = 0, ties = 0;
  for (std::size_t p = lo; p < hi; ++p) {
    const std::uint64_t key = KeyAt(keys, p), magnitude = key >> 1;
    std::uint64_t less = 0, group = 0;
#pragma GCC unroll 16
    for (std::size_t o = 0; o <= 2 * kWindow; ++o) {  // positions p - kWindow ... p + kWindow
      const std::uint64_t other = MagnitudeAt(keys, p - kWindow + o);
      less += other < magnitude ? 1 : 0;
      group += other == magnitude ? 1 : 0;
    }
    const std::uint64_t bucket = key >> bucket_shift;
    const std::uint64_t inside = KeyAt(keys, p - kWindow - 1) >> bucket_shift != bucket &&
                                         KeyAt(keys, p + kWindow + 1) >> bucket_shift != bucket
                                     ? 1
                                     : 0;
    const std::uint64_t positive = key & inside;
    twice += positive * (2 * (p + less - kWindow - n_zero) + group + 1);
    positives += positive;
    ties += inside * (group * group - 1);
  }
  tally->twice_r_plus += twice;
  tally->positives += positives;
  tally->tie_terms += ties;
}
// The keys[0, count), sorted, the first at rank0 `base`: each group of equal magnitudes [a, b)
// has rank0 base + a.
void TallySortedGroups(const double* keys, std::size_t count, std::uint64_t base,
                       RankTally* tally) {
  for (std::size_t a = 0; a < count;) {
    const std::uint64_t magnitude = MagnitudeAt(keys, a);
    std::uint64_t positives = KeyAt(keys, a) & 1;
    std::size_t b = a + 1;
    for (; b < count && MagnitudeAt(keys, b) == magnitude; ++b) positives += KeyAt(keys, b) & 1;
    const std::uint64_t t = b - a;
    tally->twice_r_plus += positives * (2 * (base + a) + t + 1);
    tally->positives += positives;
    tally->tie_terms += t * t * t - t;
    a = b;
  }
}

// The values of the bucket [begin, end) that TallyWindowed did not rank (it ranked the positions
// in [lo, hi) within kWindow of both ends of the bucket).
void TallyBucketRest(double* keys, std::size_t begin, std::size_t end, std::size_t lo,
                     std::size_t hi, std::size_t n_zero, RankTally* tally) {
  const std::uint64_t base = begin - n_zero;
  if (end - begin >= 2 * kWindow + 2) {  // too wide: none of it was ranked
    if (std::all_of(keys + begin, keys + end, [&](double k) {
          return std::bit_cast<std::uint64_t>(k) >> 1 == MagnitudeAt(keys, begin);
        })) {  // one group (quantised values): no sort
      TallySortedGroups(keys + begin, end - begin, base, tally);
      return;
    }
    std::sort(keys + begin, keys + end, [](double p, double q) {
      return std::bit_cast<std::uint64_t>(p) < std::bit_cast<std::uint64_t>(q);
    });
    TallySortedGroups(keys + begin, end - begin, base, tally);
    return;
  }
  const std::size_t done_lo = std::max(lo, end > kWindow + 1 ? end - kWindow - 1 : 0);
  const std::size_t done_hi = std::min(hi, begin + kWindow + 1);
  for (std::size_t p = begin; p < end; ++p) {
    if (p >= done_lo && p < done_hi) continue;
    const std::uint64_t magnitude = MagnitudeAt(keys, p);
    std::uint64_t less = 0, group = 0;
    for (std::size_t j = begin; j < end; ++j) {
      less += MagnitudeAt(keys, j) < magnitude ? 1 : 0;
      group += MagnitudeAt(keys, j) == magnitude ? 1 : 0;
    }
    AddValue(KeyAt(keys, p), base + less, group, tally);
  }
}

// The buckets that TallyWindowed did not rank completely (ends[k] is the end of bucket k): those
// wider than its window (`wide`, ascending) and those with values near either end of the keys,
// outside [lo, hi) (found from the keys there). Each is tallied once; bucket 0 (zeros) never.
void TallyRest(double* keys, std::size_t n, const std::vector<std::uint32_t>& ends,
               std::vector<std::uint32_t>* wide, std::size_t lo, std::size_t hi, std::size_t n_zero,
               unsigned bucket_shift, RankTally* tally) {
  std::vector<std::uint32_t>& rest = *wide;
  const auto add_buckets_of = [&](std::size_t from, std::size_t to) {
    for (std::size_t p = from; p < to; ++p) {
      rest.push_back(static_cast<std::uint32_t>(KeyAt(keys, p) >> bucket_shift));
    }
  };
  add_buckets_of(n_zero, std::min(lo, n));
  add_buckets_of(std::max(hi, n_zero), n);
  std::sort(rest.begin(), rest.end());
  rest.erase(std::unique(rest.begin(), rest.end()), rest.end());
  for (const std::uint32_t k : rest) {
    if (k != 0) TallyBucketRest(keys, ends[k - 1], ends[k], lo, hi, n_zero, tally);
  }
}

// The keys of d[0, len), len <= kIdBlock (a loop that vectorises, table lookups as gathers).
void BlockKeys(const double* d, std::size_t len, const BucketMap& map, std::uint64_t* block) {
  for (std::size_t i = 0; i < len; ++i) block[i] = map.KeyOf(d[i]);
}

// Scatters the keys of d into `keys` by bucket: on return ends[k] is the end of bucket k (and
// the start of bucket k + 1), and `wide` lists the buckets 1.. of more than kWindow + 1 values.
// With `d_keys` (d's own memory) the keys are written over d on the counting pass, and read back
// for the scatter; otherwise they are computed again. Returns false when one bucket is too full
// for the path to pay; d then holds its values again (RestoreDifferences).
bool ScatterByBucket(std::span<const double> d, double* d_keys, const BucketMap& map,
                     std::vector<std::uint32_t>* ends_out, std::vector<std::uint32_t>* wide,
                     double* keys) {
  std::vector<std::uint32_t>& ends = *ends_out;
  ends.assign(map.buckets + 1, 0);
  wide->clear();
  std::array<std::uint64_t, kIdBlock> block{};
  const unsigned bucket_shift = map.shift + 1;
  const std::size_t n = d.size();
  for (std::size_t i0 = 0; i0 < n; i0 += kIdBlock) {
    const std::size_t len = std::min(kIdBlock, n - i0);
    BlockKeys(d.data() + i0, len, map, block.data());
    for (std::size_t i = 0; i < len; ++i) ++ends[(block[i] >> bucket_shift) + 1];
    if (d_keys != nullptr) std::memcpy(d_keys + i0, block.data(), len * sizeof(double));
  }
  std::uint32_t fullest = 0;  // of buckets 1..: a reduction that vectorises
  for (std::size_t k = 2; k < ends.size(); ++k) fullest = std::max(fullest, ends[k]);
  if (fullest > kWindow + 1) {
    for (std::size_t k = 2; k < ends.size(); ++k) {
      if (ends[k] > kWindow + 1) wide->push_back(static_cast<std::uint32_t>(k - 1));
    }
  }
  for (std::size_t k = 2; k < ends.size(); ++k) ends[k] += ends[k - 1];
  if (fullest > 32 && fullest > n / 64) {  // clustered: sorting pays
    if (d_keys != nullptr) RestoreDifferences(map, std::span<double>(d_keys, n));
    return false;
  }
  for (std::size_t i0 = 0; i0 < n; i0 += kIdBlock) {
    const std::size_t len = std::min(kIdBlock, n - i0);
    const std::uint64_t* src = block.data();
    if (d_keys != nullptr) {
      src = reinterpret_cast<const std::uint64_t*>(d_keys + i0);
    } else {
      BlockKeys(d.data() + i0, len, map, block.data());
    }
    for (std::size_t i = 0; i < len; ++i) {
      keys[ends[src[i] >> bucket_shift]++] = std::bit_cast<double>(src[i]);
    }
  }
  return true;
}

}  // namespace

namespace detail::internal {

bool SumsByBuckets(std::span<const double> d, double* d_keys, const DifferenceScan& scan,
                   ZeroMethod zero_method, std::span<double> scratch,
                   detail::SignedRankSums* sums) {
  const std::size_t n = d.size(), n_zero = scan.n_zero;
  if (n < detail::kSignedRanksMinN || n > detail::kSignedRanksMaxN || n_zero == n) return false;
  if (zero_method == ZeroMethod::kZsplit && n_zero > kMaxZeroGroup) return false;
  PATLAB_CHECK(scratch.size() >= n);
  thread_local BucketMap map;  // 32 KB: not on the stack
  if (!MakeBucketMap(d, scan, &map)) return false;
  thread_local std::vector<std::uint32_t> ends, rest;  // O(buckets), at most 2^17 + 1 each
  double* const keys = scratch.data();
  if (!ScatterByBucket(d, d_keys, map, &ends, &rest, keys)) return false;
  RankTally tally;
  const unsigned bucket_shift = map.shift + 1;
  const std::size_t lo = std::max(n_zero, kWindow + 1), hi = n - kWindow - 1;
  if (lo < hi) TallyWindowed(keys, lo, hi, n_zero, bucket_shift, &tally);
  TallyRest(keys, n, ends, &rest, lo, hi, n_zero, bucket_shift, &tally);
  std::uint64_t tie_terms = tally.tie_terms;
  if (zero_method == ZeroMethod::kZsplit) tie_terms += n_zero * n_zero * n_zero - n_zero;
  if (tie_terms >= kExactTieSum) {  // the sorted walk's rounding would matter
    if (d_keys != nullptr) {
      std::copy(keys, keys + n, d_keys);
      RestoreDifferences(map, std::span<double>(d_keys, n));
    }
    return false;
  }
  // Ranks count the zeros before them unless 'wilcox' dropped the zeros.
  const std::uint64_t m = n - n_zero;
  const std::uint64_t shift = zero_method == ZeroMethod::kWilcox ? 0 : n_zero;
  const std::uint64_t twice_plus = tally.twice_r_plus + 2 * shift * tally.positives;
  const std::uint64_t twice_all = m * (m + 1) + 2 * shift * m;
  sums->r_plus = 0.5 * static_cast<double>(twice_plus);
  sums->r_minus = 0.5 * static_cast<double>(twice_all - twice_plus);
  if (zero_method == ZeroMethod::kZsplit) {
    const auto r_zero = static_cast<double>(n_zero * (n_zero + 1) / 2);
    sums->r_plus += r_zero / 2.0;
    sums->r_minus += r_zero / 2.0;
  }
  sums->tie_sum = static_cast<double>(tie_terms);
  sums->has_ties = tally.tie_terms > 0;
  return true;
}

}  // namespace detail::internal

namespace detail {

bool SignedRankSumsByBuckets(std::span<const double> d, std::size_t n_zero, ZeroMethod zero_method,
                             std::span<double> scratch, SignedRankSums* sums) {
  DifferenceScan scan = ScanDifferences(d);
  PATLAB_CHECK(scan.n_zero == n_zero && scan.largest < kInfinityBits);
  return SumsByBuckets(d, nullptr, scan, zero_method, scratch, sums);
}

}  // namespace detail

}  // namespace patlab::stats
