// Elementary functions whose results are the same bits on every x86-64 CPU, with every compiler
// and at every vector width: log, exp, sin, cos (together or apart) and atan2, written in plain
// IEEE-754 double arithmetic (+, -, *, / and bit operations only; no library call, no table, no
// branch that the vectoriser cannot turn into a select).
//
// Why: glibc picks a different implementation of sin, cos, log, exp and atan2 at run time by the
// CPU's features (scalar: SSE2, FMA or FMA4 variants; vector libmvec: SSE4, AVX2 or AVX-512
// variants), and they differ in the last bit. A Monte-Carlo result that passes millions of such
// values through a Newton iteration with a stopping tolerance, or a KS walk over nearly equal
// samples, then changes in its printed digits from one machine to the next. These functions
// give the bits the C++ expressions below give, and patlab is compiled with -ffp-contract=off
// (no fused multiply-add contraction) and without -ffast-math, so those bits do not depend on
// the machine or on how wide the compiler made the loop (docs/architecture.md, "Same bytes on
// every machine").
//
// Accuracy: within 1 ulp of the correctly rounded result over the domains stated below (the
// methods and polynomial coefficients are those of fdlibm's e_log.c, e_exp.c, k_sin.c, k_cos.c
// and s_atan.c: Sun Microsystems' freely distributable libm, 1993; the code is our own, shaped
// for the vectoriser). Tested against glibc in tests/core/portable_math_test.cpp.
//
// Loops over arrays that call these functions vectorise with GCC 12 at -O2 and above (check
// with -fopt-info-vec); the Monte-Carlo kernel (sim/batch.cpp) is written that way.
#pragma once

#include <bit>
#include <cstdint>
#include <limits>

