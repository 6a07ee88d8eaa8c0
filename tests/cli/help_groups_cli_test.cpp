// Every command's help in named option groups (src/cli/command_line.h, docs/cli.md), end to end:
// `patlab help CMD` = `patlab CMD --help`, no catch-all "options:" group, and every flag the help
// shows is one that `patlab completion bash` completes for that command, and the other way round.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../test_util.h"
#include "help_listing.h"

namespace patlab::cli {
namespace {

using testing::kPatlab;
using testing::RunCommand;

using help_listing::CommandNames;
using help_listing::Lines;

bool IsOptionLine(const std::string& line) {
  return std::regex_search(line, std::regex("^  (-\\w, |    )--[a-z0-9-]+"));
}

// The group titles of a help text, in order: a line "title:" followed by an option line.
std::vector<std::string> GroupTitles(const std::string& help) {
  const std::vector<std::string> lines = Lines(help);
  std::vector<std::string> titles;
  for (size_t k = 0; k + 1 < lines.size(); ++k) {
    if (!lines[k].empty() && lines[k].back() == ':' && IsOptionLine(lines[k + 1])) {
      titles.push_back(lines[k].substr(0, lines[k].size() - 1));
    }
  }
  return titles;
}

// Every flag the help shows, long and short.
std::set<std::string> HelpFlags(const std::string& help) {
  std::set<std::string> flags;
  const std::regex flag("^  (?:(-\\w), |    )(--[a-z0-9-]+)");
  for (const std::string& line : Lines(help)) {
    std::smatch m;
    if (!std::regex_search(line, m, flag)) continue;
    if (m[1].matched) flags.insert(m[1].str());
    flags.insert(m[2].str());
  }
  return flags;
}

// The flags `patlab completion bash` completes for `command`.
std::set<std::string> CompletionFlags(const std::string& script, const std::string& command) {
  for (const std::string& line : Lines(script)) {
    const std::string start = "    " + command + ") flags=\"";
    if (line.rfind(start, 0) != 0) continue;
    const std::string list = line.substr(start.size(), line.find('"', start.size()) - start.size());
    std::set<std::string> flags;
    std::istringstream words(list);
    for (std::string w; words >> w;) flags.insert(w);
    return flags;
  }
  return {};
}

TEST(HelpGroupsCli, EveryCommandsHelpHasNamedGroupsAndCompletionHasItsFlags) {
  const std::vector<std::string> commands = CommandNames();
  ASSERT_GE(commands.size(), 18u);
  const auto completion = RunCommand(kPatlab + " completion bash");
  ASSERT_EQ(completion.exit_code, 0) << completion.err;
  for (const std::string& command : commands) {
    SCOPED_TRACE(command);
    const auto help = RunCommand(kPatlab + " help " + command);
    ASSERT_EQ(help.exit_code, 0) << help.err;
    const auto flag = RunCommand(kPatlab + " " + command + " --help");
    ASSERT_EQ(flag.exit_code, 0) << flag.err;
    EXPECT_EQ(help.out, flag.out);
    const std::vector<std::string> titles = GroupTitles(help.out);
    // At least one named group, then help; a command whose one flag is --help (fields) has
    // the help group alone.
    const bool only_help = HelpFlags(help.out).size() <= 2;  // -h, --help
    ASSERT_GE(titles.size(), only_help ? 1u : 2u) << help.out;
    EXPECT_EQ(titles.back(), "help");
    EXPECT_EQ(std::count(titles.begin(), titles.end(), "options"), 0) << help.out;
    EXPECT_EQ(std::set<std::string>(titles.begin(), titles.end()).size(), titles.size())
        << help.out;
    EXPECT_EQ(HelpFlags(help.out), CompletionFlags(completion.out, command));
  }
}

// The groups of one command as chosen (src/cli/simulate_command.cpp): the tool-wide flags in
// "output" and "run", the noise flags together.
TEST(HelpGroupsCli, SimulatesGroupsHoldTheirFlags) {
  const auto r = RunCommand(kPatlab + " help simulate");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(GroupTitles(r.out),
            (std::vector<std::string>{"experiment", "noise model", "output", "run", "help"}));
  std::string group;
  std::map<std::string, std::string> group_of;
  const std::vector<std::string> lines = Lines(r.out);
  for (size_t k = 0; k < lines.size(); ++k) {
    if (k + 1 < lines.size() && !lines[k].empty() && lines[k].back() == ':' &&
        IsOptionLine(lines[k + 1])) {
      group = lines[k];
    } else if (IsOptionLine(lines[k])) {
      std::smatch m;
      std::regex_search(lines[k], m, std::regex("--[a-z0-9-]+"));
      group_of[m.str()] = group;
    }
  }
  EXPECT_EQ(group_of["--trials"], "experiment:");
  EXPECT_EQ(group_of["--sigma-y-ratio"], "noise model:");
  EXPECT_EQ(group_of["--outlier-sigma-ratio"], "noise model:");
  EXPECT_EQ(group_of["--out"], "output:");
  EXPECT_EQ(group_of["--name"], "output:");
  EXPECT_EQ(group_of["--threads"], "run:");
  EXPECT_EQ(group_of["--quiet"], "run:");
  EXPECT_EQ(group_of["--help"], "help:");
}

}  // namespace
}  // namespace patlab::cli
