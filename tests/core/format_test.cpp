// Tests of the one number formatter (src/patlab/core/format.h).
#include "patlab/core/format.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <clocale>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace patlab {
namespace {

TEST(FormatNumber, TwelveSignificantDigitsAndNamesForNonFinite) {
  EXPECT_EQ(FormatNumber(65.0), "65");
  EXPECT_EQ(FormatNumber(2.5), "2.5");
  EXPECT_EQ(FormatNumber(-0.125), "-0.125");
  EXPECT_EQ(FormatNumber(1.0 / 3.0), "0.333333333333");
  EXPECT_EQ(FormatNumber(123456789012345.0), "1.23456789012e+14");
  EXPECT_EQ(FormatNumber(1e-7), "1e-07");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(FormatNumber(-std::numeric_limits<double>::quiet_NaN()), "nan");
  EXPECT_EQ(FormatNumber(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatNumber(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(FormatSignificant, IsPrintfG) {
  EXPECT_EQ(FormatSignificant(53.75, 4), "53.75");
  EXPECT_EQ(FormatSignificant(1789.8123, 5), "1789.8");
  EXPECT_EQ(FormatSignificant(0.000123456, 3), "0.000123");
  EXPECT_EQ(FormatSignificant(1234567.0, 3), "1.23e+06");
  EXPECT_EQ(FormatSignificant(120.0, 12), "120");
}

TEST(FormatFixed, IsPrintfF) {
  EXPECT_EQ(FormatFixed(0.12345, 4), "0.1235");  // 0.12345 is stored a little above
  EXPECT_EQ(FormatFixed(-2.0, 3), "-2.000");
  EXPECT_EQ(FormatFixed(2.5, 0), "2");  // round half to even, as printf does
  EXPECT_EQ(FormatFixed(1e6, 1), "1000000.0");
}

TEST(FormatRoundTrip, ShortestTextThatReadsBackExactly) {
  EXPECT_EQ(FormatRoundTrip(0.1), "0.1");
  EXPECT_EQ(FormatRoundTrip(0.5), "0.5");
  EXPECT_EQ(FormatRoundTrip(1.0 / 3.0), "0.3333333333333333");   // 16 digits
  EXPECT_EQ(FormatRoundTrip(0.1 + 0.2), "0.30000000000000004");  // 17 digits
  for (const double v : {0.1, 1.0 / 3.0, 0.1 + 0.2, 1e-300, DBL_MAX, -DBL_MIN, 4.9e-324, 2003.0}) {
    SCOPED_TRACE(v);
    const std::string text = FormatRoundTrip(v);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), v);
    EXPECT_LE(text.size(), 24u);
  }
  EXPECT_EQ(FormatRoundTrip(1e-300), "1e-300");
  EXPECT_EQ(FormatRoundTrip(DBL_MAX), "1.7976931348623157e+308");
}

TEST(StringPrintf, FormatsShortAndLongText) {
  EXPECT_EQ(StringPrintf("%s,%d,%.2f", "a", 7, 0.125), "a,7,0.12");
  EXPECT_EQ(StringPrintf("%s", ""), "");
  // Long text is written whole.
  const std::string long_text(300, 'x');
  const std::string out = StringPrintf("<%s|%d>", long_text.c_str(), 42);
  EXPECT_EQ(out, "<" + long_text + "|42>");
  EXPECT_EQ(out.size(), 305u);
  EXPECT_EQ(StringPrintf("%s", std::string(127, 'y').c_str()), std::string(127, 'y'));
  EXPECT_EQ(StringPrintf("%s", std::string(128, 'z').c_str()), std::string(128, 'z'));
}

// The values on which the to_chars formatter must give glibc printf's bytes: zeros, the extremes,
// subnormals, powers of ten and two, halves (exact binary ties for %.0f and %.1f), values just
// beside a decimal tie, and a pseudo-random spread over the whole exponent range.
std::vector<double> ProbeValues() {
  std::vector<double> v = {0.0,     -0.0,     1.0,      -1.0,     0.5,      1.5,       2.5,
                           -2.5,    0.125,    0.375,    1e-7,     1e-5,     1e-4,      9.5e-5,
                           1e15,    1e16,     1e17,     1e21,     1e22,     1e23,      123456.5,
                           0.1,     0.2,      0.3,      1.0 / 3,  2.0 / 3,  DBL_MAX,   -DBL_MAX,
                           DBL_MIN, -DBL_MIN, 4.9e-324, 2.2e-308, 999999.5, 9.9999995, 0.05,
                           0.15,    0.25,     0.35,     1.005,    2.675,    1.45,      8.345};
  for (int e = -320; e <= 308; e += 7) {
    v.push_back(std::pow(10.0, e));
    v.push_back(-std::pow(10.0, e) * 1.2345678901234567);
  }
  for (int e = -60; e <= 60; ++e) v.push_back(std::ldexp(1.0, e) * 3.0);
  for (int k = 0; k < 4000; ++k) {  // halves near ties at many magnitudes
    const double base = (k % 2000) + 0.5;
    v.push_back(std::nextafter(base / std::pow(10.0, k % 9), 0.0));
    v.push_back(base / std::pow(10.0, k % 9));
    v.push_back(std::nextafter(base / std::pow(10.0, k % 9), 1e300));
  }
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (int k = 0; k < 20000; ++k) {  // random bit patterns: every exponent, every mantissa
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    double d = 0.0;
    std::memcpy(&d, &state, sizeof d);
    if (std::isfinite(d)) v.push_back(d);
  }
  return v;
}

// glibc printf "%.*g" or "%.*f" (in the test's "C" locale).
std::string Printf(std::string_view format, int precision, double value) {
  char buffer[1024];
  if (format == "%.*g") {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.*f", precision, value);
  }
  return buffer;
}

TEST(FormatSignificant, EqualsGlibcPrintfOnManyValues) {
  for (const double v : ProbeValues()) {
    for (const int digits : {1, 2, 3, 4, 6, 9, 12, 15, 16, 17, 20}) {
      ASSERT_EQ(FormatSignificant(v, digits), Printf("%.*g", digits, v)) << v << " " << digits;
    }
  }
}

TEST(FormatFixed, EqualsGlibcPrintfOnManyValues) {
  for (const double v : ProbeValues()) {
    if (std::fabs(v) > 1e30) continue;  // hundreds of integer digits: covered below
    for (const int decimals : {0, 1, 2, 3, 4, 6, 9, 12}) {
      ASSERT_EQ(FormatFixed(v, decimals), Printf("%.*f", decimals, v)) << v << " " << decimals;
    }
  }
  EXPECT_EQ(FormatFixed(DBL_MAX, 2), Printf("%.*f", 2, DBL_MAX));
  EXPECT_EQ(FormatFixed(4.9e-324, 330), Printf("%.*f", 330, 4.9e-324));
}

// The previous implementation: the shortest of printf %.15g..%.17g that strtod reads back.
std::string PrintfRoundTrip(double value) {
  std::string text;
  for (int digits = 15; digits <= 17; ++digits) {
    text = Printf("%.*g", digits, value);
    if (std::strtod(text.c_str(), nullptr) == value) break;
  }
  return text;
}

TEST(FormatRoundTrip, EqualsThePrintfLoopOnManyValues) {
  for (const double v : ProbeValues()) ASSERT_EQ(FormatRoundTrip(v), PrintfRoundTrip(v)) << v;
}

TEST(Format, NonFiniteAsPrintf) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double v : {nan, -nan, inf, -inf}) {
    EXPECT_EQ(FormatSignificant(v, 6), Printf("%.*g", 6, v));
    EXPECT_EQ(FormatFixed(v, 3), Printf("%.*f", 3, v));
    EXPECT_EQ(FormatRoundTrip(v), PrintfRoundTrip(v));
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "[%8.3f|%-8g|%+e|%E|%G]", v, v, v, v, v);
    EXPECT_EQ(StringPrintf("[%8.3f|%-8g|%+e|%E|%G]", v, v, v, v, v), buffer);
  }
}

