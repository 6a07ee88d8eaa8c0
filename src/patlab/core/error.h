// Errors, in the three tiers of docs/architecture.md rule 9:
//  1. bad input      -> InputError carrying "file:line: what is wrong; expected what", caught in
//  cli/
//                       and printed on stderr with exit status 2;
//  2. broken invariant -> PATLAB_CHECK / PATLAB_CHECK_OP, which print the operands and abort;
//  3. numerical outcome -> a status in the result (e.g. estimate::Summary), never an exception.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

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
