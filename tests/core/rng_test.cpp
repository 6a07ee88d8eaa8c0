#include "patlab/core/rng.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace patlab {
namespace {

TEST(PhiloxBatch, MatchesRandom123ForEveryLane) {
  // The vectorised batch must give exactly Random123's Philox4x32-10 words.
  std::vector<uint32_t> c0(1000), o0(1000), o1(1000), o2(1000), o3(1000);
  for (uint32_t k = 0; k < c0.size(); ++k) c0[k] = 0xFFFFFF00u + k * 2654435761u;
  const uint64_t key = 0x0123456789ABCDEFull;
  PhiloxBatch(key, c0.data(), 7, 0xDEADBEEF, 3, static_cast<int>(c0.size()), o0.data(), o1.data(),
              o2.data(), o3.data());
  for (size_t k = 0; k < c0.size(); ++k) {
    const auto ref = PhiloxBlock(key, c0[k], 7, 0xDEADBEEF, 3);
    ASSERT_EQ(o0[k], ref[0]) << k;
    ASSERT_EQ(o1[k], ref[1]) << k;
    ASSERT_EQ(o2[k], ref[2]) << k;
    ASSERT_EQ(o3[k], ref[3]) << k;
  }
}

TEST(PhiloxBlock, MatchesTheRandom123KnownAnswer) {
  // Random123's kat_vectors: philox4x32 10 rounds, counter and key all ones (0xffffffff).
  const auto w = PhiloxBlock(0xFFFFFFFFFFFFFFFFull, 0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff);
  EXPECT_EQ(w[0], 0x408f276du);
  EXPECT_EQ(w[1], 0x41c83b0eu);
  EXPECT_EQ(w[2], 0xa20bc7c6u);
  EXPECT_EQ(w[3], 0x6d5451fdu);
}

TEST(Uniforms, StayStrictlyInsideTheUnitInterval) {
  EXPECT_GT(UniformOpen01(0u, 0u), 0.0);
  EXPECT_LT(UniformOpen01(0xFFFFFFFFu, 0xFFFFFFFFu), 1.0);
  EXPECT_EQ(UniformOpen01(0u, 0u), 0x1.0p-53);
  EXPECT_EQ(UniformOpen01(0xFFFFFFFFu, 0xFFFFFFFFu), 1.0 - 0x1.0p-53);
  EXPECT_GT(UniformOpen01(0u), 0.0);
  EXPECT_LT(UniformOpen01(0xFFFFFFFFu), 1.0);
  EXPECT_EQ(UniformOpen01(0x80000000u), 0.5 + 0x1.0p-33);
}

TEST(RandomStream, IsAPureFunctionOfItsIdentity) {
  RandomStream a(42, 3, 1000), b(42, 3, 1000), c(42, 3, 1001);
  for (int k = 0; k < 10; ++k) {
    const double x = a.Normal();
    EXPECT_EQ(x, b.Normal());
    EXPECT_NE(x, c.Normal());
  }
}

TEST(RandomStream, NormalsHaveUnitVarianceWithinFourStandardErrors) {
  RandomStream s(1, 0, 0);
  const int n = 200000;
  double sum = 0, sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const double z = s.Normal();
    sum += z;
    sum2 += z * z;
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  EXPECT_NEAR(mean, 0.0, 4.0 / std::sqrt(n));
  EXPECT_NEAR(var, 1.0, 4.0 * std::sqrt(2.0 / n));
}

TEST(RandomStream, BelowStaysInRange) {
  RandomStream s(3, 1, 2);
  std::vector<int> counts(7, 0);
  for (int k = 0; k < 70000; ++k) {
    const uint64_t v = s.Below(7);
    ASSERT_LT(v, 7u);
    ++counts[v];
  }
  for (int c : counts) EXPECT_NEAR(c, 10000, 4 * std::sqrt(10000 * 6.0 / 7.0));
}

}  // namespace
}  // namespace patlab

namespace patlab {
namespace {

TEST(StreamKey, DependsOnEveryValueAndTheirOrderOnly) {
  const uint64_t a = StreamKey(7).Add(1.0).Add(uint64_t{2}).Add(std::string_view("fast")).value();
  EXPECT_EQ(a, StreamKey(7).Add(1.0).Add(uint64_t{2}).Add(std::string_view("fast")).value());
  EXPECT_NE(a, StreamKey(8).Add(1.0).Add(uint64_t{2}).Add(std::string_view("fast")).value());
  EXPECT_NE(a, StreamKey(7).Add(uint64_t{2}).Add(1.0).Add(std::string_view("fast")).value());
  EXPECT_NE(a, StreamKey(7).Add(1.0).Add(uint64_t{2}).Add(std::string_view("fasu")).value());
  EXPECT_NE(a, StreamKey(7)
                   .Add(std::nextafter(1.0, 2.0))
                   .Add(uint64_t{2})
                   .Add(std::string_view("fast"))
                   .value());
  // -0 and +0 are one value; "ab" then "" is not "a" then "b".
  EXPECT_EQ(StreamKey(1).Add(-0.0).value(), StreamKey(1).Add(0.0).value());
  EXPECT_NE(StreamKey(1).Add(std::string_view("ab")).Add(std::string_view("")).value(),
            StreamKey(1).Add(std::string_view("a")).Add(std::string_view("b")).value());
  // A 9-byte string uses both of its words.
  EXPECT_NE(StreamKey(1).Add(std::string_view("123456789")).value(),
            StreamKey(1).Add(std::string_view("12345678A")).value());
}

}  // namespace
}  // namespace patlab