// Every conversion patlab's format strings use, with flags, widths and precisions.
TEST(StringPrintf, EqualsGlibcPrintf) {
  char buffer[512];
  for (const double v : {0.0, -0.0, 1.5, -2.25, 1234.5678, 1e-9, -3e12, 0.000123456}) {
    std::snprintf(buffer, sizeof buffer,
                  "%.3f|%-9.4f|%10.3f|%010.2f|%+.1f|% .2e|%.3e|%.6g|%-14.4f|%.0f|%12.5g|%G|%f|%e",
                  v, v, v, v, v, v, v, v, v, v, v, v, v, v);
    EXPECT_EQ(StringPrintf(
                  "%.3f|%-9.4f|%10.3f|%010.2f|%+.1f|% .2e|%.3e|%.6g|%-14.4f|%.0f|%12.5g|%G|%f|%e",
                  v, v, v, v, v, v, v, v, v, v, v, v, v, v),
              buffer);
  }
  for (const long long n : {0LL, 7LL, -42LL, 1234567890123LL, -9223372036854775807LL}) {
    std::snprintf(buffer, sizeof buffer, "%lld|%-8lld|%08lld|%+lld|% lld|%.5lld|%llx|%016llx|%llX",
                  n, n, n, n, n, n, static_cast<unsigned long long>(n),
                  static_cast<unsigned long long>(n), static_cast<unsigned long long>(n));
    EXPECT_EQ(StringPrintf("%lld|%-8lld|%08lld|%+lld|% lld|%.5lld|%llx|%016llx|%llX", n, n, n, n, n,
                           n, static_cast<unsigned long long>(n),
                           static_cast<unsigned long long>(n), static_cast<unsigned long long>(n)),
              buffer);
  }
  const size_t z = 123;
  std::snprintf(buffer, sizeof buffer,
                "%d|%-5d|%4d|%u|%ld|%9ld|%zu|%8zu|%-5zu|%02x|%o|%c|%%|%5s|"
                "%-6s|%.2s|%*d|%-*d|%.*f",
                -5, 3, 12, 4000000000u, -7L, 99L, z, z, z, 10, 8, 'q', "ab", "cd", "xyz", 6, 1, 6,
                2, 3, 2.5);
  EXPECT_EQ(StringPrintf("%d|%-5d|%4d|%u|%ld|%9ld|%zu|%8zu|%-5zu|%02x|%o|%c|%%|%5s|%-6s|%.2s|%*d|"
                         "%-*d|%.*f",
                         -5, 3, 12, 4000000000u, -7L, 99L, z, z, z, 10, 8, 'q', "ab", "cd", "xyz",
                         6, 1, 6, 2, 3, 2.5),
            buffer);
}

