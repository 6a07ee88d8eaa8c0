// Internals of the summaries shared by their source files: summary.cpp (means, stds, their
// intervals, the moments of samples) and summary_planar.cpp (the planar moments). Not part of the
// public API: include summary.h instead.
#pragma once

#include <cstddef>
#include <span>

namespace patlab::stats::detail {

// InputError naming `what` when x has fewer than min_n values.
void RequireCount(std::span<const double> x, std::size_t min_n, const char* what);

}  // namespace patlab::stats::detail
