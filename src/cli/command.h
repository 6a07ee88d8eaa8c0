// Subcommand registry. Each subcommand lives in its own file in src/cli/ and registers itself:
//
//   int RunFoo(const std::vector<std::string>& args);  // args after "patlab foo"
//   PATLAB_REGISTER_COMMAND("foo", "one-line summary", RunFoo);
//
// A subcommand parses its flags with Boost.Program_options into a plain options struct, prints
// results on stdout and returns the exit status: 0 ok, 2 bad input or usage (kExitBadInput).
// It may throw patlab::InputError or boost::program_options::error: main() prints the message
// on stderr and exits with 2.
#pragma once

#include <string>
#include <vector>

namespace patlab::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;   // the run itself failed (e.g. cannot write results)
inline constexpr int kExitBadInput = 2;  // bad input or usage

using CommandFn = int (*)(const std::vector<std::string>& args);

struct Command {
  const char* name;
  const char* summary;
  CommandFn run;
};

bool RegisterCommand(const Command& command);
const std::vector<Command>& Commands();

}  // namespace patlab::cli

#define PATLAB_CLI_CONCAT_INNER(a, b) a##b
#define PATLAB_CLI_CONCAT(a, b) PATLAB_CLI_CONCAT_INNER(a, b)
#define PATLAB_REGISTER_COMMAND(name, summary, fn)                               \
  static const bool PATLAB_CLI_CONCAT(patlab_registered_command_, __COUNTER__) = \
      ::patlab::cli::RegisterCommand(::patlab::cli::Command{name, summary, fn})