// A program that calls setlocale(LC_ALL, "") under LANG=de_DE.UTF-8 gets printf's "1,5"; patlab's
// text stays "1.5". Skips only when the German locale is not installed (scripts/setup.sh makes it).
TEST(Format, SameTextUnderAGermanLocale) {
  const std::string c_text = FormatSignificant(1.5, 6) + FormatFixed(-2.25, 3) +
                             FormatRoundTrip(0.1) + StringPrintf("%.2f %g %e", 3.5, 1e-7, 2.0);
  const std::string saved = std::setlocale(LC_ALL, nullptr);
  if (std::setlocale(LC_ALL, "de_DE.UTF-8") == nullptr) {
    GTEST_SKIP() << "locale de_DE.UTF-8 is not installed (scripts/setup.sh generates it)";
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", 1.5);
  const std::string printf_text = buffer;
  const std::string german_text = FormatSignificant(1.5, 6) + FormatFixed(-2.25, 3) +
                                  FormatRoundTrip(0.1) + StringPrintf("%.2f %g %e", 3.5, 1e-7, 2.0);
  std::setlocale(LC_ALL, saved.c_str());
  EXPECT_EQ(printf_text, "1,5");  // the locale is really in force
  EXPECT_EQ(german_text, c_text);
  EXPECT_EQ(c_text, "1.5-2.2500.13.50 1e-07 2.000000e+00");
}

}  // namespace
}  // namespace patlab
