#include "patlab/core/error.h"

#include <cstdio>
#include <cstdlib>

namespace patlab::detail {

void CheckFailed(const char* file, int line, const std::string& message) {
  std::fprintf(stderr, "patlab: internal check failed at %s:%d: %s\n", file, line, message.c_str());
  std::abort();
}

}  // namespace patlab::detail
