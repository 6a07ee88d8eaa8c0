#include "patlab/stats/ks.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "patlab/core/error.h"
#include "patlab/core/portable_math.h"
#include "patlab/stats/ks_internal.h"
#include "patlab/stats/sort.h"
#include "patlab/stats/summary.h"

namespace patlab::stats {

namespace detail {

using internal::Buffers;
using internal::ExtremesOfSameSamples;
using internal::OrderKey;
using internal::SameSamples;
using internal::SortSmall;
using internal::ThreadBuffers;
using internal::WalkSorted;

namespace internal {

// Walks the merged order of a[0, n1) and b[0, n2), both sorted and followed by a +infinity
// sentinel, whose first elements are elements i0 and j0 of the whole samples, and compares the
// ECDFs only after every copy of a tied value, as scipy does with searchsorted(side=right). Each
// step consumes the smaller head value from one or both samples without a branch on which (that
// branch mispredicted every other element); a step ends a group of equal values when neither
// head still equals it, and only then is F1 - F2 compared, with the group's value taken at its
// first step, as an element-at-a-time walk would.
void WalkSorted(const double* a, std::size_t n1, const double* b, std::size_t n2, std::size_t i0,
                std::size_t j0, double dn1, double dn2, EcdfExtremes* e) {
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
    const double diff = static_cast<double>(i0 + i) / dn1 - static_cast<double>(j0 + j) / dn2;
    if (diff > e->max_diff) e->max_diff = diff, e->max_loc = group_v;
    if (diff < e->min_diff) e->min_diff = diff, e->min_loc = group_v;
  }
}

}  // namespace internal

namespace {

// Copies [first, last) into out followed by a +infinity sentinel, sorted in SortAscending's order.
void SortedWithSentinel(const double* first, const double* last, std::vector<double>* out) {
  out->assign(first, last);
  std::sort(out->begin(), out->end(), [](double p, double q) { return OrderKey(p) < OrderKey(q); });
  out->push_back(std::numeric_limits<double>::infinity());
}

}  // namespace

namespace internal {

// Sorts v[0, n) in SortAscending's order: insertion sort for the few values of a bucket,
// std::sort beyond.
void SortSmall(double* v, std::size_t n) {
  if (n > 16) {
    std::sort(v, v + n, [](double p, double q) { return OrderKey(p) < OrderKey(q); });
    return;
  }
  for (std::size_t i = 1; i < n; ++i) {
    const double value = v[i];
    const uint64_t key = OrderKey(value);
    std::size_t k = i;
    for (; k > 0 && OrderKey(v[k - 1]) > key; --k) v[k] = v[k - 1];
    v[k] = value;
  }
}

Buffers& ThreadBuffers() {
  thread_local Buffers buffers;
  return buffers;
}

}  // namespace internal

namespace internal {

// Samples that are the same values index by index (e.g. two estimators that agree exactly) have
// F1 = F2 after every group: the walk sees diff = i / n - i / n = 0 at every group end, and keeps
// the first, whose value is the smallest in SortAscending's order.
bool SameSamples(std::span<const double> x, std::span<const double> y) {
  return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
}
namespace {
// The extremes of samples equal index by index, from the smallest OrderKey of their values: the
// ECDFs are equal at every group end, first at the smallest value.
EcdfExtremes SameExtremesAt(uint64_t smallest) {
  const double loc = std::bit_cast<double>(
      (smallest & (uint64_t{1} << 63)) ? (smallest & ~(uint64_t{1} << 63)) : ~smallest);
  return EcdfExtremes{0.0, 0.0, loc, loc};
}
}  // namespace
EcdfExtremes ExtremesOfSameSamples(std::span<const double> x) {
  uint64_t smallest = OrderKey(x[0]);
  for (const double v : x) smallest = std::min(smallest, OrderKey(v));
  return SameExtremesAt(smallest);
}
bool ExtremesIfSameSamples(std::span<const double> x, std::span<const double> y, EcdfExtremes* e) {
  if (x.size() != y.size() || x.empty()) return false;
  constexpr std::size_t kBlock = 1024;  // 8 KB of each sample
  constexpr double kMax = std::numeric_limits<double>::max();
  uint64_t smallest = OrderKey(x[0]);
  unsigned bad = 0;
  for (std::size_t first = 0; first < x.size(); first += kBlock) {
    const std::size_t n = std::min(kBlock, x.size() - first);
    const double* v = x.data() + first;
    if (x.data() != y.data() && std::memcmp(v, y.data() + first, n * sizeof(double)) != 0) {
      return false;
    }
    for (std::size_t i = 0; i < n; ++i) {  // no early exit: a loop that vectorises
      bad |= std::fabs(v[i]) <= kMax ? 0U : 1U;
      smallest = std::min(smallest, OrderKey(v[i]));
    }
  }
  if (bad != 0) RequireFinite(x, "sample 1");  // throws, naming the first non-finite value
  *e = SameExtremesAt(smallest);
  return true;
}

}  // namespace internal

EcdfExtremes EcdfExtremesBySorting(std::span<const double> x, std::span<const double> y) {
  Buffers& s = ThreadBuffers();
  SortedWithSentinel(x.data(), x.data() + x.size(), &s.a);
  SortedWithSentinel(y.data(), y.data() + y.size(), &s.b);
  EcdfExtremes e;
  WalkSorted(s.a.data(), x.size(), s.b.data(), y.size(), 0, 0, static_cast<double>(x.size()),
             static_cast<double>(y.size()), &e);
  return e;
}

}  // namespace detail

namespace {

// Samples this large go through the buckets (two passes and a few small sorts); smaller ones
// are sorted whole.
constexpr std::size_t kKsBucketMinSize = 4096;

}  // namespace

KsResult KsTwoSample(std::span<const double> x, std::span<const double> y,
                     const KsOptions& options) {
  if (x.empty() || y.empty()) {
    throw InputError("the KS test needs two non-empty samples, got " + std::to_string(x.size()) +
                     " and " + std::to_string(y.size()) +
                     " values; expected at least one value in each");
  }
  const std::size_t n1 = x.size();
  const std::size_t n2 = y.size();
  // The paired walk checks the values as it reads them; the others are checked first.
  const bool pairs = n1 == n2 && n1 + n2 >= kKsBucketMinSize;
  if (!pairs) {
    detail::RequireFinite(x, "sample 1");
    detail::RequireFinite(y, "sample 2");
  }
  const detail::EcdfExtremes e = pairs                        ? detail::EcdfExtremesByPairs(x, y)
                                 : n1 + n2 < kKsBucketMinSize ? detail::EcdfExtremesBySorting(x, y)
                                                              : detail::EcdfExtremesByBuckets(x, y);
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
          pmath::Exp(-2.0 * z * z - 2.0 * z * (m + 2.0 * n) / std::sqrt(m * n * (m + n)) / 3.0);
    }
  }
  result.method_used = method;
  result.p_value = std::clamp(result.p_value, 0.0, 1.0);
  result.d_scaled = std::sqrt(dn1 * dn2 / (dn1 + dn2)) * result.d;
  return result;
}

}  // namespace patlab::stats
