#include "cli/command_line.h"

#include <algorithm>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "patlab/core/close_names.h"
#include "patlab/core/error.h"

namespace patlab::cli {

namespace po = boost::program_options;

namespace {

std::vector<std::string>* g_flag_sink = nullptr;

constexpr size_t kHelpWidth = 100;
constexpr size_t kFlagColumn = 30;

// `text` wrapped at kHelpWidth, continuation lines indented by `indent` columns; `first` is the
// column the first line starts at.
std::string Wrap(const std::string& text, size_t first, size_t indent) {
  std::istringstream words(text);
  std::string out, word;
  size_t column = first;
  bool line_start = true;
  while (words >> word) {
    if (!line_start && column + 1 + word.size() > kHelpWidth) {
      out += "\n" + std::string(indent, ' ');
      column = indent;
      line_start = true;
    }
    if (!line_start) {
      out += ' ';
      ++column;
    }
    out += word;
    column += word.size();
    line_start = false;
  }
  return out;
}

// An option whose value is an unsigned integer: Boost reads "-1" into it as the largest value
// (18446744073709551615), so Parse refuses a negative one first and the help says so.
template <typename... T>
bool IsAnyOf(const po::value_semantic* semantic) {
  return (... || (dynamic_cast<const po::typed_value<T>*>(semantic) != nullptr));
}
bool IsUnsigned(const po::option_description& option) {
  return IsAnyOf<unsigned char, unsigned short, unsigned int, unsigned long, unsigned long long>(
      option.semantic().get());
}
constexpr const char* kUnsignedExpected = "an integer >= 0";

// A negative value of an unsigned option: "--frame is '-1'; expected an integer >= 0".
void RefuseNegativeUnsigned(const po::parsed_options& parsed, const po::options_description& all) {
  for (const po::option& option : parsed.options) {
    if (option.unregistered || option.string_key.empty()) continue;
    const po::option_description* described = all.find_nothrow(option.string_key, false);
    if (described == nullptr || !IsUnsigned(*described)) continue;
    for (const std::string& value : option.value) {
      const size_t start = value.find_first_not_of(" \t");
      if (start == std::string::npos || value[start] != '-') continue;
      throw InputError("--" + described->long_name() + " is '" + EscapeForMessage(value) +
                       "'; expected " + kUnsignedExpected);
    }
  }
}

// "  -o, --out DIR" and "(default: results)" from one option.
std::pair<std::string, std::string> FlagAndDefault(const po::option_description& option) {
  std::string parameter = option.format_parameter();
  std::string fallback;
  if (const size_t open = parameter.find(" (="); open != std::string::npos) {
    fallback = parameter.substr(open + 3, parameter.size() - open - 4);
    parameter.resize(open);
  }
  if (parameter == "arg") parameter = "VALUE";
  const std::string short_name =
      option.canonical_display_name(po::command_line_style::allow_dash_for_short);
  std::string flag = "  ";
  flag += short_name.size() == 2 && short_name[0] == '-' ? short_name + ", " : "    ";
  flag += "--" + option.long_name();
  if (!parameter.empty()) flag += " " + parameter;
  return {flag, fallback};
}

void PrintGroup(const std::string& title, const po::options_description& group, std::ostream& os) {
  os << "\n" << title << ":\n";
  for (const auto& option : group.options()) {
    auto [flag, fallback] = FlagAndDefault(*option);
    std::string description = option->description();
    if (IsUnsigned(*option)) description += std::string(" (") + kUnsignedExpected + ")";
    if (!fallback.empty()) description += " (default: " + fallback + ")";
    if (flag.size() + 2 > kFlagColumn) {
      os << flag << "\n" << std::string(kFlagColumn, ' ');
    } else {
      os << flag << std::string(kFlagColumn - flag.size(), ' ');
    }
    os << Wrap(description, kFlagColumn, kFlagColumn) << "\n";
  }
}

}  // namespace

void CollectFlagsInto(std::vector<std::string>* sink) { g_flag_sink = sink; }

CommandLine::CommandLine(std::string command, CommandHelp help)
    : command_(std::move(command)), help_(help) {}

po::options_description_easy_init CommandLine::Group(const std::string& title) {
  for (auto& [name, group] : groups_) {
    if (name == title) return group->add_options();
  }
  groups_.emplace_back(title, std::make_unique<po::options_description>(title));
  return groups_.back().second->add_options();
}

void CommandLine::Add(const std::string& title,
                      const boost::shared_ptr<po::option_description>& option) {
  Group(title);
  for (auto& [name, group] : groups_) {
    if (name == title) group->add(option);
  }
}

namespace {

// The group of a tool-wide option that the command's groups do not list, or "".
std::string SharedGroup(const std::string& long_name) {
  if (long_name == "out" || long_name == "format") return "output";
  if (long_name == "quiet" || long_name == "threads" || long_name == "seed") return "run";
  return "";
}

}  // namespace

void CommandLine::AddGrouped(const po::options_description& options, const OptionGroups& groups) {
  std::vector<std::pair<std::string, std::string>> placed;  // long name, group title
  std::vector<std::string> titles;
  for (const auto& [title, names] : groups) titles.push_back(title);
  for (const auto& option : options.options()) {
    const std::string& name = option->long_name();
    if (name == "help") continue;
    std::string title;
    for (const auto& [group, names] : groups) {
      if (std::find(names.begin(), names.end(), name) != names.end()) title = group;
    }
    if (title.empty()) title = SharedGroup(name);
    if (title.empty()) {
      throw std::logic_error("patlab " + command_ + ": option --" + name + " is in no group");
    }
    placed.emplace_back(name, title);
  }
  // The shared groups after the command's own, output before run.
  for (const char* shared : {"output", "run"}) {
    const bool used = std::any_of(placed.begin(), placed.end(),
                                  [&](const auto& p) { return p.second == shared; });
    if (used && std::find(titles.begin(), titles.end(), shared) == titles.end()) {
      titles.emplace_back(shared);
    }
  }
  for (const std::string& title : titles) {
    for (const auto& option : options.options()) {
      for (const auto& [name, group] : placed) {
        if (name == option->long_name() && group == title) Add(title, option);
      }
    }
  }
}

void CommandLine::Positional(const char* name, po::value_semantic* value, int max_count) {
  positional_name_ = name;
  positional_.reset(value);
  positional_max_ = max_count;
}

void CommandLine::Removed(const std::string& flag, const std::string& replacement) {
  removed_.emplace_back(flag, replacement);
}

std::vector<std::string> CommandLine::Flags() const {
  std::vector<std::string> flags = {"--help", "-h"};
  for (const auto& [title, group] : groups_) {
    for (const auto& option : group->options()) {
      flags.push_back("--" + option->long_name());
      const std::string short_name =
          option->canonical_display_name(po::command_line_style::allow_dash_for_short);
      if (short_name.size() == 2 && short_name[0] == '-') flags.push_back(short_name);
    }
  }
  return flags;
}

std::string CommandLine::Help() const {
  std::ostringstream os;
  os << "usage: " << help_.usage << "\n";
  size_t start = 0;
  while (start < help_.description.size()) {
    size_t end = help_.description.find("\n\n", start);
    if (end == std::string::npos) end = help_.description.size();
    const std::string paragraph = help_.description.substr(start, end - start);
    // An indented paragraph (a list, a table) keeps its lines; prose is wrapped.
    if (paragraph.starts_with(" ") || paragraph.find("\n ") != std::string::npos) {
      os << "\n" << paragraph << "\n";
    } else if (paragraph.find_first_not_of(" \n") != std::string::npos) {
      os << "\n" << Wrap(paragraph, 0, 0) << "\n";
    }
    start = end + 2;
  }
  for (const auto& [title, group] : groups_) PrintGroup(title, *group, os);
  os << "\nhelp:\n  -h, --help" << std::string(kFlagColumn - 12, ' ')
     << "show this help (also: patlab help " << command_ << ")\n";
  os << "\nexamples:\n" << help_.examples;
  return os.str();
}

bool CommandLine::Parse(const std::vector<std::string>& args, po::variables_map* vm) {
  if (g_flag_sink != nullptr) {
    const std::vector<std::string> flags = Flags();
    g_flag_sink->insert(g_flag_sink->end(), flags.begin(), flags.end());
    return false;
  }
  po::options_description all;
  all.add_options()("help,h", "show this help");
  for (const auto& [title, group] : groups_) all.add(*group);
  po::positional_options_description positionals;
  if (positional_ != nullptr) {
    all.add_options()(positional_name_.c_str(), positional_.release());
    positionals.add(positional_name_.c_str(), positional_max_);
  }
  const int style = po::command_line_style::default_style & ~po::command_line_style::allow_guessing;
  po::parsed_options parsed(nullptr);
  try {
    parsed = po::command_line_parser(args).options(all).positional(positionals).style(style).run();
  } catch (const po::unknown_option& e) {
    const std::string flag = e.get_option_name();
    for (const auto& [old_flag, replacement] : removed_) {
      if (flag == old_flag) {
        throw InputError(flag + " was removed; expected " + replacement + " (docs/cli.md)");
      }
    }
    const std::vector<std::string> close = CloseNames(flag, Flags());
    throw InputError("unknown option " + EscapeForMessage(flag) +
                     (close.empty() ? "" : " (did you mean " + QuotedAlternatives(close) + "?)") +
                     "; expected an option that 'patlab help " + command_ + "' lists");
  }
  RefuseNegativeUnsigned(parsed, all);
  po::store(parsed, *vm);
  if (vm->count("help")) {
    std::cout << Help();
    return false;
  }
  po::notify(*vm);
  return true;
}

void AddOut(po::options_description_easy_init add, std::string* dir, const char* what) {
  add("out,o", po::value(dir)->value_name("DIR"), what);
}

void AddQuiet(po::options_description_easy_init add, bool* quiet) {
  add("quiet,q", po::bool_switch(quiet), "no progress or summary on stderr");
}

void AddThreads(po::options_description_easy_init add, int* threads) {
  add("threads,j", po::value(threads)->value_name("N"),
      "worker threads, 0 = all cores; results do not depend on it (default: 0)");
}

void AddSeed(po::options_description_easy_init add, std::string* seed, const char* what) {
  add("seed", po::value(seed)->value_name("N"), what);
}

void AddFormat(po::options_description_easy_init add, std::string* format, const char* choices) {
  add("format", po::value(format)->value_name("FORMAT")->default_value(*format),
      (std::string("what stdout gets: ") + choices).c_str());
}

void CheckFormat(const std::string& format, const char* choices) {
  std::istringstream list(choices);
  std::vector<std::string> names;
  for (std::string name; std::getline(list, name, '|');) {
    if (name == format) return;
    names.push_back(name);
  }
  // "csv or json", "table, csv or json"
  std::string expected;
  for (size_t k = 0; k < names.size(); ++k) {
    if (k > 0) expected += k + 1 == names.size() ? " or " : ", ";
    expected += names[k];
  }
  throw InputError("--format is '" + EscapeForMessage(format) + "'; expected " + expected);
}

}  // namespace patlab::cli