namespace patlab::pmath {

namespace detail {

inline double FromBits(uint64_t b) { return std::bit_cast<double>(b); }
inline uint64_t ToBits(double x) { return std::bit_cast<uint64_t>(x); }

// 2^52 + 2^51: adding it to |v| < 2^51 rounds v to the nearest integer (ties to even) and leaves
// that integer, two's complement, in the low bits of the sum's representation.
constexpr double kRoundShift = 0x1.8p52;

// The integer nearest to v, as a double, for |v| < 2^51.
inline double RoundToInteger(double v) { return (v + kRoundShift) - kRoundShift; }

// atan(x) for |x| <= 7/16 (fdlibm s_atan.c, its polynomial in x^2 split in odd and even parts).
inline double AtanKernel(double x) {
  constexpr double a0 = 3.33333333333329318027e-01, a1 = -1.99999999998764832476e-01,
                   a2 = 1.42857142725034663711e-01, a3 = -1.11111104054623557880e-01,
                   a4 = 9.09088713343650656196e-02, a5 = -7.69187620504482999495e-02,
                   a6 = 6.66107313738753120669e-02, a7 = -5.83357013379057348645e-02,
                   a8 = 4.97687799461593236017e-02, a9 = -3.65315727442169155270e-02,
                   a10 = 1.62858201153657823623e-02;
  const double z = x * x, w = z * z;
  const double s1 = z * (a0 + w * (a2 + w * (a4 + w * (a6 + w * (a8 + w * a10)))));
  const double s2 = w * (a1 + w * (a3 + w * (a5 + w * (a7 + w * a9))));
  return x - x * (s1 + s2);
}

// sin(r) and cos(r) for |r| <= pi/4 (fdlibm k_sin.c and k_cos.c without the tail term).
inline double SinKernel(double r) {
  constexpr double s1 = -1.66666666666666324348e-01, s2 = 8.33333333332248946124e-03,
                   s3 = -1.98412698298579493134e-04, s4 = 2.75573137070700676789e-06,
                   s5 = -2.50507602534068634195e-08, s6 = 1.58969099521155010221e-10;
  const double z = r * r, v = z * r;
  const double p = s2 + z * (s3 + z * (s4 + z * (s5 + z * s6)));
  const double sin_r = r + v * (s1 + z * p);
  return z < 0x1.0p-54 ? r : sin_r;  // sin r = r to the last bit there, and -0 stays -0
}

inline double CosKernel(double r) {
  constexpr double c1 = 4.16666666666666019037e-02, c2 = -1.38888888888741095749e-03,
                   c3 = 2.48015872894767294178e-05, c4 = -2.75573143513906633035e-07,
                   c5 = 2.08757232129817482790e-09, c6 = -1.13596475577881948265e-11;
  const double z = r * r;
  const double p = z * (c1 + z * (c2 + z * (c3 + z * (c4 + z * (c5 + z * c6)))));
  const double hz = 0.5 * z, w = 1.0 - hz;
  return w + (((1.0 - w) - hz) + z * p);
}

// x = k pi/2 + r with |r| <= pi/4 (Cody-Waite: pi/2 in three parts of 33 bits, so that k times
// each part is exact for |k| < 2^20). Returns r; *quadrant_bits holds k in its low bits.
inline double ReduceHalfPi(double x, uint64_t* quadrant_bits) {
  constexpr double two_over_pi = 6.36619772367581382433e-01;
  constexpr double pio2_1 = 1.57079632673412561417e+00, pio2_2 = 6.07710050630396597660e-11,
                   pio2_3 = 2.02226624871116645580e-21;
  const double shifted = x * two_over_pi + kRoundShift;
  *quadrant_bits = ToBits(shifted);
  const double k = shifted - kRoundShift;
  return ((x - k * pio2_1) - k * pio2_2) - k * pio2_3;
}

// a when the mask is all ones, b when it is zero (bitwise, so that it vectorises as and/or).
inline double Blend(uint64_t mask, double a, double b) {
  return FromBits((ToBits(a) & mask) | (ToBits(b) & ~mask));
}

}  // namespace detail

// Natural logarithm of a positive normal double (2^-1022 <= x < inf); patlab calls it on
// uniforms in (0, 1). Zero, negative, subnormal, infinite and NaN arguments give unspecified
// finite or NaN values, never a trap.
inline double Log(double x) {
  using namespace detail;
  constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
  constexpr double lg1 = 6.666666666666735130e-01, lg2 = 3.999999999940941908e-01,
                   lg3 = 2.857142874366239149e-01, lg4 = 2.222219843214978396e-01,
                   lg5 = 1.818357216161805012e-01, lg6 = 1.531383769920937332e-01,
                   lg7 = 1.479819860511658591e-01;
  constexpr uint64_t kMantissa = (uint64_t{1} << 52) - 1, kOneBits = uint64_t{1023} << 52;
  const uint64_t bits = ToBits(x);
  // x = 2^e m with m in [1, 2); the biased exponent turned into a double exactly through the
  // 2^52 trick (no integer-to-double conversion, which SSE2 lacks for 64-bit lanes).
  double m = FromBits((bits & kMantissa) | kOneBits);
  double e = FromBits((bits >> 52) | (uint64_t{0x433} << 52)) - 0x1.0p52 - 1023.0;
  // m in [sqrt(2)/2, sqrt(2)), so that f = m - 1 is small.
  const bool high = m > 1.41421356237309504880;
  m = high ? 0.5 * m : m;
  e = high ? e + 1.0 : e;
  const double f = m - 1.0;
  const double s = f / (2.0 + f), z = s * s, w = z * z;
  const double t1 = w * (lg2 + w * (lg4 + w * lg6));
  const double t2 = z * (lg1 + w * (lg3 + w * (lg5 + w * lg7)));
  const double r = t2 + t1, hfsq = 0.5 * f * f;
  return e * ln2_hi - ((hfsq - (s * (hfsq + r) + e * ln2_lo)) - f);
}

// e^x for -708 <= x <= 709; smaller arguments give 0, larger ones +inf.
inline double Exp(double x) {
  using namespace detail;
  constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10,
                   inv_ln2 = 1.44269504088896338700e+00;
  constexpr double p1 = 1.66666666666666019037e-01, p2 = -2.77777777770155933842e-03,
                   p3 = 6.61375632143793436117e-05, p4 = -1.65339022054652515390e-06,
                   p5 = 4.13813679705723846039e-08;
  const double clamped = x < -708.0 ? -708.0 : (x > 709.0 ? 709.0 : x);
  const double k = RoundToInteger(clamped * inv_ln2);
  const double hi = clamped - k * ln2_hi, lo = k * ln2_lo, r = hi - lo;
  const double t = r * r;
  const double c = r - t * (p1 + t * (p2 + t * (p3 + t * (p4 + t * p5))));
  const double y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi);
  // y * 2^k with k in [-1022, 1023], as two exact powers of two so that no step overflows.
  const double k1 = RoundToInteger(0.5 * k), k2 = k - k1;
  const auto power = [](double e) {
    return FromBits(static_cast<uint64_t>(ToBits(e + kRoundShift + 1023.0) & 0x7FF) << 52);
  };
  const double result = y * power(k1) * power(k2);
  return x < -708.0 ? 0.0 : (x > 709.0 ? std::numeric_limits<double>::infinity() : result);
}

