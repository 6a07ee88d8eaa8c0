// Internals of the signed-rank test shared by its source files: wilcoxon.cpp (the test, its
// p-values and the ranking by sorting) and wilcoxon_buckets.cpp (the rank sums by buckets,
// without a full sort). Not part of the public API: include wilcoxon.h instead.
#pragma once

#include <bit>
#include <cstdint>
#include <span>

#include "patlab/stats/wilcoxon.h"

namespace patlab::stats::detail::internal {

inline constexpr std::uint64_t kSignBit = std::uint64_t{1} << 63;
// The bits of +infinity: a magnitude's bits are at least this iff it is not finite.
inline constexpr std::uint64_t kInfinityBits = std::uint64_t{0x7ff} << 52;

// What one pass over the differences finds: the zeros, and the bits of the largest |d| and of the
// smallest non-zero |d| (the bits of non-negative doubles order as the values do).
struct DifferenceScan {
  std::size_t n_zero = 0;
  std::uint64_t largest = 0;
  std::uint64_t smallest = 0;  // 0 when every difference is zero
};

// One loop without an early exit, written (ternaries, no std::max on references) so that the
// compiler vectorises it: m - 1 wraps a zero magnitude round to the largest integer, so the
// minimum skips the zeros.
inline DifferenceScan ScanDifferences(std::span<const double> d) {
  std::uint64_t largest = 0, smallest_less_one = ~std::uint64_t{0}, zeros = 0;
  for (const double v : d) {
    const std::uint64_t m = std::bit_cast<std::uint64_t>(v) & ~kSignBit;
    largest = m > largest ? m : largest;
    smallest_less_one = m - 1 < smallest_less_one ? m - 1 : smallest_less_one;
    zeros += m == 0 ? 1 : 0;
  }
  return {zeros, largest, smallest_less_one + 1};
}

// The sums without sorting (detail::SignedRankSumsByBuckets) given the scan of d; with d_keys
// (d's memory, writable) d may be overwritten while the path runs, and holds its values again
// when it returns false (definition in wilcoxon_buckets.cpp).
bool SumsByBuckets(std::span<const double> d, double* d_keys, const DifferenceScan& scan,
                   ZeroMethod zero_method, std::span<double> scratch, detail::SignedRankSums* sums);

}  // namespace patlab::stats::detail::internal
