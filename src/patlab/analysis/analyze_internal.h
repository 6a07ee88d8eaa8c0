// Text helpers shared by the analyze pieces (analyze.cpp: the report; analyze_input.cpp: reading
// the track). Not installed.
#pragma once

#include <string>
#include <string_view>

#include "patlab/core/error.h"

namespace patlab::analysis::detail {

// Concatenation by append (GCC 12's -Wrestrict misfires on "literal" + std::string chains).
template <typename... Parts>
std::string Cat(const Parts&... parts) {
  std::string out;
  (out.append(parts), ...);
  return out;
}

// A name or value in a message: quoted, escaped and cut to 60 bytes.
inline std::string Quoted(std::string_view s) { return Cat("\"", EscapeForMessage(s, 60), "\""); }

}  // namespace patlab::analysis::detail
