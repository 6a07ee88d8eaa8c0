// Tables describing a sample's distribution: histograms (paper Fig. 2) and empirical CDFs
// (paper Fig. 3, "cumulative distributions of absolute error").
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace patlab::stats {

struct Histogram {
  std::vector<double> edges;        // bins + 1 increasing edges, data units
  std::vector<std::size_t> counts;  // bins counts; values outside [edges.front(), edges.back()]
                                    // are not counted
};

// Equal-width histogram on [lo, hi] with numpy.histogram's rules: bins are half-open [a, b)
// except the last, which includes hi; lo == hi widens the range to [lo - 0.5, hi + 0.5].
// Needs bins >= 1, lo <= hi finite, finite data (InputError otherwise).
Histogram MakeHistogram(std::span<const double> x, std::size_t bins, double lo, double hi);
// Range [min(x), max(x)]; x must be non-empty.
Histogram MakeHistogram(std::span<const double> x, std::size_t bins);

// Empirical CDF as a step table: the distinct sorted values and F(v) = #{x <= v} / n.
struct EcdfTable {
  std::vector<double> values;
  std::vector<double> cumulative_fraction;
};
// x must be non-empty and finite.
EcdfTable MakeEcdf(std::span<const double> x);

}  // namespace patlab::stats
