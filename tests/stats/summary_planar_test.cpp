// The planar moments (summary_planar.cpp) against their plain definition, bit for bit, on every
// kind of data and length, and the tiles their second pass shows.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "../expect_error.h"
#include "patlab/core/error.h"
#include "patlab/stats/summary.h"

namespace patlab::stats {
namespace {

// The plain definition of the planar moments, one column at a time: every sum in index order,
// each product stored in a volatile (rounded to double, so never fused into the addition that
// follows, whatever the compiler's contraction setting), x^2 + y^2 as fma(x, x, y * y) where the
// target has FMA (the runner's former loops, contracted by GCC), else the rounded sum.
double Rounded(double v) {
  volatile double stored = v;
  return stored;
}
double PlainSquaredRadius(double x, double y) {
#ifdef __FMA__
  return std::fma(x, x, Rounded(y * y));
#else
  return Rounded(x * x) + Rounded(y * y);
#endif
}
Moments PlainMoments(const std::vector<double>& v) {
  double sum = 0.0;
  for (const double x : v) sum += x;
  const double mean = sum / static_cast<double>(v.size());
  double m2 = 0.0;
  for (const double x : v) m2 += Rounded((x - mean) * (x - mean));
  return Moments{static_cast<std::int64_t>(v.size()), mean, m2};
}
struct PlainPlanar {
  Moments x, y, theta, radial;
  double sum_sq = 0.0;
};
PlainPlanar PlainPlanarMoments(const std::vector<double>& x, const std::vector<double>& y,
                               const std::vector<double>& theta) {
  std::vector<double> r(x.size());
  double sum_sq = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double sq = PlainSquaredRadius(x[i], y[i]);
    sum_sq += sq;
    r[i] = std::sqrt(sq);
  }
  return PlainPlanar{PlainMoments(x), PlainMoments(y), PlainMoments(theta), PlainMoments(r),
                     sum_sq};
}

// Bit equality (so +0 and -0 differ) that also holds for NaN == NaN (an overflowing sum).
void ExpectSameBits(double a, double b, const std::string& what) {
  EXPECT_TRUE(std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b) ||
              (std::isnan(a) && std::isnan(b)))
      << what << ": " << a << " vs " << b;
}
void ExpectSameMoments(const Moments& a, const Moments& b, const std::string& what) {
  EXPECT_EQ(a.n, b.n) << what;
  ExpectSameBits(a.mean, b.mean, what + " mean");
  ExpectSameBits(a.m2, b.m2, what + " m2");
}

struct PlanarData {
  std::vector<std::vector<double>> x, y, theta;
};
// `count` samples of n values; kind picks the data: values near 1, huge, tiny, offsets far from
// zero (where the order of the additions shows), mixed magnitudes, quantised values with ties and
// signed zeros, or heavy tails (Cauchy).
PlanarData MakePlanar(size_t count, size_t n, int kind, uint64_t seed) {
  PlanarData d;
  uint64_t state = seed;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * 0x1p-53 - 0.5;
  };
  auto value = [&](size_t i) {
    const double u = next();
    switch (kind) {
      case 1:
        return u * 1e150;  // squares near 1e300
      case 2:
        return u * 1e-160;  // squares below the normal range
      case 3:
        return 1e6 + u;
      case 4:
        return u * std::pow(10.0, static_cast<double>(i % 13) - 6.0);
      case 5:
        return u < -0.25 ? -0.0 : u < 0.0 ? 0.0 : std::round(u * 8.0) / 8.0;
      case 6:
        return std::tan(3.14159265358979 * u);
      default:
        return u;
    }
  };
  for (size_t k = 0; k < count; ++k) {
    for (auto* column : {&d.x, &d.y, &d.theta}) {
      column->emplace_back(n);
      for (size_t i = 0; i < n; ++i) column->back()[i] = value(i);
    }
  }
  return d;
}

std::vector<PlanarSample> Spans(const PlanarData& d) {
  std::vector<PlanarSample> s;
  for (size_t k = 0; k < d.x.size(); ++k) s.push_back(PlanarSample{d.x[k], d.y[k], d.theta[k]});
  return s;
}

