#include "patlab/core/format.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <system_error>

#include "patlab/core/error.h"

// Every conversion goes through std::to_chars and std::from_chars, which use the "C" locale's
// forms whatever setlocale() says: a decimal point, never a comma (docs/architecture.md,
// "Numbers as text"). std::to_chars with a precision is specified as printf in the "C" locale, and
// libstdc++'s is exact (no double rounding), as glibc's printf is: the same bytes.

namespace patlab {

namespace {

// Up to a double's whole 309 integer digits plus the requested decimals.
constexpr int kMaxPrecision = 400;

std::string ToChars(double value, std::chars_format fmt, int precision) {
  if (precision < 0) precision = 6;  // printf: a negative precision is taken as omitted
  PATLAB_CHECK(precision <= kMaxPrecision);
  std::array<char, 720> buffer;
  const auto [end, ec] =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), value, fmt, precision);
  PATLAB_CHECK(ec == std::errc());
  return std::string(buffer.data(), end);
}

bool ReadsBackAs(const std::string& text, double value) {
  double back = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), back);
  return ec == std::errc() && end == text.data() + text.size() && back == value;
}

// One printf conversion specification: %[flags][width][.precision][length]conversion.
struct Spec {
  bool left = false, plus = false, space = false, zero = false;
  int width = 0;
  int precision = -1;       // -1: none given
  std::string_view length;  // "", "hh", "h", "l", "ll", "z", "j", "t", "L"
  char conversion = 0;
};

const char* ParseSpec(const char* p, Spec* spec, va_list* args) {
  for (;; ++p) {
    if (*p == '-')
      spec->left = true;
    else if (*p == '+')
      spec->plus = true;
    else if (*p == ' ')
      spec->space = true;
    else if (*p == '0')
      spec->zero = true;
    else
      break;
  }
  PATLAB_CHECK(*p != '#');  // the alternative forms are not used
  if (*p == '*') {
    spec->width = va_arg(*args, int);
    if (spec->width < 0) {
      spec->left = true;
      spec->width = -spec->width;
    }
    ++p;
  }
  for (; *p >= '0' && *p <= '9'; ++p) spec->width = spec->width * 10 + (*p - '0');
  if (*p == '.') {
    ++p;
    spec->precision = 0;
    if (*p == '*') {
      spec->precision = va_arg(*args, int);
      if (spec->precision < 0) spec->precision = -1;
      ++p;
    }
    for (; *p >= '0' && *p <= '9'; ++p) spec->precision = spec->precision * 10 + (*p - '0');
  }
  const char* start = p;
  while (*p == 'h' || *p == 'l' || *p == 'z' || *p == 'j' || *p == 't' || *p == 'L') ++p;
  spec->length = std::string_view(start, static_cast<size_t>(p - start));
  spec->conversion = *p;
  PATLAB_CHECK(*p != '\0');
  return p + 1;
}

intmax_t SignedArg(const Spec& s, va_list* args) {
  if (s.length == "l") return va_arg(*args, long);
  if (s.length == "ll") return va_arg(*args, long long);
  if (s.length == "z" || s.length == "t") return va_arg(*args, std::ptrdiff_t);
  if (s.length == "j") return va_arg(*args, intmax_t);
  const int v = va_arg(*args, int);
  if (s.length == "hh") return static_cast<signed char>(v);
  if (s.length == "h") return static_cast<short>(v);
  return v;
}

uintmax_t UnsignedArg(const Spec& s, va_list* args) {
  if (s.length == "l") return va_arg(*args, unsigned long);
  if (s.length == "ll") return va_arg(*args, unsigned long long);
  if (s.length == "z" || s.length == "t") return va_arg(*args, size_t);
  if (s.length == "j") return va_arg(*args, uintmax_t);
  const unsigned v = va_arg(*args, unsigned);
  if (s.length == "hh") return static_cast<unsigned char>(v);
  if (s.length == "h") return static_cast<unsigned short>(v);
  return v;
}

// `sign` + `digits` padded to the width: zeros after the sign, or blanks on either side.
void Pad(const Spec& s, std::string_view sign, std::string_view digits, bool zero_ok,
         std::string* out) {
  const size_t used = sign.size() + digits.size();
  const size_t fill =
      s.width > 0 && static_cast<size_t>(s.width) > used ? static_cast<size_t>(s.width) - used : 0;
  if (s.left) {
    out->append(sign).append(digits).append(fill, ' ');
  } else if (s.zero && zero_ok) {
    out->append(sign).append(fill, '0').append(digits);
  } else {
    out->append(fill, ' ').append(sign).append(digits);
  }
}

