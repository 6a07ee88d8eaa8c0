#include "patlab/stats/effective_n.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "patlab/core/error.h"

namespace patlab::stats {

EffectiveSize VarianceEffectiveSize(std::span<const std::span<const double>> segments, int max_lag,
                                    int min_lags) {
  if (max_lag < 1) {
    throw InputError("effective sample size: max_lag is " + std::to_string(max_lag) +
                     "; expected an integer >= 1");
  }
  EffectiveSize out;
  std::vector<std::vector<double>> dev;
  double m2 = 0.0;
  std::size_t shortest = std::numeric_limits<std::size_t>::max();
  for (const std::span<const double> s : segments) {
    detail::RequireFinite(s, "effective sample size");
    if (s.size() < 2) continue;
    double mean = 0.0;
    for (double v : s) mean += v;
    mean /= static_cast<double>(s.size());
    std::vector<double> d(s.size());
    for (std::size_t t = 0; t < s.size(); ++t) {
      d[t] = s[t] - mean;
      m2 += d[t] * d[t];
    }
    out.n += static_cast<double>(s.size());
    out.dof += static_cast<double>(s.size()) - 1.0;
    shortest = std::min(shortest, s.size());
    dev.push_back(std::move(d));
  }
  out.dof_eff = out.dof;
  out.lag1 = std::nan("");
  if (dev.empty() || m2 <= 0.0) return out;
  const double band = 2.0 / std::sqrt(out.n);
  const int cap =
      static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(max_lag), shortest - 1));
  double sum = 0.0;
  bool inside_band = false;
  for (int k = 1; k <= cap; ++k) {
    double c = 0.0;
    for (const std::vector<double>& d : dev) {
      for (std::size_t t = 0; t + static_cast<std::size_t>(k) < d.size(); ++t) {
        c += d[t] * d[t + static_cast<std::size_t>(k)];
      }
    }
    const double r = c / m2;
    if (k == 1) out.lag1 = r;
    inside_band = inside_band || std::abs(r) < band;
    if (inside_band && k > min_lags) break;
    // A lag summed only because of min_lags is mostly noise: its r_k^2 carries about 1 / n of
    // it, which is taken off (else 2R lags of a short series would inflate tau by 4R / n).
    sum += inside_band ? r * r - 1.0 / out.n : r * r;
    out.lags = k;
  }
  out.tau = std::max(1.0, 1.0 + 2.0 * sum);
  out.dof_eff = out.dof / out.tau;
  return out;
}

StdWithCi StdIntervalEffective(double std, const EffectiveSize& size, double level) {
  return StdConfidenceInterval(std, size.dof_eff, level);
}

}  // namespace patlab::stats
