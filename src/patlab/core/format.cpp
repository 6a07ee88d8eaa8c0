#include "patlab/core/format.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>

namespace patlab {

std::string FormatNumber(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return FormatSignificant(value, 12);
}

std::string FormatSignificant(double value, int digits) {
  return StringPrintf("%.*g", digits, value);
}

std::string FormatFixed(double value, int decimals) {
  return StringPrintf("%.*f", decimals, value);
}

std::string FormatRoundTrip(double value) {
  std::string text;
  for (int digits = 15; digits <= 17; ++digits) {
    text = FormatSignificant(value, digits);
    if (std::strtod(text.c_str(), nullptr) == value) break;
  }
  return text;
}

std::string StringPrintf(const char* format, ...) {
  va_list args;
  va_start(args, format);
  va_list copy;
  va_copy(copy, args);
  char small[128];
  const int n = std::vsnprintf(small, sizeof small, format, args);
  va_end(args);
  std::string out;
  if (n < 0) {
    out.clear();
  } else if (static_cast<size_t>(n) < sizeof small) {
    out.assign(small, static_cast<size_t>(n));
  } else {
    out.resize(static_cast<size_t>(n));
    std::vsnprintf(out.data(), out.size() + 1, format, copy);
  }
  va_end(copy);
  return out;
}

}  // namespace patlab