// PlanarMomentsOfEach on all of d's samples at once against the plain definition of each.
void ExpectPlainBits(const PlanarData& d, const std::string& what) {
  std::vector<PlanarMoments> out(d.x.size());
  PlanarMomentsOfEach(Spans(d), out);
  for (size_t k = 0; k < d.x.size(); ++k) {
    const std::string sample = what + " sample " + std::to_string(k);
    const PlainPlanar p = PlainPlanarMoments(d.x[k], d.y[k], d.theta[k]);
    ExpectSameMoments(out[k].x, p.x, sample + " x");
    ExpectSameMoments(out[k].y, p.y, sample + " y");
    ExpectSameMoments(out[k].theta, p.theta, sample + " theta");
    ExpectSameMoments(out[k].radial, p.radial, sample + " radial");
    ExpectSameBits(out[k].sum_sq, p.sum_sq, sample + " sum_sq");
  }
}

TEST(PlanarMoments, HaveTheBitsOfThePlainDefinition) {
  // n = 1, 2, 3, around the 128-value tile (remainders 1 and 127), and a data point's 100,000;
  // 1 to kMaxPlanarSamples samples; every kind of data.
  for (const size_t n : {size_t{1}, size_t{2}, size_t{3}, size_t{127}, size_t{128}, size_t{129},
                         size_t{1000}, size_t{100000}}) {
    for (size_t count = 1; count <= kMaxPlanarSamples; ++count) {
      for (int kind = 0; kind <= 4; ++kind) {
        if (n == 100000 && (count == 3 || kind == 2)) continue;  // enough of the large ones
        ExpectPlainBits(MakePlanar(count, n, kind, 11 * n + 7 * count + kind),
                        "n " + std::to_string(n) + " samples " + std::to_string(count) + " kind " +
                            std::to_string(kind));
      }
    }
  }
}

TEST(PlanarMoments, ShowEveryTileOfPassTwoWithItsRadialErrorsOnceRead) {
  // The overload with a visitor: the same bits as the plain definition; tiles in index order that
  // cover [0, n) once, each with every sample's r = sqrt(x^2 + y^2) by the plain rule; and a
  // visitor that overwrites the tile's values (as the runner writes its paired differences there)
  // changes nothing, so each tile was read before it was shown and never read again.
  for (const size_t n :
       {size_t{1}, size_t{127}, size_t{128}, size_t{129}, size_t{300}, size_t{1000}}) {
    for (size_t count = 1; count <= kMaxPlanarSamples; ++count) {
      for (const int kind : {0, 5, 6}) {
        const std::string what = "n " + std::to_string(n) + " samples " + std::to_string(count) +
                                 " kind " + std::to_string(kind);
        const PlanarData original = MakePlanar(count, n, kind, 13 * n + 5 * count + kind);
        PlanarData d = original;
        size_t next = 0, mismatches = 0;
        std::vector<PlanarMoments> out(count);
        PlanarMomentsOfEach(Spans(d), out, [&](const PlanarTile& tile) {
          EXPECT_EQ(tile.first, next) << what;
          EXPECT_GE(tile.count, 1u) << what;
          EXPECT_LE(tile.first + tile.count, n) << what;
          next = tile.first + tile.count;
          for (size_t k = 0; k < count; ++k) {
            for (size_t j = 0; j < tile.count; ++j) {
              const size_t i = tile.first + j;
              const double r = std::sqrt(PlainSquaredRadius(original.x[k][i], original.y[k][i]));
              mismatches +=
                  std::bit_cast<uint64_t>(tile.radial[k][j]) != std::bit_cast<uint64_t>(r);
              d.x[k][i] = d.y[k][i] = d.theta[k][i] = std::numeric_limits<double>::quiet_NaN();
            }
          }
        });
        EXPECT_EQ(next, n) << what;
        EXPECT_EQ(mismatches, 0u) << what;
        for (size_t k = 0; k < count; ++k) {
          const PlainPlanar p = PlainPlanarMoments(original.x[k], original.y[k], original.theta[k]);
          const std::string sample = what + " sample " + std::to_string(k);
          ExpectSameMoments(out[k].x, p.x, sample + " x");
          ExpectSameMoments(out[k].y, p.y, sample + " y");
          ExpectSameMoments(out[k].theta, p.theta, sample + " theta");
          ExpectSameMoments(out[k].radial, p.radial, sample + " radial");
          ExpectSameBits(out[k].sum_sq, p.sum_sq, sample + " sum_sq");
        }
        if (HasFailure()) return;
      }
    }
  }
}

