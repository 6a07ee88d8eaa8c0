#include "patlab/stats/sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace patlab::stats {
namespace {

std::vector<double> Sample(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 3.0);
  std::vector<double> v(n);
  for (double& x : v) x = normal(rng);
  // Ties, zeros of both signs, extremes, subnormals.
  for (size_t k = 0; k + 10 < n; k += 97) v[k] = v[k + 1];
  if (n > 20) {
    v[3] = 0.0;
    v[5] = -0.0;
    v[7] = 1e300;
    v[9] = -1e300;
    v[11] = 4.9e-324;
    v[13] = -4.9e-324;
    v[15] = -v[16];
  }
  return v;
}

TEST(SortAscending, AgreesWithStdSortBitForBitUpToSignedZeros) {
  for (size_t n : {0u, 1u, 2u, 5u, 1000u, 100000u}) {
    std::vector<double> v = Sample(n, n + 1), expected = v;
    std::sort(expected.begin(), expected.end());
    SortAscending(v);
    ASSERT_EQ(v.size(), expected.size());
    for (size_t k = 0; k < n; ++k) ASSERT_EQ(v[k], expected[k]) << n << " at " << k;
    EXPECT_TRUE(std::is_sorted(v.begin(), v.end()));
  }
}

TEST(SortByMagnitude, OrdersByAbsoluteValueAndKeepsSigns) {
  for (size_t n : {1u, 7u, 1000u, 100000u}) {
    std::vector<double> v = Sample(n, n + 2), original = v;
    SortByMagnitude(v);
    for (size_t k = 1; k < n; ++k) ASSERT_LE(std::fabs(v[k - 1]), std::fabs(v[k])) << k;
    std::sort(v.begin(), v.end());
    std::sort(original.begin(), original.end());
    EXPECT_EQ(v, original);  // a permutation: the same multiset of signed values
  }
}

}  // namespace
}  // namespace patlab::stats