// sin(x) and cos(x) of one angle; full accuracy for |x| < 1.6e6, finite and deterministic
// beyond (the reduction then loses bits). NaN or infinite x gives NaN.
inline void SinCos(double x, double* sin_x, double* cos_x) {
  using namespace detail;
  uint64_t k = 0;
  const double r = ReduceHalfPi(x, &k);
  const double s = SinKernel(r), c = CosKernel(r);
  // Quadrant k mod 4: (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s).
  const uint64_t odd = uint64_t{0} - (k & 1);
  const uint64_t sin_sign = (k & 2) << 62, cos_sign = ((k + 1) & 2) << 62;
  *sin_x = FromBits(ToBits(Blend(odd, c, s)) ^ sin_sign);
  *cos_x = FromBits(ToBits(Blend(odd, s, c)) ^ cos_sign);
}

inline double Sin(double x) {
  double s, c;
  SinCos(x, &s, &c);
  return s;
}

inline double Cos(double x) {
  double s, c;
  SinCos(x, &s, &c);
  return c;
}

// The angle of (x, y) in [-pi, pi], with std::atan2's signs for zeros (atan2(+-0, -0) = +-pi,
// atan2(+-0, +0) = +-0). Finite arguments; NaN propagates.
inline double Atan2(double y, double x) {
  using namespace detail;
  constexpr double tan_pi_8 = 0.41421356237309503;
  constexpr double pio4_hi = 7.85398163397448278999e-01, pio4_lo = 3.06161699786838301793e-17;
  constexpr double pio2_hi = 1.57079632679489655800e+00, pio2_lo = 6.12323399573676603587e-17;
  constexpr double pi_hi = 3.14159265358979311600e+00, pi_lo = 1.22464679914735317720e-16;
  constexpr uint64_t kSign = uint64_t{1} << 63;
  const double ax = FromBits(ToBits(x) & ~kSign), ay = FromBits(ToBits(y) & ~kSign);
  const bool steep = ay > ax;
  const double num = steep ? ax : ay, den = steep ? ay : ax;
  const double a = den > 0.0 ? num / den : num;  // in [0, 1]; 0 / 0 -> 0
  // atan(a) = pi/4 + atan((a - 1) / (a + 1)) above tan(pi/8), where the kernel is less accurate.
  const bool upper = a > tan_pi_8;
  const double t = upper ? (a - 1.0) / (a + 1.0) : a;
  const double kernel = AtanKernel(t);
  const double small = upper ? pio4_hi + (kernel + pio4_lo) : kernel;  // atan(min / max)
  // The octant's correction in one step (one rounding), so that the axes come out exact:
  // pi/2 - small, pi/2 + small or pi - small for steep, steep and x < 0, and x < 0.
  const bool left = (ToBits(x) & kSign) != 0;  // x < 0 or x = -0
  const double base = steep ? pio2_hi : (left ? pi_hi : 0.0);
  const double tail = steep ? pio2_lo : (left ? pi_lo : 0.0);
  const bool add = steep && left;
  const double angle = !steep && !left ? small
                       : add           ? base + (small + tail)
                                       : base - (small - tail);
  return FromBits(ToBits(angle) | (ToBits(y) & kSign));
}

