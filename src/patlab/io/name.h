// Names that reach a file name or a results cell: pattern, class and label names, experiment
// names and every --name. One rule, checked once where the name is read: 1 to 200 bytes of
// UTF-8 without a path separator ('/' or '\'), control characters or NUL. So a name can neither
// leave the folder it is written into (`--name ../../x`), nor split a line of a CSV or a report,
// nor make the JSON writer throw on invalid UTF-8.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace patlab::io {

inline constexpr size_t kMaxNameBytes = 200;
// What a message expects of a name.
inline constexpr const char* kNameExpected =
    "a non-empty name of at most 200 bytes of UTF-8 without '/', '\\', control characters or NUL";

// "" when `name` follows the rule above, else what is wrong with it: "is empty", "is longer than
// 200 bytes", "holds '/'", "holds '\'", "holds a control character or NUL", "is not valid UTF-8".
std::string NameProblem(std::string_view name);

// Throws InputError "<what> '<name, escaped>' <problem>; expected <kNameExpected>" when
// NameProblem finds one; `what` names the flag or key ("--name", "pattern name").
void CheckName(std::string_view name, std::string_view what);

}  // namespace patlab::io
