#include "patlab/stats/sort.h"

#include <array>
#include <bit>
#include <cstdint>
#include <vector>

namespace patlab::stats {

namespace {

constexpr int kDigitBits = 11;
constexpr int kBins = 1 << kDigitBits;
constexpr int kPasses = (64 + kDigitBits - 1) / kDigitBits;  // 6
constexpr uint64_t kSignBit = uint64_t{1} << 63;

// The keys, the scatter buffer and the digit counts of one thread, grown to the largest sample
// seen and then reused: a fresh 100,000-element array costs more in page faults and zeroing
// than the sort itself (perf on stats_bench: 55% of the time in the kernel's page faults and
// memset before this). Only serial code below touches it, so no task can interleave.
struct Scratch {
  std::vector<uint64_t> keys, buffer;
  std::array<std::array<uint32_t, kBins>, kPasses> counts;
};

Scratch& ThreadScratch(size_t n) {
  thread_local Scratch scratch;
  if (scratch.keys.size() < n) {
    scratch.keys.resize(n);
    scratch.buffer.resize(n);
  }
  return scratch;
}

inline uint32_t Digit(uint64_t key, int pass) {
  return static_cast<uint32_t>(key >> (pass * kDigitBits)) & (kBins - 1);
}

// LSD radix sort of the keys key_of(values[i]), 11 bits a pass; the counts of every pass come
// from one read of the values, and passes in which every key has the same digit are skipped.
// Returns the array that holds the sorted keys (s.keys or s.buffer).
template <class KeyOf>
const uint64_t* RadixSort(std::span<const double> values, KeyOf key_of, Scratch& s) {
  const size_t n = values.size();
  uint64_t* src = s.keys.data();
  uint64_t* dst = s.buffer.data();
  for (auto& c : s.counts) c.fill(0);
  for (size_t i = 0; i < n; ++i) {
    const uint64_t k = key_of(std::bit_cast<uint64_t>(values[i]));
    src[i] = k;
    for (int p = 0; p < kPasses; ++p) ++s.counts[p][Digit(k, p)];
  }
  for (int p = 0; p < kPasses; ++p) {
    auto& c = s.counts[p];
    if (c[Digit(src[0], p)] == n) continue;
    uint32_t offset = 0;
    for (uint32_t& bin : c) {
      const uint32_t count = bin;
      bin = offset;
      offset += count;
    }
    for (size_t i = 0; i < n; ++i) {
      const uint64_t k = src[i];
      dst[c[Digit(k, p)]++] = k;
    }
    std::swap(src, dst);
  }
  return src;
}

}  // namespace

void SortAscending(std::span<double> values) {
  const size_t n = values.size();
  if (n < 2) return;
  Scratch& s = ThreadScratch(n);
  // IEEE-754 order as unsigned integers: flip all bits of negatives, the sign bit of the rest.
  const uint64_t* keys = RadixSort(
      values, [](uint64_t u) { return (u & kSignBit) ? ~u : (u | kSignBit); }, s);
  for (size_t i = 0; i < n; ++i) {
    const uint64_t k = keys[i];
    values[i] = std::bit_cast<double>((k & kSignBit) ? (k & ~kSignBit) : ~k);
  }
}

void SortByMagnitude(std::span<double> values) {
  const size_t n = values.size();
  if (n < 2) return;
  Scratch& s = ThreadScratch(n);
  // Key: the 63 magnitude bits shifted up, and the sign inverted into the lowest bit, so that
  // |v| orders first and a negative value precedes a positive one of equal magnitude.
  const uint64_t* keys = RadixSort(
      values, [](uint64_t u) { return ((u & ~kSignBit) << 1) | ((u & kSignBit) ? 0 : 1); }, s);
  for (size_t i = 0; i < n; ++i) {
    const uint64_t k = keys[i];
    values[i] = std::bit_cast<double>((k >> 1) | ((k & 1) ? 0 : kSignBit));
  }
}

}  // namespace patlab::stats
