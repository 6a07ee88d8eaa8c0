#include "patlab/core/portable_math.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace patlab::pmath {
namespace {

constexpr double kPi = std::numbers::pi;

// Distance in units in the last place between two finite doubles (0 when equal, also +0 / -0).
int64_t UlpDistance(double a, double b) {
  const auto ordered = [](double x) {
    const auto bits = std::bit_cast<int64_t>(x);
    return bits < 0 ? std::numeric_limits<int64_t>::min() - bits : bits;
  };
  const int64_t d = ordered(a) - ordered(b);
  return d < 0 ? -d : d;
}

std::vector<double> Uniform(double lo, double hi, int n, uint32_t seed) {
  std::mt19937_64 gen(seed);  // test inputs only: the values, not the stream, matter here
  std::uniform_real_distribution<double> dist(lo, hi);
  std::vector<double> v(n);
  for (double& x : v) x = dist(gen);
  return v;
}

// glibc's functions are within 1 ulp of the correctly rounded value; so are ours, so the two
// may differ by up to 2 ulp. A wrong coefficient, quadrant or reduction constant moves the
// result by far more than that.
constexpr int64_t kMaxUlpFromGlibc = 2;

TEST(PortableMath, LogAgreesWithGlibcOnUniformsAndAcrossExponents) {
  std::vector<double> xs = Uniform(0x1.0p-33, 1.0, 200000, 1);
  for (double x : Uniform(-1000.0, 1000.0, 20000, 2)) xs.push_back(std::exp2(x));
  xs.insert(xs.end(), {1.0, 0x1.0p-33, std::sqrt(2.0), std::nextafter(std::sqrt(2.0), 2.0), 0.5,
                       2.0, 1.0 - 0x1.0p-53, 1.0 + 0x1.0p-52, std::numeric_limits<double>::min(),
                       std::numeric_limits<double>::max()});
  for (double x : xs) ASSERT_LE(UlpDistance(Log(x), std::log(x)), kMaxUlpFromGlibc) << x;
  EXPECT_EQ(Log(1.0), 0.0);
}

TEST(PortableMath, ExpAgreesWithGlibcAndSaturatesOutsideItsRange) {
  std::vector<double> xs = Uniform(-708.0, 709.0, 200000, 3);
  for (double x : Uniform(-2.0, 2.0, 50000, 4)) xs.push_back(x);
  xs.insert(xs.end(), {0.0, 1.0, -1.0, -708.0, 709.0, 1e-300, -1e-300});
  for (double x : xs) ASSERT_LE(UlpDistance(Exp(x), std::exp(x)), kMaxUlpFromGlibc) << x;
  EXPECT_EQ(Exp(0.0), 1.0);
  EXPECT_EQ(Exp(-800.0), 0.0);
  EXPECT_EQ(Exp(800.0), std::numeric_limits<double>::infinity());
}

TEST(PortableMath, SinAndCosAgreeWithGlibcInEveryQuadrant) {
  std::vector<double> xs = Uniform(-2.0 * kPi, 2.0 * kPi, 200000, 5);
  for (double x : Uniform(-1e5, 1e5, 50000, 6)) xs.push_back(x);
  for (double x : Uniform(-1e-6, 1e-6, 10000, 7)) xs.push_back(x);
  for (int k = -8; k <= 8; ++k) {  // the quadrant boundaries and their neighbours
    const double b = k * kPi / 4.0;
    xs.insert(xs.end(), {b, std::nextafter(b, -10.0), std::nextafter(b, 10.0)});
  }
  for (double x : xs) {
    double s = 0.0, c = 0.0;
    SinCos(x, &s, &c);
    // Near a zero of sin or cos the relative error of any implementation grows; compare there
    // in absolute terms (one ulp of 1).
    if (std::abs(std::sin(x)) > 1e-3) {
      ASSERT_LE(UlpDistance(s, std::sin(x)), kMaxUlpFromGlibc) << x;
    } else {
      ASSERT_NEAR(s, std::sin(x), 0x1.0p-52) << x;
    }
    if (std::abs(std::cos(x)) > 1e-3) {
      ASSERT_LE(UlpDistance(c, std::cos(x)), kMaxUlpFromGlibc) << x;
    } else {
      ASSERT_NEAR(c, std::cos(x), 0x1.0p-52) << x;
    }
    ASSERT_EQ(std::bit_cast<uint64_t>(Sin(x)), std::bit_cast<uint64_t>(s));
    ASSERT_EQ(std::bit_cast<uint64_t>(Cos(x)), std::bit_cast<uint64_t>(c));
  }
  EXPECT_EQ(Sin(0.0), 0.0);
  EXPECT_TRUE(std::signbit(Sin(-0.0)));
  EXPECT_EQ(Cos(0.0), 1.0);
  EXPECT_TRUE(std::isnan(Sin(std::numeric_limits<double>::quiet_NaN())));
}

TEST(PortableMath, Atan2AgreesWithGlibcAroundTheCircleAndOnTheAxes) {
  const std::vector<double> ys = Uniform(-10.0, 10.0, 200000, 8);
  const std::vector<double> xs = Uniform(-10.0, 10.0, 200000, 9);
  for (size_t k = 0; k < ys.size(); ++k) {
    const double y = ys[k], x = xs[k];
    ASSERT_LE(UlpDistance(Atan2(y, x), std::atan2(y, x)), kMaxUlpFromGlibc) << y << " " << x;
    // Directions near the octant boundaries, where the reduction switches branch.
    const double xb = y * (1.0 + 1e-9 * x);
    ASSERT_LE(UlpDistance(Atan2(y, xb), std::atan2(y, xb)), kMaxUlpFromGlibc) << y << " " << xb;
    const double xt = y / std::tan(kPi / 8.0) * (1.0 + 1e-12 * x);
    ASSERT_LE(UlpDistance(Atan2(y, xt), std::atan2(y, xt)), kMaxUlpFromGlibc) << y << " " << xt;
  }
  for (double y : {0.0, -0.0, 1.0, -1.0, 1e-300, -1e300}) {
    for (double x : {0.0, -0.0, 1.0, -1.0, 1e-300, -1e300}) {
      EXPECT_EQ(std::bit_cast<uint64_t>(Atan2(y, x)), std::bit_cast<uint64_t>(std::atan2(y, x)))
          << y << " " << x;
    }
  }
}

// Calls in a loop that GCC vectorises (the kernel's shape), against one call at a time with
// vectorisation switched off: the same bits whatever the vector width.
void VectorLoop(const double* x, const double* y, int n, double* out) {
  for (int k = 0; k < n; ++k) out[k] = Log(x[k]);
  for (int k = 0; k < n; ++k) out[n + k] = Sin(y[k]);
  for (int k = 0; k < n; ++k) out[2 * n + k] = Cos(y[k]);
  for (int k = 0; k < n; ++k) out[3 * n + k] = Atan2(y[k], x[k] - 0.5);
  for (int k = 0; k < n; ++k) out[4 * n + k] = Exp(-y[k]);
}

#if defined(__clang__)
#define PATLAB_NO_VECTORISE __attribute__((noinline))
#define PATLAB_NO_VECTORISE_LOOP _Pragma("clang loop vectorize(disable) interleave(disable)")
#else
#define PATLAB_NO_VECTORISE __attribute__((optimize("no-tree-vectorize"), noinline))
#define PATLAB_NO_VECTORISE_LOOP
#endif

PATLAB_NO_VECTORISE void ScalarLoop(const double* x, const double* y, int n, double* out) {
  PATLAB_NO_VECTORISE_LOOP
  for (int k = 0; k < n; ++k) {
    out[k] = Log(x[k]);
    out[n + k] = Sin(y[k]);
    out[2 * n + k] = Cos(y[k]);
    out[3 * n + k] = Atan2(y[k], x[k] - 0.5);
    out[4 * n + k] = Exp(-y[k]);
  }
}

TEST(PortableMath, VectorisedLoopsGiveTheBitsOfOneCallAtATime) {
  const int n = 4099;  // not a multiple of any vector width: the remainder loop runs too
  const std::vector<double> x = Uniform(1e-9, 1.0, n, 10), y = Uniform(-20.0, 20.0, n, 11);
  std::vector<double> vec(5 * n), one(5 * n);
  VectorLoop(x.data(), y.data(), n, vec.data());
  ScalarLoop(x.data(), y.data(), n, one.data());
  for (int k = 0; k < 5 * n; ++k) {
    ASSERT_EQ(std::bit_cast<uint64_t>(vec[k]), std::bit_cast<uint64_t>(one[k])) << k;
  }
}

// Bits recorded once: a machine, compiler or flag that changes any of them changes patlab's
// results, and this test says which function moved.
TEST(PortableMath, KnownBitsOnEveryMachine) {
  EXPECT_EQ(Log(0.3), -0x1.34378fcbda721p+0);
  EXPECT_EQ(Log(0x1.0p-33), -0x1.6dfb516f20bbfp+4);
  EXPECT_EQ(Exp(-0.7), 0x1.fc80db9dd5542p-2);
  EXPECT_EQ(Sin(2.5), 0x1.326af0dcfcabp-1);
  EXPECT_EQ(Cos(2.5), -0x1.9a2f7ef858b7dp-1);
  EXPECT_EQ(Sin(-5.9), 0x1.7ed98640bbd1bp-2);
  EXPECT_EQ(Atan2(-0.3, -0.8), -0x1.643382c07913ap+1);
}

// The exact wrap by another road: IEEE remainder (exact by definition, glibc's integer long
// division), moved from -pi to pi.
double ReferenceWrap(double x) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  const double r = std::remainder(x, two_pi);
  return r <= -std::numbers::pi ? r + two_pi : r;
}

