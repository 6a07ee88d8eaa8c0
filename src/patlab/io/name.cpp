#include "patlab/io/name.h"

#include "patlab/core/error.h"

namespace patlab::io {

std::string NameProblem(std::string_view name) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxNameBytes)
    return "is longer than " + std::to_string(kMaxNameBytes) + " bytes";
  for (const char c : name) {
    if (c == '/') return "holds '/'";
    if (c == '\\') return "holds '\\'";
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      return "holds a control character or NUL";
  }
  if (!IsValidUtf8(name)) return "is not valid UTF-8";
  return "";
}

void CheckName(std::string_view name, std::string_view what) {
  const std::string problem = NameProblem(name);
  if (problem.empty()) return;
  throw InputError(std::string(what) + " '" + EscapeForMessage(name) + "' " + problem +
                   "; expected " + kNameExpected);
}

}  // namespace patlab::io
