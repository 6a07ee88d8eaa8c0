#include "patlab/stats/sort.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
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

// The orders both sorts promise, as keys: IEEE order with -0.0 before +0.0; |v| with a negative
// value before a positive one of equal magnitude. Equal keys are equal bits.
uint64_t AscendingKey(double v) {
  const uint64_t u = std::bit_cast<uint64_t>(v), sign = uint64_t{1} << 63;
  return (u & sign) ? ~u : (u | sign);
}
uint64_t MagnitudeKey(double v) {
  const uint64_t u = std::bit_cast<uint64_t>(v), sign = uint64_t{1} << 63;
  return ((u & ~sign) << 1) | ((u & sign) ? 0 : 1);
}

// Smooth samples take the bucket sort (n >= 1024, no extremes), the rest the radix sort; both
// must give std::sort's order bit for bit. kinds: 0 normal with ties and signed zeros, 1 uniform
// and quantised (many ties), 2 normal with +-infinity (no range: radix), 3 clustered (one value
// in most places, some spread: uneven buckets), 4 tiny and huge magnitudes mixed (subnormals and
// 1e300), 5 all equal but signed zeros.
std::vector<double> Kind(int kind, size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 3.0);
  std::uniform_int_distribution<int> level(-40, 40);
  std::vector<double> v(n);
  for (size_t k = 0; k < n; ++k) {
    double x = normal(rng);
    if (kind == 1) x = level(rng) / 8.0;
    if (kind == 3) x = k % 5 == 0 ? x : 1.25;
    if (kind == 4) x = k % 3 == 0 ? x * 1e-310 : (k % 3 == 1 ? x * 1e300 : x);
    if (kind == 5) x = k % 2 == 0 ? 0.0 : -0.0;
    v[k] = x;
  }
  if (kind == 2 && n > 4) v[1] = INFINITY, v[3] = -INFINITY;
  if (n > 10) v[2] = 0.0, v[4] = -0.0, v[6] = v[8];
  return v;
}

template <class Sort, class Key>
void ExpectKeyOrder(Sort sort, Key key) {
  for (int kind = 0; kind < 6; ++kind) {
    for (size_t n : {0u, 1u, 2u, 17u, 1023u, 1024u, 5000u, 100000u, 300000u}) {
      SCOPED_TRACE(::testing::Message() << "kind " << kind << " n " << n);
      std::vector<double> v = Kind(kind, n, 7 * n + kind), expected = v;
      std::sort(expected.begin(), expected.end(),
                [&](double p, double q) { return key(p) < key(q); });
      sort(std::span<double>(v));
      ASSERT_EQ(v.size(), n);
      for (size_t k = 0; k < n; ++k) {
        ASSERT_EQ(std::bit_cast<uint64_t>(v[k]), std::bit_cast<uint64_t>(expected[k])) << k;
      }
    }
  }
}

TEST(SortAscending, GivesTheKeyOrderBitForBitOnEveryKindOfSample) {
  ExpectKeyOrder([](std::span<double> v) { SortAscending(v); }, AscendingKey);
}

TEST(SortByMagnitude, GivesTheKeyOrderBitForBitOnEveryKindOfSample) {
  ExpectKeyOrder([](std::span<double> v) { SortByMagnitude(v); }, MagnitudeKey);
}

// The overloads with the caller's scratch (the runner's dead sample arrays): the same order, with
// a scratch longer than the values and full of garbage (NaN patterns), and the values' storage
// holding the result whether the radix sort ran an odd or an even number of passes.
std::vector<double> Garbage(size_t n) {
  std::vector<double> g(n + 3);
  for (size_t k = 0; k < g.size(); ++k) {
    g[k] = std::bit_cast<double>(0x7ff4000000000000ull + k);  // signalling NaNs
  }
  return g;
}

TEST(SortAscending, WithTheCallersScratchGivesTheSameOrder) {
  ExpectKeyOrder(
      [](std::span<double> v) {
        std::vector<double> scratch = Garbage(v.size());
        SortAscending(v, scratch);
      },
      AscendingKey);
}

TEST(SortByMagnitude, WithTheCallersScratchGivesTheSameOrder) {
  ExpectKeyOrder(
      [](std::span<double> v) {
        std::vector<double> scratch = Garbage(v.size());
        SortByMagnitude(v, scratch);
      },
      MagnitudeKey);
}

// A radix sort whose digits vary in an odd number of passes (here only the lowest 11 bits of the
// keys differ, and two thirds of the values are one value, too clustered for the buckets) ends
// in the scratch; the result must still be copied home.
TEST(SortAscending, OddNumberOfRadixPassesEndsInTheValues) {
  std::vector<double> v(3000), scratch(3000);
  for (size_t k = 0; k < v.size(); ++k) {
    const uint64_t low = k % 3 == 0 ? (k * 7919) % 2048 : 0;
    v[k] = std::bit_cast<double>(std::bit_cast<uint64_t>(1.5) + low);
  }
  std::vector<double> expected = v;
  std::sort(expected.begin(), expected.end());
  SortAscending(v, scratch);
  EXPECT_EQ(v, expected);
}

}  // namespace
}  // namespace patlab::stats