TEST(PlanarMoments, HaveThePlainBitsAtEveryLengthUpTo300) {
  // The sums run in vector lanes (one lane per column of a sample) over blocks of 8 indices, with
  // a scalar tail, and pass 2 in tiles of 128: every length up to 300 crosses every block and tile
  // remainder, for 1 to 4 samples (5 to 20 chains in pass 1, 4 to 16 in pass 2: every mix of lane
  // groups of 8, 4, 2 and 1).
  for (size_t n = 1; n <= 300; ++n) {
    for (size_t count = 1; count <= kMaxPlanarSamples; ++count) {
      for (const int kind : {3, 5, 6}) {
        ExpectPlainBits(MakePlanar(count, n, kind, 3 * n + count + 1000 * kind),
                        "n " + std::to_string(n) + " samples " + std::to_string(count) + " kind " +
                            std::to_string(kind));
        if (HasFailure()) return;
      }
    }
  }
}

TEST(PlanarMoments, HaveThePlainBitsOnEveryKindOfData) {
  // The kinds the length sweep skips, and every kind at lengths just off a data point's 100,000.
  for (const size_t n : {size_t{255}, size_t{99999}, size_t{100001}}) {
    for (int kind = 0; kind <= 6; ++kind) {
      const size_t count = n == 99999 ? 3 : 2;
      ExpectPlainBits(MakePlanar(count, n, kind, 5 * n + count + kind),
                      "n " + std::to_string(n) + " samples " + std::to_string(count) + " kind " +
                          std::to_string(kind));
    }
  }
}

TEST(PlanarMoments, KeepEachChainInItsLane) {
  // Every column of every sample a different constant offset plus small noise: a sum that lands
  // in another column's lane, or takes its values in another order, changes the bits.
  for (const size_t n : {size_t{8}, size_t{16}, size_t{37}, size_t{129}}) {
    for (size_t count = 1; count <= kMaxPlanarSamples; ++count) {
      PlanarData d = MakePlanar(count, n, 0, 77 + n + count);
      for (size_t k = 0; k < count; ++k) {
        for (size_t i = 0; i < n; ++i) {
          d.x[k][i] += 1e3 * static_cast<double>(3 * k + 1);
          d.y[k][i] += 1e3 * static_cast<double>(3 * k + 2);
          d.theta[k][i] += 1e3 * static_cast<double>(3 * k + 3);
        }
      }
      ExpectPlainBits(d, "n " + std::to_string(n) + " samples " + std::to_string(count));
    }
  }
}

TEST(PlanarMoments, HandComputed) {
  // x, y = (3, 4) and (0, 0): radii 5 and 0, sum_sq 25; theta 1 and 3.
  const std::vector<double> x = {3.0, 0.0}, y = {4.0, 0.0}, theta = {1.0, 3.0};
  PlanarMoments m;
  PlanarMomentsOfEach(std::vector<PlanarSample>{{x, y, theta}}, std::span<PlanarMoments>(&m, 1));
  EXPECT_EQ(m.x.n, 2);
  EXPECT_EQ(m.x.mean, 1.5);
  EXPECT_EQ(m.x.m2, 4.5);
  EXPECT_EQ(m.y.mean, 2.0);
  EXPECT_EQ(m.y.m2, 8.0);
  EXPECT_EQ(m.theta.mean, 2.0);
  EXPECT_EQ(m.theta.m2, 2.0);
  EXPECT_EQ(m.radial.mean, 2.5);
  EXPECT_EQ(m.radial.m2, 12.5);
  EXPECT_EQ(m.sum_sq, 25.0);
}

TEST(PlanarMoments, AgreeWithMomentsOfEachOnAVectorisedLength) {
  // On lengths that are a multiple of 8, MomentsOfEach's sums of squares are the rounded products
  // too (its vector loop; its scalar tail may fuse), so the two give the same bits there with GCC.
  // Clang contracts MomentsOfEach's (v - mean) * (v - mean) + s into an FMA (-ffp-contract=on,
  // seen in the sanitizer build), so there the old call's bits are not the plain definition's;
  // HaveTheBitsOfThePlainDefinition checks PlanarMomentsOfEach on every compiler.
#if defined(__clang__)
  GTEST_SKIP() << "clang fuses MomentsOfEach's squared deviations; see the comment";
#endif
  const PlanarData d = MakePlanar(2, 4096, 4, 5);
  std::vector<PlanarMoments> out(2);
  PlanarMomentsOfEach(Spans(d), out);
  for (size_t k = 0; k < 2; ++k) {
    Moments m[3];
    MomentsOfEach(std::vector<std::span<const double>>{d.x[k], d.y[k], d.theta[k]}, m);
    ExpectSameMoments(out[k].x, m[0], "x");
    ExpectSameMoments(out[k].y, m[1], "y");
    ExpectSameMoments(out[k].theta, m[2], "theta");
  }
}

