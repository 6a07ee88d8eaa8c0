// Sorting for the rank statistics. Samples of 1024 values or more that spread smoothly over their
// range are bucket-sorted: scattered into ~n / 2 equal-width buckets (two passes) and each bucket
// sorted by key; the rest (too few values, +-infinity, no range, or buckets too uneven) go through
// an LSD radix sort on order-preserving 64-bit keys (11-bit digits, constant digits skipped).
// Both give exactly the order described below, the order std::sort gives with the same keys; a
// 100,000 sample sorts several times faster than with std::sort.
#pragma once

#include <span>

namespace patlab::stats {

// Sorts finite values ascending, exactly as std::sort would (-0.0 and +0.0 compare equal and end
// up adjacent; -0.0 first).
void SortAscending(std::span<double> values);

// Sorts finite values by absolute value ascending (for a tie in |v|, negative values first),
// keeping each value's sign: the order the Wilcoxon signed-rank test ranks in.
void SortByMagnitude(std::span<double> values);

// The same with the caller's scratch (at least values.size() long; its contents are
// overwritten): the sorts then use no memory that grows with the sample, only O(1) counters and
// at most 2^17 bucket starts. For callers that have a dead array of the sample's size at hand
// (the runner's sample arrays once their last test is done).
void SortAscending(std::span<double> values, std::span<double> scratch);
void SortByMagnitude(std::span<double> values, std::span<double> scratch);

}  // namespace patlab::stats
