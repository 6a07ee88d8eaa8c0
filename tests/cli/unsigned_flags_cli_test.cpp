// Every unsigned option of every command refuses a negative value, naming the flag, the value and
// what is expected (src/cli/command_line.cpp): Boost.Program_options reads "-1" into an unsigned
// option as 18446744073709551615. The options are found in each command's help, which marks
// every unsigned option "(an integer >= 0)" from its type, so no list here can go stale.
#include <gtest/gtest.h>

#include <algorithm>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../test_util.h"
#include "help_listing.h"

namespace patlab::cli {
namespace {

using testing::kPatlab;
using testing::RunCommand;

using help_listing::CommandNames;
using help_listing::Lines;

// (command, --flag) of every option whose help, continuation lines joined, says it takes an
// integer >= 0 by its type.
std::vector<std::pair<std::string, std::string>> UnsignedOptions() {
  const std::regex option_line("^  (-\\w, |    )(--[a-z0-9-]+)");
  std::vector<std::pair<std::string, std::string>> found;
  for (const std::string& command : CommandNames()) {
    std::string flag, text;
    const auto finish = [&] {
      if (!flag.empty() && text.find("(an integer >= 0)") != std::string::npos) {
        found.emplace_back(command, flag);
      }
      flag.clear();
      text.clear();
    };
    for (const std::string& line : Lines(RunCommand(kPatlab + " help " + command).out)) {
      std::smatch m;
      if (std::regex_search(line, m, option_line)) {
        finish();
        flag = m[2];
        text = line;
      } else if (!flag.empty() && line.rfind(std::string(30, ' '), 0) == 0) {
        text.append(" ").append(line, 30);
      } else {
        finish();
      }
    }
    finish();
  }
  return found;
}

TEST(UnsignedFlagsCli, EveryUnsignedOptionOfEveryCommandRefusesANegativeValue) {
  const std::vector<std::pair<std::string, std::string>> options = UnsignedOptions();
  // The walk finds them: render's frame identity is one (a uint64_t).
  EXPECT_NE(std::find(options.begin(), options.end(),
                      std::pair<std::string, std::string>{"render", "--frame"}),
            options.end());
  for (const auto& [command, flag] : options) {
    testing::TempDir dir;  // an empty working directory: nothing may be written
    const std::string run = std::string("cd ").append(dir.Path()).append(" && ").append(kPatlab);
    for (const std::string& form : {flag + " -1", flag + "=-1", flag + " ' -1'"}) {
      const auto r = RunCommand(run + " " + command + " " + form);
      EXPECT_EQ(r.exit_code, 2) << command << " " << form << "\n" << r.err;
      const std::string value = form.find("' -1'") != std::string::npos ? " -1" : "-1";
      std::string expected = std::string("patlab ").append(command).append(": ").append(flag);
      expected.append(" is '").append(value).append("'; expected an integer >= 0\n");
      EXPECT_EQ(r.err, expected) << command << " " << form;
      EXPECT_EQ(r.out, "");
    }
    // Zero is a value like any other: the refusal is of the sign, not of the option.
    const auto zero = RunCommand(run + " " + command + " " + flag + " 0");
    EXPECT_EQ(zero.err.find("expected an integer >= 0"), std::string::npos) << zero.err;
  }
}

}  // namespace
}  // namespace patlab::cli