TEST(PlanarMoments, OverflowingFiniteSamplesGiveTheArithmeticsResult) {
  // Finite values whose sum overflows: no error (the finiteness search finds nothing), and the
  // moments are what the plain arithmetic gives (an infinite mean, NaN or infinite m2).
  const std::vector<double> x = {1.5e308, 1.5e308, -1.0}, y = {1.0, 2.0, 3.0},
                            theta = {0.0, 0.0, 1.0};
  PlanarMoments m;
  PlanarMomentsOfEach(std::vector<PlanarSample>{{x, y, theta}}, std::span<PlanarMoments>(&m, 1));
  const PlainPlanar p = PlainPlanarMoments(x, y, theta);
  EXPECT_TRUE(std::isinf(m.x.mean));
  ExpectSameMoments(m.x, p.x, "x");
  ExpectSameMoments(m.y, p.y, "y");
  ExpectSameMoments(m.radial, p.radial, "radial");
  ExpectSameBits(m.sum_sq, p.sum_sq, "sum_sq");
}

TEST(PlanarMoments, RejectNonFiniteValuesNamingTheFirst) {
  const std::vector<double> good = {1.0, 2.0, 3.0}, nan = {1.0, 2.0, std::nan("")},
                            inf = {1.0, -std::numeric_limits<double>::infinity(), 3.0},
                            both = {std::numeric_limits<double>::infinity(), 1.0,
                                    -std::numeric_limits<double>::infinity()};
  std::vector<PlanarMoments> out(2);
  auto run = [&out](const std::vector<PlanarSample>& s) {
    PlanarMomentsOfEach(s, std::span<PlanarMoments>(out.data(), s.size()));
  };
  EXPECT_INPUT_ERROR((run({{good, good, nan}})), "sample value 3 is NaN; expected finite numbers");
  EXPECT_INPUT_ERROR((run({{good, inf, good}})),
                     "sample value 2 is infinite; expected finite numbers");
  // +inf and -inf sum to NaN: still found.
  EXPECT_INPUT_ERROR((run({{both, good, good}})),
                     "sample value 1 is infinite; expected finite numbers");
  // The first bad column in the order sample 0's x, y, theta, then sample 1's.
  EXPECT_INPUT_ERROR((run({{good, good, good}, {nan, inf, good}})),
                     "sample value 3 is NaN; expected finite numbers");
  EXPECT_INPUT_ERROR((run({{good, good, inf}, {nan, good, good}})),
                     "sample value 2 is infinite; expected finite numbers");
  const std::vector<double> none;
  EXPECT_INPUT_ERROR((run({{none, none, none}})),
                     "the moments needs at least 1 samples, got 0; expected at least 1");
}

TEST(PlanarMoments, RejectANonFiniteValueInAnyLaneAndPosition) {
  // One NaN or infinity in any column of any of 1 to 4 samples, in a vector block (first, last
  // index of a block) or the scalar tail: the message names it.
  constexpr size_t kN = 301;  // 37 blocks of 8 and a tail of 5
  for (size_t count = 1; count <= 4; ++count) {
    for (size_t k = 0; k < count; ++k) {
      for (int column = 0; column < 3; ++column) {
        for (const size_t at :
             {size_t{0}, size_t{7}, size_t{8}, size_t{150}, size_t{297}, kN - 1}) {
          for (const bool nan : {true, false}) {
            PlanarData d = MakePlanar(count, kN, 0, 9 + at);
            auto& values = column == 0 ? d.x : column == 1 ? d.y : d.theta;
            values[k][at] = nan ? std::nan("") : -std::numeric_limits<double>::infinity();
            std::vector<PlanarMoments> out(count);
            EXPECT_INPUT_ERROR(PlanarMomentsOfEach(Spans(d), out),
                               "sample value " + std::to_string(at + 1) + " is " +
                                   (nan ? "NaN" : "infinite") + "; expected finite numbers");
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace patlab::stats
