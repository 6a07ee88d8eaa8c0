#include "patlab/core/error.h"

#include <cerrno>

#include <cstdio>
#include <cstdlib>

namespace patlab {

namespace {

// The length of the well-formed UTF-8 sequence at text[i], or 0 (RFC 3629 section 4, the
// table of well-formed byte sequences).
size_t Utf8SequenceLength(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  if (c < 0x80) return 1;
  size_t n = 0;
  unsigned char lo = 0x80, hi = 0xbf;
  if (c >= 0xc2 && c <= 0xdf) {
    n = 2;
  } else if (c >= 0xe0 && c <= 0xef) {
    n = 3;
    if (c == 0xe0) lo = 0xa0;
    if (c == 0xed) hi = 0x9f;
  } else if (c >= 0xf0 && c <= 0xf4) {
    n = 4;
    if (c == 0xf0) lo = 0x90;
    if (c == 0xf4) hi = 0x8f;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xbf) return 0;
  }
  return n;
}

}  // namespace

bool IsValidUtf8(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    const size_t n = Utf8SequenceLength(text, i);
    if (n == 0) return false;
    i += n;
  }
  return true;
}

std::string EscapeForMessage(std::string_view text, size_t max_bytes) {
  std::string out;
  const std::string_view shown = text.substr(0, std::min(text.size(), max_bytes));
  for (size_t i = 0; i < shown.size();) {
    const auto c = static_cast<unsigned char>(shown[i]);
    const size_t n = Utf8SequenceLength(shown, i);
    if (n == 0 || c < 0x20 || c == 0x7f) {
      char hex[5];
      std::snprintf(hex, sizeof(hex), "\\x%02x", c);
      out += hex;
      ++i;
    } else {
      out.append(shown.substr(i, n));
      i += n;
    }
  }
  if (shown.size() < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

namespace detail {

void CheckFailed(const char* file, int line, const std::string& message) {
  std::fprintf(stderr, "patlab: internal check failed at %s:%d: %s\n", file, line, message.c_str());
  std::abort();
}

}  // namespace detail
void ThrowIfPathUnusable(const std::string& path, const std::error_code& ec) {
  if (ec.value() == ENAMETOOLONG) {
    throw InputError(EscapeForMessage(path, 1024) + ": " + ec.message() +
                     "; expected a path whose every component is at most 255 bytes");
  }
  if (ec.value() == ELOOP) {
    throw InputError(EscapeForMessage(path, 1024) + ": " + ec.message() +
                     "; expected a path without a symbolic link loop");
  }
}

}  // namespace patlab