void AppendInteger(const Spec& s, va_list* args, std::string* out) {
  const char c = s.conversion;
  std::string_view sign;
  uintmax_t magnitude = 0;
  if (c == 'd' || c == 'i') {
    const intmax_t v = SignedArg(s, args);
    magnitude = v < 0 ? uintmax_t{0} - static_cast<uintmax_t>(v) : static_cast<uintmax_t>(v);
    sign = v < 0 ? "-" : s.plus ? "+" : s.space ? " " : "";
  } else {
    magnitude = UnsignedArg(s, args);
  }
  const int base = c == 'x' || c == 'X' ? 16 : c == 'o' ? 8 : 10;
  std::array<char, 80> buffer;
  const auto [end, ec] =
      std::to_chars(buffer.data(), buffer.data() + buffer.size(), magnitude, base);
  std::string digits(buffer.data(), end);
  if (c == 'X') {
    for (char& d : digits) d = static_cast<char>(d >= 'a' && d <= 'f' ? d - 'a' + 'A' : d);
  }
  if (s.precision >= 0) {
    if (s.precision == 0 && magnitude == 0) digits.clear();
    if (digits.size() < static_cast<size_t>(s.precision)) {
      digits.insert(0, static_cast<size_t>(s.precision) - digits.size(), '0');
    }
  }
  Pad(s, sign, digits, s.precision < 0, out);
}

void AppendFloat(const Spec& s, va_list* args, std::string* out) {
  const double v =
      s.length == "L" ? static_cast<double>(va_arg(*args, long double)) : va_arg(*args, double);
  const char lower = static_cast<char>(s.conversion | 0x20);
  const std::chars_format fmt = lower == 'f'   ? std::chars_format::fixed
                                : lower == 'e' ? std::chars_format::scientific
                                               : std::chars_format::general;
  PATLAB_CHECK(lower == 'f' || lower == 'e' || lower == 'g');
  std::string text = ToChars(std::fabs(v), fmt, s.precision < 0 ? 6 : s.precision);
  if (s.conversion != lower) {
    for (char& ch : text) ch = static_cast<char>(ch >= 'a' && ch <= 'z' ? ch - 'a' + 'A' : ch);
  }
  const std::string_view sign = std::signbit(v) ? "-" : s.plus ? "+" : s.space ? " " : "";
  Pad(s, sign, text, std::isfinite(v), out);
}

void AppendConversion(const Spec& s, va_list* args, std::string* out) {
  switch (s.conversion) {
    case '%':
      out->push_back('%');
      return;
    case 'c': {
      const char ch = static_cast<char>(va_arg(*args, int));
      Pad(s, "", std::string_view(&ch, 1), false, out);
      return;
    }
    case 's': {
      const char* text = va_arg(*args, const char*);
      std::string_view view = text == nullptr ? "(null)" : text;
      if (s.precision >= 0 && view.size() > static_cast<size_t>(s.precision)) {
        view = view.substr(0, static_cast<size_t>(s.precision));
      }
      Pad(s, "", view, false, out);
      return;
    }
    case 'd':
    case 'i':
    case 'u':
    case 'x':
    case 'X':
    case 'o':
      AppendInteger(s, args, out);
      return;
    default:
      AppendFloat(s, args, out);
  }
}

}  // namespace

std::string FormatNumber(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return FormatSignificant(value, 12);
}

std::string FormatSignificant(double value, int digits) {
  return ToChars(value, std::chars_format::general, digits);
}

std::string FormatFixed(double value, int decimals) {
  return ToChars(value, std::chars_format::fixed, decimals);
}

std::string FormatRoundTrip(double value) {
  std::string text;
  for (int digits = 15; digits <= 17; ++digits) {
    text = FormatSignificant(value, digits);
    if (ReadsBackAs(text, value)) break;
  }
  return text;
}

std::string StringPrintf(const char* format, ...) {
  va_list args;
  va_start(args, format);
  std::string out;
  for (const char* p = format; *p != '\0';) {
    if (*p != '%') {
      const char* next = p;
      while (*next != '\0' && *next != '%') ++next;
      out.append(p, static_cast<size_t>(next - p));
      p = next;
      continue;
    }
    Spec spec;
    p = ParseSpec(p + 1, &spec, &args);
    AppendConversion(spec, &args, &out);
  }
  va_end(args);
  return out;
}

}  // namespace patlab
