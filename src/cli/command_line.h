// The one command-line layer of the subcommands (docs/cli.md): options in named groups over
// Boost.Program_options, one help format (`patlab help COMMAND` = `patlab COMMAND --help`: usage,
// description, the groups, examples), "did you mean" for a misspelt flag, clear errors for
// removed flags, and the flag list that `patlab completion bash` prints.
#pragma once

#include <boost/program_options.hpp>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace patlab::cli {

// A command's option groups, in print order: a title ("input", "noise model") and the long names
// of its options. The tool-wide options need not be listed: --out and --format go to "output",
// --quiet, --threads and --seed to "run" (after the listed groups, unless listed themselves).
using OptionGroups = std::vector<std::pair<std::string, std::vector<std::string>>>;

struct CommandHelp {
  std::string usage;        // after "usage: ", e.g. "patlab simulate EXPERIMENT [options]"
  std::string description;  // paragraphs, each wrapped at 100 columns
  std::string examples;     // "  patlab ..." lines, an optional "# comment" after each
};

class CommandLine {
 public:
  CommandLine(std::string command, CommandHelp help);
  CommandLine(const CommandLine&) = delete;
  CommandLine& operator=(const CommandLine&) = delete;

  // Adds options to the group `title` (made on first use; groups print in that order).
  boost::program_options::options_description_easy_init Group(const std::string& title);
  // Adds an option made elsewhere to the group `title`.
  void Add(const std::string& title,
           const boost::shared_ptr<boost::program_options::option_description>& option);
  // Adds every option of `options` (but --help) to its group in `groups`. An option in no group
  // is a programming error (std::logic_error), so every command's help has only named groups.
  void AddGrouped(const boost::program_options::options_description& options,
                  const OptionGroups& groups);
  // Positional arguments stored into `value` (at most `max_count`; -1 = any number).
  void Positional(const char* name, boost::program_options::value_semantic* value, int max_count);
  // A flag that no longer exists: using it is an error that names its replacement.
  void Removed(const std::string& flag, const std::string& replacement);

  // Parses `args`. false when the command has nothing more to do: --help printed the help on
  // stdout, or `patlab completion` is collecting flag names. Unknown flags throw InputError with
  // the close names; other Program_options errors propagate (main() reports them, exit 2).
  bool Parse(const std::vector<std::string>& args, boost::program_options::variables_map* vm);

  std::string Help() const;
  // Every flag, long ("--out") and short ("-o").
  std::vector<std::string> Flags() const;

 private:
  std::string command_;
  CommandHelp help_;
  std::vector<std::pair<std::string, std::unique_ptr<boost::program_options::options_description>>>
      groups_;
  std::vector<std::pair<std::string, std::string>> removed_;
  std::string positional_name_;
  // Owned until Parse hands it to the options it parses with (which then own it).
  std::unique_ptr<boost::program_options::value_semantic> positional_;
  int positional_max_ = 0;
};

// `patlab completion` collects every command's flags by running it with this set: Parse() then
// stores the flags here and returns false.
void CollectFlagsInto(std::vector<std::string>* sink);

// The tool-wide options, one meaning each (docs/cli.md). Each adds one flag to `group`.
void AddOut(boost::program_options::options_description_easy_init add, std::string* dir,
            const char* what);
void AddQuiet(boost::program_options::options_description_easy_init add, bool* quiet);
void AddThreads(boost::program_options::options_description_easy_init add, int* threads);
void AddSeed(boost::program_options::options_description_easy_init add, std::string* seed,
             const char* what);
void AddFormat(boost::program_options::options_description_easy_init add, std::string* format,
               const char* choices);

// --format's value, checked against the command's choices ("table|json").
void CheckFormat(const std::string& format, const char* choices);

}  // namespace patlab::cli
