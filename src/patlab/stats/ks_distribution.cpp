// The distribution of the two-sample KS statistic: the asymptotic Kolmogorov survival function
// and the exact p-values of samples of equal and of unequal size (KsTwoSample's p-value).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/core/portable_math.h"
#include "patlab/stats/ks.h"

namespace patlab::stats {

double KolmogorovSurvival(double x) {
  if (!(x > 0.0)) return 1.0;
  if (x < 1.0) {
    // Small x: P(K <= x) = sqrt(2 pi)/x sum_{k>=1} exp(-(2k-1)^2 pi^2 / (8 x^2)) converges fast.
    const double w = -std::numbers::pi * std::numbers::pi / (8.0 * x * x);
    double sum = 0.0;
    for (int k = 1; k < 100; ++k) {
      const double term = pmath::Exp(w * (2 * k - 1) * (2 * k - 1));
      sum += term;
      if (term <= 1e-18 * sum) break;
    }
    return std::clamp(1.0 - std::sqrt(2.0 * std::numbers::pi) / x * sum, 0.0, 1.0);
  }
  // Large x: P(K > x) = 2 sum_{k>=1} (-1)^(k-1) exp(-2 k^2 x^2), no cancellation for x >= 1.
  double sum = 0.0;
  for (int k = 1; k < 100; ++k) {
    const double term = pmath::Exp(-2.0 * k * k * x * x);
    sum += (k % 2 == 1) ? term : -term;
    if (term <= 1e-18 * sum) break;
  }
  return std::clamp(2.0 * sum, 0.0, 1.0);
}

double KsExactEqualTwoSided(std::int64_t n, std::int64_t h) {
  PATLAB_CHECK(n > 0 && h >= 0 && h <= n);
  if (h == 0) return 1.0;
  // P = 2 A0 (1 - A1 (1 - A2 (1 - ...))), A_k = C(2n, n-(k+1)h)/C(2n, n-kh) in product form
  // (scipy _compute_prob_outside_square); avoids the cancellation of the plain alternating sum.
  double p = 0.0;
  for (std::int64_t k = n / h; k >= 0; --k) {
    double p1 = 1.0;
    for (std::int64_t j = 0; j < h; ++j) {
      p1 = static_cast<double>(n - k * h - j) * p1 / static_cast<double>(n + k * h + j + 1);
    }
    p = p1 * (1.0 - p);
  }
  return std::clamp(2.0 * p, 0.0, 1.0);
}

double KsExactEqualOneSided(std::int64_t n, std::int64_t h) {
  PATLAB_CHECK(n > 0 && h >= 0 && h <= n);
  double p = 1.0;
  for (std::int64_t j = 0; j < h; ++j) {
    p *= static_cast<double>(n - j) / static_cast<double>(n + j + 1);
  }
  return std::clamp(p, 0.0, 1.0);
}

double KsExactLattice(std::int64_t n1, std::int64_t n2, std::int64_t h, bool two_sided) {
  PATLAB_CHECK(n1 > 0 && n2 > 0 && h >= 0);
  if (h == 0) return 1.0;
  const std::int64_t g = std::gcd(n1, n2);
  const std::int64_t n1g = n1 / g;
  const std::int64_t n2g = n2 / g;
  // A path takes i steps of sample 1 and j of sample 2; there F1 - F2 = (i n2g - j n1g) / lcm.
  // b[j] holds B(i, j) = P(a uniformly random path to (i, j) has touched |F1 - F2| >= h/lcm)
  // (or F1 - F2 >= h/lcm one-sided). B = 1 on the boundary, else
  // B(i, j) = (i B(i-1, j) + j B(i, j-1)) / (i + j) because a fraction i/(i+j) of the paths to
  // (i, j) arrive from (i-1, j) (Viehmann 2021, eq. 5).
  auto outside = [&](std::int64_t i, std::int64_t j) {
    const std::int64_t diff = i * n2g - j * n1g;
    return two_sided ? (diff >= h || -diff >= h) : diff >= h;
  };
  std::vector<double> b(static_cast<std::size_t>(n2) + 1);
  b[0] = 0.0;
  for (std::int64_t j = 1; j <= n2; ++j) b[j] = outside(0, j) ? 1.0 : b[j - 1];
  for (std::int64_t i = 1; i <= n1; ++i) {
    const double di = static_cast<double>(i);
    b[0] = outside(i, 0) ? 1.0 : b[0];
    for (std::int64_t j = 1; j <= n2; ++j) {
      if (outside(i, j)) {
        b[j] = 1.0;
      } else {
        const double dj = static_cast<double>(j);
        b[j] = (di * b[j] + dj * b[j - 1]) / (di + dj);
      }
    }
  }
  return std::clamp(b[n2], 0.0, 1.0);
}

}  // namespace patlab::stats
