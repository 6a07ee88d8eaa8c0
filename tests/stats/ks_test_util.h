// Helpers of the KS walks' tests (ks_walk_test.cpp, ks_pairs_test.cpp): the walk as first
// written, to compare the fast walks with, and a small deterministic generator.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "patlab/stats/ks.h"

namespace patlab::stats::testing {

// The walk as first written: std::sort, then one tied value at a time.
inline detail::EcdfExtremes StraightforwardExtremes(std::vector<double> a, std::vector<double> b) {
  // -0.0 before +0.0, as SortAscending orders them.
  const auto less = [](double p, double q) {
    return p < q || (p == q && std::signbit(p) && !std::signbit(q));
  };
  std::sort(a.begin(), a.end(), less);
  std::sort(b.begin(), b.end(), less);
  const size_t n1 = a.size(), n2 = b.size();
  detail::EcdfExtremes e;
  size_t i = 0, j = 0;
  while (i < n1 || j < n2) {
    const double v = (j >= n2 || (i < n1 && a[i] <= b[j])) ? a[i] : b[j];
    while (i < n1 && a[i] == v) ++i;
    while (j < n2 && b[j] == v) ++j;
    const double diff = static_cast<double>(i) / static_cast<double>(n1) -
                        static_cast<double>(j) / static_cast<double>(n2);
    if (diff > e.max_diff) e.max_diff = diff, e.max_loc = v;
    if (diff < e.min_diff) e.min_diff = diff, e.min_loc = v;
  }
  return e;
}

inline void ExpectSameExtremes(const detail::EcdfExtremes& got, const detail::EcdfExtremes& want) {
  EXPECT_EQ(got.max_diff, want.max_diff);
  EXPECT_EQ(got.min_diff, want.min_diff);
  EXPECT_EQ(got.max_loc, want.max_loc);
  EXPECT_EQ(got.min_loc, want.min_loc);
  EXPECT_EQ(std::signbit(got.max_loc), std::signbit(want.max_loc));
  EXPECT_EQ(std::signbit(got.min_loc), std::signbit(want.min_loc));
}

// A small deterministic generator for the walks' tests (an LCG; Box-Muller for normals).
struct Lcg {
  uint64_t state;
  double Uniform() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) * 0x1p-53;
  }
  double Normal() {
    const double u = Uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * Uniform());
  }
};

}  // namespace patlab::stats::testing