// Angle wrapping: x - 2 pi k in (-pi, pi] for the integer k that puts it there, where "pi" is
// the double nearest pi (so 2 pi is exact) and the result is exact, not rounded: x - 2 pi k is
// representable for every finite x (it is a multiple of the coarser of ulp(x) and 2^-47, the
// last bit of 2 pi, and smaller than 4), and both functions below compute it without a rounding
// error, so any correct implementation gives these bits. An angle already in range is returned
// unchanged (-0 included); -pi becomes pi.

// |x| below this: WrapAngleNear is exact.
inline constexpr double kWrapNearLimit = 0x1.0p24;

namespace detail {
constexpr double kTwoPi = 6.28318530717958647692;     // 0x1.921fb54442d18p+2, 50 significant bits
constexpr double kHalfTurn = 3.14159265358979323846;  // kTwoPi / 2 exactly
// kTwoPi in a 26-bit head and the 24-bit rest: k times either is exact for |k| < 2^22.
constexpr double kTwoPiHead =
    std::bit_cast<double>(std::bit_cast<uint64_t>(kTwoPi) & ~uint64_t{0x7FFFFFF});
constexpr double kTwoPiTail = kTwoPi - kTwoPiHead;
}  // namespace detail

// For |x| < kWrapNearLimit, branch-free (loops over it vectorise). k = round(x / 2 pi) is below
// 2^22, so k head and k tail are exact; x - k head is exact (both are multiples of ulp(x), and
// the difference is smaller than x); the second subtraction rounds a representable value, so it
// is exact too; the rounding of x / 2 pi can leave the result just past +-pi, fixed exactly.
inline double WrapAngleNear(double x) {
  using namespace detail;
  const double k = RoundToInteger(x * (1.0 / kTwoPi));
  const double r = (x - k * kTwoPiHead) - k * kTwoPiTail;
  const double below = r > kHalfTurn ? r - kTwoPi : r;
  return below <= -kHalfTurn ? below + kTwoPi : below;
}

// Any finite x (NaN for NaN and infinities), by integer long division: |x| = M 2^e with M a
// 53-bit integer and 2 pi = N 2^-47 with N a 50-bit integer, so |x| mod 2 pi is
// ((M 2^(e + 47)) mod N) 2^-47, computed 13 bits of shift at a time in 64-bit integers. Slow
// (up to 80 integer divisions); WrapAngle calls it only beyond kWrapNearLimit.
inline double WrapAngleFar(double x) {
  using namespace detail;
  if (!(x - x == 0.0)) return x - x;  // NaN, infinities
  if (x < kWrapNearLimit && x > -kWrapNearLimit) return WrapAngleNear(x);
  const uint64_t bits = ToBits(x);
  const uint64_t n = ((ToBits(kTwoPi) & ((uint64_t{1} << 52) - 1)) | (uint64_t{1} << 52)) >> 3;
  const int exponent = static_cast<int>((bits >> 52) & 0x7FF);  // >= 1047 here
  uint64_t remainder = ((bits & ((uint64_t{1} << 52) - 1)) | (uint64_t{1} << 52)) % n;
  for (int shift = exponent - 1075 + 47; shift > 0; shift -= 13) {
    remainder = (remainder << (shift < 13 ? shift : 13)) % n;
  }
  const double magnitude = static_cast<double>(remainder) * 0x1.0p-47;  // exact: < 2^50 units
  if ((bits >> 63) == 0) return magnitude > kHalfTurn ? magnitude - kTwoPi : magnitude;
  const double negative = 0.0 - magnitude;
  return negative <= -kHalfTurn ? negative + kTwoPi : negative;
}

// The one angle wrap of patlab: exact, in (-pi, pi], for every finite x.
inline double WrapAngle(double x) {
  return x < kWrapNearLimit && x > -kWrapNearLimit ? WrapAngleNear(x) : WrapAngleFar(x);
}

}  // namespace patlab::pmath
