#include "patlab/stats/intervals.h"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>

#include "patlab/core/error.h"

namespace patlab::stats {

namespace {
// The two-sided 95% normal quantile, z_{0.975}.
constexpr double kZ95 = 1.959963984540054;
}  // namespace

Proportion WilsonInterval(int64_t count, int64_t total) {
  PATLAB_CHECK(count >= 0 && count <= total);
  Proportion p;
  p.count = count;
  p.total = total;
  if (total == 0) {
    p.rate = p.lower = p.upper = std::nan("");
    return p;
  }
  const double n = static_cast<double>(total);
  const double rate = static_cast<double>(count) / n;
  const double z2 = kZ95 * kZ95;
  const double denominator = 1.0 + z2 / n;
  const double centre = (rate + z2 / (2.0 * n)) / denominator;
  const double half = kZ95 / denominator * std::sqrt(rate * (1.0 - rate) / n + z2 / (4.0 * n * n));
  p.rate = rate;
  // At k = 0 (k = n) the lower (upper) end is 0 (1) exactly; rounding would leave ~1e-17.
  p.lower = count == 0 ? 0.0 : std::max(0.0, centre - half);
  p.upper = count == total ? 1.0 : std::min(1.0, centre + half);
  return p;
}

PoissonRate GarwoodInterval(int64_t count, int64_t frames) {
  PATLAB_CHECK(count >= 0 && frames > 0);
  PoissonRate r;
  r.count = count;
  r.frames = frames;
  const double k = static_cast<double>(count), f = static_cast<double>(frames);
  r.rate = k / f;
  r.lower = count == 0
                ? 0.0
                : boost::math::quantile(boost::math::chi_squared(2.0 * k), 0.025) / (2.0 * f);
  r.upper = boost::math::quantile(boost::math::chi_squared(2.0 * k + 2.0), 0.975) / (2.0 * f);
  return r;
}

}  // namespace patlab::stats