TEST(PortableMath, WrapAngleIsTheExactRemainderForEveryMagnitude) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  int far = 0;
  for (int exponent = -40; exponent <= 1023; ++exponent) {
    for (int j = 0; j < 40; ++j) {
      const double x = (j % 2 == 0 ? 1.0 : -1.0) * std::ldexp(mantissa(rng), exponent);
      const double want = ReferenceWrap(x);
      ASSERT_EQ(WrapAngle(x), want) << std::hexfloat << x;
      ASSERT_GT(WrapAngle(x), -std::numbers::pi) << std::hexfloat << x;
      ASSERT_LE(WrapAngle(x), std::numbers::pi) << std::hexfloat << x;
      ASSERT_EQ(WrapAngleFar(x), want) << std::hexfloat << x;
      if (std::abs(x) < kWrapNearLimit) {
        ASSERT_EQ(WrapAngleNear(x), want) << std::hexfloat << x;
      } else {
        ++far;
      }
    }
  }
  EXPECT_GT(far, 30000);
  // Whole turns away from an angle: 3 turns is 3 x 2pi rounded once, so compare with the
  // reference, and with the angle itself to rounding.
  EXPECT_EQ(WrapAngle(0.25 + 6.0 * std::numbers::pi), ReferenceWrap(0.25 + 6.0 * std::numbers::pi));
  EXPECT_NEAR(WrapAngle(0.25 + 6.0 * std::numbers::pi), 0.25, 1e-14);
  EXPECT_NEAR(WrapAngle(-1.0 - 2e6 * std::numbers::pi), -1.0, 1e-9);
}

