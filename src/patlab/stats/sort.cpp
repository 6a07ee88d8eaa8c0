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

// LSD radix sort of 64-bit keys, 11 bits a pass; passes in which every key has the same digit
// are skipped.
void RadixSort(std::vector<uint64_t>& keys) {
  const size_t n = keys.size();
  if (n < 2) return;
  std::vector<std::array<uint32_t, kBins>> counts(kPasses);
  for (auto& c : counts) c.fill(0);
  for (uint64_t k : keys) {
    for (int p = 0; p < kPasses; ++p) ++counts[p][(k >> (p * kDigitBits)) & (kBins - 1)];
  }
  std::vector<uint64_t> buffer(n);
  for (int p = 0; p < kPasses; ++p) {
    auto& c = counts[p];
    if (c[(keys[0] >> (p * kDigitBits)) & (kBins - 1)] == n) continue;
    uint32_t offset = 0;
    for (uint32_t& bin : c) {
      const uint32_t count = bin;
      bin = offset;
      offset += count;
    }
    for (uint64_t k : keys) buffer[c[(k >> (p * kDigitBits)) & (kBins - 1)]++] = k;
    keys.swap(buffer);
  }
}

constexpr uint64_t kSignBit = uint64_t{1} << 63;

}  // namespace

void SortAscending(std::span<double> values) {
  // IEEE-754 order as unsigned integers: flip all bits of negatives, the sign bit of the rest.
  std::vector<uint64_t> keys(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    const uint64_t u = std::bit_cast<uint64_t>(values[i]);
    keys[i] = (u & kSignBit) ? ~u : (u | kSignBit);
  }
  RadixSort(keys);
  for (size_t i = 0; i < values.size(); ++i) {
    const uint64_t k = keys[i];
    values[i] = std::bit_cast<double>((k & kSignBit) ? (k & ~kSignBit) : ~k);
  }
}

void SortByMagnitude(std::span<double> values) {
  // Key: the 63 magnitude bits shifted up, and the sign inverted into the lowest bit, so that
  // |v| orders first and a negative value precedes a positive one of equal magnitude.
  std::vector<uint64_t> keys(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    const uint64_t u = std::bit_cast<uint64_t>(values[i]);
    keys[i] = ((u & ~kSignBit) << 1) | ((u & kSignBit) ? 0 : 1);
  }
  RadixSort(keys);
  for (size_t i = 0; i < values.size(); ++i) {
    const uint64_t k = keys[i];
    values[i] = std::bit_cast<double>((k >> 1) | ((k & 1) ? 0 : kSignBit));
  }
}

}  // namespace patlab::stats
