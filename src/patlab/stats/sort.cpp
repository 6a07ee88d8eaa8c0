#include "patlab/stats/sort.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "patlab/core/error.h"

namespace patlab::stats {

namespace {

constexpr int kDigitBits = 11;
constexpr int kBins = 1 << kDigitBits;
constexpr int kPasses = (64 + kDigitBits - 1) / kDigitBits;  // 6
constexpr uint64_t kSignBit = uint64_t{1} << 63;
constexpr size_t kBucketMinSize = 1024;  // below, the radix sort's fixed costs are small

// The digit counts of one radix sort (O(1) memory: 6 x 2048 counters).
using DigitCounts = std::array<std::array<uint32_t, kBins>, kPasses>;

// The scatter buffer of one thread for the overloads without a caller's scratch, grown to the
// largest sample seen and then reused: a fresh 100,000-element array costs more in page faults
// and zeroing than the sort itself (perf on stats_bench: 55% of the time in the kernel's page
// faults and memset before this). Only serial code below touches it, so no task can interleave.
std::span<double> ThreadScratch(size_t n) {
  thread_local std::vector<double> scratch;
  if (scratch.size() < n) scratch.resize(n);
  return {scratch.data(), n};
}

inline uint32_t Digit(uint64_t key, int pass) {
  return static_cast<uint32_t>(key >> (pass * kDigitBits)) & (kBins - 1);
}

// LSD radix sort of the keys key_of(values[i]), 11 bits a pass, done in the values' own storage
// (the keys replace the values, bit_cast) with `scratch` (at least as long) as the only other
// array; the counts of every pass come from one read of the values, and passes in which every
// key has the same digit are skipped. The sorted keys end in the values' storage (copied back if
// an odd number of passes ran) and are turned back into values by value_of.
template <class KeyOf, class ValueOf>
void RadixSort(std::span<double> values, std::span<double> scratch, KeyOf key_of,
               ValueOf value_of) {
  const size_t n = values.size();
  // Keys are stored as doubles of the same bits (bit_cast); plain copies keep every bit, NaN
  // patterns included.
  double* const home = values.data();
  double* src = home;
  double* dst = scratch.data();
  thread_local DigitCounts counts;
  for (auto& c : counts) c.fill(0);
  for (size_t i = 0; i < n; ++i) {
    const uint64_t k = key_of(std::bit_cast<uint64_t>(src[i]));
    src[i] = std::bit_cast<double>(k);
    for (int p = 0; p < kPasses; ++p) ++counts[p][Digit(k, p)];
  }
  const uint64_t first = std::bit_cast<uint64_t>(src[0]);
  for (int p = 0; p < kPasses; ++p) {
    auto& c = counts[p];
    if (c[Digit(first, p)] == n) continue;
    uint32_t offset = 0;
    for (uint32_t& bin : c) {
      const uint32_t count = bin;
      bin = offset;
      offset += count;
    }
    for (size_t i = 0; i < n; ++i) {
      const double v = src[i];
      dst[c[Digit(std::bit_cast<uint64_t>(v), p)]++] = v;
    }
    std::swap(src, dst);
  }
  if (src != home) std::copy_n(src, n, home);
  for (size_t i = 0; i < n; ++i) home[i] = value_of(std::bit_cast<uint64_t>(home[i]));
}

// Bucket sort for smooth samples: values are scattered into about n / 2 buckets of equal width
// on bucket_value(v), a non-decreasing function of the key order, so that bucket k holds keys
// <= those of bucket k + 1 and equal keys share a bucket; each bucket (a handful of values) is
// then sorted by key. The result is the key order, exactly as the radix sort gives it, in two
// passes over the values instead of six. Returns false (values untouched) when the values span
// no range or a range too wide to scale, and when the buckets are too uneven to pay (then the
// caller sorts by radix).
constexpr std::size_t kMaxBuckets = std::size_t{1} << 17;
constexpr uint32_t kSmallBucket = 32;

template <class KeyOf, class ValueOf>
bool SortByBuckets(std::span<double> values, std::span<double> scratch, KeyOf key_of,
                   ValueOf bucket_value) {
  const size_t n = values.size();
  double lo = bucket_value(values[0]), hi = lo;
  for (const double v : values) {
    const double b = bucket_value(v);
    lo = b < lo ? b : lo;
    hi = b > hi ? b : hi;
  }
  const size_t buckets = std::clamp<size_t>(n / 2, 1, kMaxBuckets);
  const double scale = static_cast<double>(buckets) / (hi - lo);
  if (!(hi > lo) || !std::isfinite(scale) || !std::isfinite(hi - lo)) return false;
  const auto bucket_of = [lo, scale, last = static_cast<int64_t>(buckets) - 1](double b) {
    return static_cast<uint32_t>(std::min(static_cast<int64_t>((b - lo) * scale), last));
  };
  thread_local std::vector<uint32_t> bucket_start;  // O(buckets), at most kMaxBuckets + 1
  bucket_start.assign(buckets + 1, 0);
  uint32_t* start = bucket_start.data();
  for (const double v : values) ++start[bucket_of(bucket_value(v)) + 1];
  uint32_t largest = 0;
  for (size_t k = 1; k <= buckets; ++k) {
    largest = std::max(largest, start[k]);
    start[k] += start[k - 1];
  }
  if (largest > kSmallBucket && largest > n / 64) return false;  // clustered: radix pays
  double* out = scratch.data();
  for (const double v : values) out[start[bucket_of(bucket_value(v))]++] = v;
  // start[k] is now the end of bucket k, and bucket k begins at start[k - 1] (0 for k = 0).
  uint32_t begin = 0;
  for (size_t k = 0; k < buckets; ++k) {
    const uint32_t end = start[k];
    if (end - begin > 16) {
      std::sort(out + begin, out + end, [&](double p, double q) { return key_of(p) < key_of(q); });
    } else {
      for (uint32_t i = begin + 1; i < end; ++i) {
        const double value = out[i];
        const uint64_t key = key_of(value);
        uint32_t j = i;
        for (; j > begin && key_of(out[j - 1]) > key; --j) out[j] = out[j - 1];
        out[j] = value;
      }
    }
    begin = end;
  }
  std::copy_n(out, n, values.data());
  return true;
}

inline uint64_t AscendingKey(double v) {
  const uint64_t u = std::bit_cast<uint64_t>(v);
  return (u & kSignBit) ? ~u : (u | kSignBit);
}
inline uint64_t MagnitudeKey(double v) {
  const uint64_t u = std::bit_cast<uint64_t>(v);
  return ((u & ~kSignBit) << 1) | ((u & kSignBit) ? 0 : 1);
}

}  // namespace

void SortAscending(std::span<double> values, std::span<double> scratch) {
  const size_t n = values.size();
  if (n < 2) return;
  PATLAB_CHECK(scratch.size() >= n);
  scratch = scratch.first(n);
  if (n >= kBucketMinSize &&
      SortByBuckets(
          values, scratch, [](double v) { return AscendingKey(v); }, [](double v) { return v; })) {
    return;
  }
  // IEEE-754 order as unsigned integers: flip all bits of negatives, the sign bit of the rest.
  RadixSort(
      values, scratch, [](uint64_t u) { return (u & kSignBit) ? ~u : (u | kSignBit); },
      [](uint64_t k) { return std::bit_cast<double>((k & kSignBit) ? (k & ~kSignBit) : ~k); });
}

void SortByMagnitude(std::span<double> values, std::span<double> scratch) {
  const size_t n = values.size();
  if (n < 2) return;
  PATLAB_CHECK(scratch.size() >= n);
  scratch = scratch.first(n);
  if (n >= kBucketMinSize && SortByBuckets(
                                 values, scratch, [](double v) { return MagnitudeKey(v); },
                                 [](double v) { return std::fabs(v); })) {
    return;
  }
  // Key: the 63 magnitude bits shifted up, and the sign inverted into the lowest bit, so that
  // |v| orders first and a negative value precedes a positive one of equal magnitude.
  RadixSort(
      values, scratch, [](uint64_t u) { return ((u & ~kSignBit) << 1) | ((u & kSignBit) ? 0 : 1); },
      [](uint64_t k) { return std::bit_cast<double>((k >> 1) | ((k & 1) ? 0 : kSignBit)); });
}

void SortAscending(std::span<double> values) {
  if (values.size() < 2) return;
  SortAscending(values, ThreadScratch(values.size()));
}

void SortByMagnitude(std::span<double> values) {
  if (values.size() < 2) return;
  SortByMagnitude(values, ThreadScratch(values.size()));
}

}  // namespace patlab::stats