TEST(PortableMath, WrapAngleKeepsAnglesInRangeAndMovesMinusPiToPi) {
  const double pi = std::numbers::pi;
  for (double x : {0.0, 1e-300, -1e-300, 1.0, -1.0, pi, std::nextafter(pi, 0.0),
                   std::nextafter(-pi, 0.0), 3.0, -3.0}) {
    EXPECT_EQ(std::bit_cast<uint64_t>(WrapAngle(x)), std::bit_cast<uint64_t>(x)) << x;
  }
  EXPECT_EQ(std::bit_cast<uint64_t>(WrapAngle(-0.0)), std::bit_cast<uint64_t>(-0.0));
  EXPECT_EQ(WrapAngle(-pi), pi);
  EXPECT_EQ(WrapAngle(3.0 * pi), ReferenceWrap(3.0 * pi));
  EXPECT_EQ(WrapAngle(std::nextafter(pi, 4.0)), std::nextafter(pi, 4.0) - 2.0 * pi);
  EXPECT_EQ(WrapAngle(2.0 * pi), 0.0);
  EXPECT_EQ(WrapAngle(-2.0 * pi), 0.0);
  EXPECT_EQ(WrapAngle(std::numeric_limits<double>::max()),
            ReferenceWrap(std::numeric_limits<double>::max()));
  EXPECT_EQ(WrapAngle(kWrapNearLimit), ReferenceWrap(kWrapNearLimit));
  EXPECT_EQ(WrapAngle(std::nextafter(kWrapNearLimit, 0.0)),
            ReferenceWrap(std::nextafter(kWrapNearLimit, 0.0)));
  EXPECT_TRUE(std::isnan(WrapAngle(std::numeric_limits<double>::infinity())));
  EXPECT_TRUE(std::isnan(WrapAngle(std::numeric_limits<double>::quiet_NaN())));
}

}  // namespace
}  // namespace patlab::pmath
