#include "cli/text_output.h"

namespace patlab::cli {

std::string TrimLineEnds(const std::string& text) {
  std::string trimmed;
  trimmed.reserve(text.size());
  for (char ch : text) {
    if (ch == '\n') {
      while (!trimmed.empty() && trimmed.back() == ' ') trimmed.pop_back();
    }
    trimmed += ch;
  }
  return trimmed;
}

}  // namespace patlab::cli
