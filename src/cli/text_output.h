// Text output shared by the subcommands that print padded tables.
#pragma once

#include <string>

namespace patlab::cli {

// `text` with the spaces before each newline removed: tables padded with std::setw end their
// lines without trailing blanks.
std::string TrimLineEnds(const std::string& text);

}  // namespace patlab::cli
