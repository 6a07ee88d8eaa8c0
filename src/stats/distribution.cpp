#include "stats/distribution.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "stats/summary.h"

// Bin edges and indices must be numpy's bit for bit: lo + k * step rounded twice, never fused
// into one fma (which -march=native would otherwise allow).
#pragma GCC optimize("fp-contract=off")

namespace patlab::stats {

Histogram MakeHistogram(std::span<const double> x, std::size_t bins, double lo, double hi) {
  if (bins == 0) throw InputError("a histogram needs at least 1 bin, got 0");
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo <= hi)) {
    throw InputError("histogram range [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "] is invalid; expected finite lo <= hi");
  }
  detail::RequireFinite(x, "sample");
  if (lo == hi) lo -= 0.5, hi += 0.5;
  Histogram h;
  h.edges.resize(bins + 1);
  // numpy.linspace: lo + k * step, last edge exactly hi.
  const double step = (hi - lo) / static_cast<double>(bins);
  for (std::size_t k = 0; k <= bins; ++k) h.edges[k] = lo + static_cast<double>(k) * step;
  h.edges[bins] = hi;
  h.counts.assign(bins, 0);
  const double norm = static_cast<double>(bins) / (hi - lo);
  for (double v : x) {
    if (v < lo || v > hi) continue;
    // numpy's equal-width fast path, then the same one-step corrections against the edges.
    auto k = static_cast<std::size_t>((v - lo) * norm);
    if (k >= bins) k = bins - 1;
    if (v < h.edges[k])
      --k;
    else if (v >= h.edges[k + 1] && k != bins - 1)
      ++k;
    ++h.counts[k];
  }
  return h;
}

Histogram MakeHistogram(std::span<const double> x, std::size_t bins) {
  if (x.empty()) throw InputError("a histogram of an empty sample needs an explicit range");
  detail::RequireFinite(x, "sample");
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  return MakeHistogram(x, bins, *lo, *hi);
}

EcdfTable MakeEcdf(std::span<const double> x) {
  if (x.empty()) throw InputError("the empirical CDF needs at least one value, got none");
  detail::RequireFinite(x, "sample");
  std::vector<double> s(x.begin(), x.end());
  std::sort(s.begin(), s.end());
  EcdfTable t;
  const double n = static_cast<double>(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i + 1 < s.size() && s[i + 1] == s[i]) continue;
    t.values.push_back(s[i]);
    t.cumulative_fraction.push_back(static_cast<double>(i + 1) / n);
  }
  return t;
}

}  // namespace patlab::stats
