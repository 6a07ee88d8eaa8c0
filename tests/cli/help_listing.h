// What `patlab help` lists, for the tests that walk every command's options
// (help_groups_cli_test.cpp, unsigned_flags_cli_test.cpp).
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "../test_util.h"

namespace patlab::cli::help_listing {

inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The command names `patlab help` lists under "commands:".
inline std::vector<std::string> CommandNames() {
  std::vector<std::string> names;
  bool listing = false;
  for (const std::string& line : Lines(testing::RunCommand(testing::kPatlab + " help").out)) {
    if (line == "commands:") {
      listing = true;
    } else if (listing && line.rfind("  ", 0) == 0) {
      names.push_back(line.substr(2, line.find(' ', 2) - 2));
    } else if (listing) {
      break;
    }
  }
  return names;
}

}  // namespace patlab::cli::help_listing
