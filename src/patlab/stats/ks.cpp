#include "patlab/stats/ks.h"

#include "patlab/stats/sort.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/stats/summary.h"

namespace patlab::stats {

double KolmogorovSurvival(double x) {
  if (!(x > 0.0)) return 1.0;
  if (x < 1.0) {
    // Small x: P(K <= x) = sqrt(2 pi)/x sum_{k>=1} exp(-(2k-1)^2 pi^2 / (8 x^2)) converges fast.
    const double w = -std::numbers::pi * std::numbers::pi / (8.0 * x * x);
    double sum = 0.0;
    for (int k = 1; k < 100; ++k) {
      const double term = std::exp(w * (2 * k - 1) * (2 * k - 1));
      sum += term;
      if (term <= 1e-18 * sum) break;
    }
    return std::clamp(1.0 - std::sqrt(2.0 * std::numbers::pi) / x * sum, 0.0, 1.0);
  }
  // Large x: P(K > x) = 2 sum_{k>=1} (-1)^(k-1) exp(-2 k^2 x^2), no cancellation for x >= 1.
  double sum = 0.0;
  for (int k = 1; k < 100; ++k) {
    const double term = std::exp(-2.0 * k * k * x * x);
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

namespace {

// The extremes of F1 - F2 over the merged order, with a sample value where each is first reached.
struct EcdfExtremes {
  double max_diff = -1.0, min_diff = 1.0;
  double max_loc = 0.0, min_loc = 0.0;
};

// The two samples sorted into this thread's buffers, each followed by a +infinity sentinel (the
// samples are finite). The buffers grow to the largest sample seen and are then reused: fresh
// 100,000-element arrays cost more in page faults than the sorts. Only serial code uses them.
struct SortedPair {
  std::vector<double> a, b;
};
SortedPair& SortCopies(std::span<const double> x, std::span<const double> y) {
  thread_local SortedPair pair;
  if (pair.a.size() < x.size() + 1) pair.a.resize(x.size() + 1);
  if (pair.b.size() < y.size() + 1) pair.b.resize(y.size() + 1);
  std::copy(x.begin(), x.end(), pair.a.begin());
  std::copy(y.begin(), y.end(), pair.b.begin());
  SortAscending(std::span<double>(pair.a.data(), x.size()));
  SortAscending(std::span<double>(pair.b.data(), y.size()));
  pair.a[x.size()] = pair.b[y.size()] = std::numeric_limits<double>::infinity();
  return pair;
}

// Walks the merged order and compares the ECDFs only after every copy of a tied value, as scipy
// does with searchsorted(side=right). Each step consumes the smaller head value from one or both
// samples without a branch on which (the branch mispredicted every other element); a step ends a
// group of equal values when neither head still equals it, and only then is F1 - F2 compared.
// The group's value is taken at its first step, as the element-at-a-time walk would.
EcdfExtremes CompareEcdfs(std::span<const double> x, std::span<const double> y) {
  const SortedPair& sorted = SortCopies(x, y);
  const double* a = sorted.a.data();
  const double* b = sorted.b.data();
  const std::size_t n1 = x.size(), n2 = y.size();
  const double dn1 = static_cast<double>(n1), dn2 = static_cast<double>(n2);
  EcdfExtremes e;
  std::size_t i = 0, j = 0;
  double group_v = 0.0;
  bool group_start = true;
  while (i < n1 || j < n2) {
    const double ai = a[i], bj = b[j];
    const double v = ai <= bj ? ai : bj;
    i += ai == v ? 1 : 0;
    j += bj == v ? 1 : 0;
    group_v = group_start ? v : group_v;
    group_start = a[i] != v && b[j] != v;
    if (!group_start) continue;
    // Same operations as scipy: searchsorted(...)/n1 - searchsorted(...)/n2.
    const double diff = static_cast<double>(i) / dn1 - static_cast<double>(j) / dn2;
    if (diff > e.max_diff) e.max_diff = diff, e.max_loc = group_v;
    if (diff < e.min_diff) e.min_diff = diff, e.min_loc = group_v;
  }
  return e;
}

}  // namespace

KsResult KsTwoSample(std::span<const double> x, std::span<const double> y,
                     const KsOptions& options) {
  if (x.empty() || y.empty()) {
    throw InputError("the KS test needs two non-empty samples, got " + std::to_string(x.size()) +
                     " and " + std::to_string(y.size()) + " values");
  }
  detail::RequireFinite(x, "sample 1");
  detail::RequireFinite(y, "sample 2");
  const std::size_t n1 = x.size();
  const std::size_t n2 = y.size();
  const EcdfExtremes e = CompareEcdfs(x, y);
  const double dn1 = static_cast<double>(n1);
  const double dn2 = static_cast<double>(n2);
  const double max_diff = e.max_diff, min_diff = e.min_diff;
  const double max_loc = e.max_loc, min_loc = e.min_loc;
  const double min_s = std::clamp(-min_diff, 0.0, 1.0);

  KsResult result;
  result.n1 = n1;
  result.n2 = n2;
  const Alternative alt = options.alternative;
  if (alt == Alternative::kLess || (alt == Alternative::kTwoSided && min_s > max_diff)) {
    result.d = min_s, result.sign = -1, result.location = min_loc;
  } else {
    result.d = max_diff, result.sign = 1, result.location = max_loc;
  }

  KsMethod method = options.method;
  if (method == KsMethod::kAuto) {
    method = std::max(n1, n2) <= kKsMaxAutoExactN ? KsMethod::kExact : KsMethod::kAsymptotic;
  }
  const std::int64_t g = std::gcd(static_cast<std::int64_t>(n1), static_cast<std::int64_t>(n2));
  if (method == KsMethod::kExact) {
    const std::int64_t lcm = static_cast<std::int64_t>(n1) / g * static_cast<std::int64_t>(n2);
    const auto h = static_cast<std::int64_t>(std::nearbyint(result.d * static_cast<double>(lcm)));
    result.d = static_cast<double>(h) / static_cast<double>(lcm);
    const bool two_sided = alt == Alternative::kTwoSided;
    if (n1 == n2) {
      const auto n = static_cast<std::int64_t>(n1);
      result.p_value = two_sided ? KsExactEqualTwoSided(n, h) : KsExactEqualOneSided(n, h);
    } else if (static_cast<std::uint64_t>(n1) * n2 <= kKsMaxExactLatticeSteps) {
      result.p_value = KsExactLattice(static_cast<std::int64_t>(n1), static_cast<std::int64_t>(n2),
                                      h, two_sided);
    } else {
      method = KsMethod::kAsymptotic;
    }
  }
  if (method == KsMethod::kAsymptotic) {
    const double m = std::max(dn1, dn2);
    const double n = std::min(dn1, dn2);
    const double en = m * n / (m + n);
    const double z = std::sqrt(en) * result.d;
    if (alt == Alternative::kTwoSided) {
      result.p_value = KolmogorovSurvival(z);
    } else {
      // Hodges (1958) eq. 5.3, as scipy; m is the larger sample.
      result.p_value =
          std::exp(-2.0 * z * z - 2.0 * z * (m + 2.0 * n) / std::sqrt(m * n * (m + n)) / 3.0);
    }
  }
  result.method_used = method;
  result.p_value = std::clamp(result.p_value, 0.0, 1.0);
  result.d_scaled = std::sqrt(dn1 * dn2 / (dn1 + dn2)) * result.d;
  return result;
}

}  // namespace patlab::stats
