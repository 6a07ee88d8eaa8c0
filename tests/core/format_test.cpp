// Tests of the one number formatter (src/patlab/core/format.h).
#include "patlab/core/format.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

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
  // Beyond the 128-byte stack buffer: the second vsnprintf pass must write it all.
  const std::string long_text(300, 'x');
  const std::string out = StringPrintf("<%s|%d>", long_text.c_str(), 42);
  EXPECT_EQ(out, "<" + long_text + "|42>");
  EXPECT_EQ(out.size(), 305u);
  // Exactly at the boundary: 127 characters fit the buffer with its terminator, 128 do not.
  EXPECT_EQ(StringPrintf("%s", std::string(127, 'y').c_str()), std::string(127, 'y'));
  EXPECT_EQ(StringPrintf("%s", std::string(128, 'z').c_str()), std::string(128, 'z'));
}

}  // namespace
}  // namespace patlab
