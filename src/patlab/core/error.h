// Errors, in the three tiers of docs/architecture.md rule 9:
//  1. bad input      -> InputError carrying "file:line: what is wrong; expected what", caught in
//                       cli/ and printed on stderr with exit status 2; a failure of the
//                       environment rather than of the input (cannot write the results, out of
//                       memory) is an EnvironmentError, exit status 1;
//  2. broken invariant -> PATLAB_CHECK / PATLAB_CHECK_OP, which print the operands and abort;
//  3. numerical outcome -> a status in the result (e.g. estimate::Summary), never an exception.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

namespace patlab {

// Where in an input a problem was found. line == 0 means "the file as a whole".
struct FileLoc {
  std::string file;
  int line = 0;

  std::string ToString() const { return line > 0 ? file + ":" + std::to_string(line) : file; }
};

// Bad user input. what() is the complete message shown to the user.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
  InputError(const FileLoc& loc, const std::string& message)
      : std::runtime_error(loc.file.empty() ? message : loc.ToString() + ": " + message) {}
};

// A failure of the environment, not of the input: results cannot be written (permissions, disk
// full, a read-only file system). It is an InputError so that every caller that reports bad input
// reports it too, but the CLI exits with status 1 for it (docs/hardening.md).
class EnvironmentError : public InputError {
 public:
  using InputError::InputError;
};

// Throws InputError when `ec` (from a std::filesystem query on `path`) says the path itself is
// unusable: a component longer than the file system takes (ENAMETOOLONG) or a symbolic link loop
// (ELOOP), with the wording the tool's top-level handler uses; other codes return.
void ThrowIfPathUnusable(const std::string& path, const std::error_code& ec);

// User-supplied text quoted in a message (a cell, a flag value, a file name): bytes below 0x20,
// 0x7f and bytes that are not part of valid UTF-8 are written as \xNN, so a NUL cannot cut the
// message and a terminal sees no control codes; text longer than `max_bytes` is cut there and
// "... (N bytes)" says how long it was.
std::string EscapeForMessage(std::string_view text, size_t max_bytes = 120);

// True when `text` is well-formed UTF-8 (no overlong forms, surrogates or code points above
// U+10FFFF). Text that goes into a JSON result must be.
bool IsValidUtf8(std::string_view text);

namespace detail {
[[noreturn]] void CheckFailed(const char* file, int line, const std::string& message);
}  // namespace detail

}  // namespace patlab

#define PATLAB_CHECK(condition)                                                      \
  do {                                                                               \
    if (!(condition)) ::patlab::detail::CheckFailed(__FILE__, __LINE__, #condition); \
  } while (false)

#define PATLAB_CHECK_OP(a, op, b)                                                             \
  do {                                                                                        \
    const auto& patlab_check_a = (a);                                                         \
    const auto& patlab_check_b = (b);                                                         \
    if (!(patlab_check_a op patlab_check_b)) {                                                \
      std::ostringstream patlab_check_os;                                                     \
      patlab_check_os << #a " " #op " " #b " (" << patlab_check_a << " vs " << patlab_check_b \
                      << ")";                                                                 \
      ::patlab::detail::CheckFailed(__FILE__, __LINE__, patlab_check_os.str());               \
    }                                                                                         \
  } while (false)
