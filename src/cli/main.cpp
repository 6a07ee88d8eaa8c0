// patlab: the command-line front end. Dispatches to the registered subcommands and is the one
// top-level handler: every exception becomes a message on stderr and an exit status, 2 for bad
// input and 1 for the environment (docs/architecture.md rule 9, docs/hardening.md). No exception
// type leaves main.
#include <malloc.h>

#include <boost/program_options/errors.hpp>
#include <cerrno>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "cli/build_info.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "patlab/core/close_names.h"
#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"

namespace patlab::cli {

std::vector<Command>& MutableCommands() {
  static std::vector<Command> commands;
  return commands;
}

bool RegisterCommand(const Command& command) {
  MutableCommands().push_back(command);
  return true;
}

const std::vector<Command>& Commands() { return MutableCommands(); }

namespace {

void PrintUsage(std::ostream& os) {
  os << "patlab " PATLAB_VERSION
        " - design, evaluate and detect planar colour-patch fiducial patterns\n\n"
        "usage: patlab COMMAND [options]     patlab help COMMAND (= patlab COMMAND --help)\n"
        "       patlab --version             patlab completion bash\n\n"
        "commands:\n";
  for (const Command& c : Commands()) {
    std::string name = c.name;
    name.resize(std::max<size_t>(name.size() + 2, 12), ' ');
    os << "  " << name << c.summary << "\n";
  }
  os << "\nShipped patterns, experiments and settings are found by name (patlab simulate fig5);\n"
        "docs/cli.md describes the options every command shares.\n";
}

void PrintVersion() {
  std::cout << "patlab " PATLAB_VERSION "\ncompiler: " PATLAB_BUILD_COMPILER
               "\nbuild type: " PATLAB_BUILD_TYPE "\nflags: " PATLAB_BUILD_FLAGS "\n";
}

std::vector<std::string> CommandNames() {
  std::vector<std::string> names;
  for (const Command& c : Commands()) names.emplace_back(c.name);
  return names;
}

const Command* FindCommand(const std::string& name) {
  for (const Command& c : Commands()) {
    if (name == c.name) return &c;
  }
  return nullptr;
}

int UnknownCommand(const std::string& name) {
  const std::vector<std::string> close = CloseNames(name, CommandNames());
  std::cerr << "patlab: unknown command '" << patlab::EscapeForMessage(name) << "'"
            << (close.empty() ? "" : " (did you mean " + QuotedAlternatives(close) + "?)")
            << "; expected one of the commands that 'patlab help' lists\n";
  return kExitBadInput;
}

// patlab completion bash: commands, each command's flags (collected by running each command's
// CommandLine in collecting mode), and file names for everything else.
int PrintCompletion(const std::vector<std::string>& args) {
  if (args.size() != 1 || args[0] != "bash") {
    std::cerr << "patlab completion: expected 'patlab completion bash'\n";
    return kExitBadInput;
  }
  std::string commands = "help completion --help --version";
  std::string cases;
  for (const Command& c : Commands()) {
    commands += std::string(" ") + c.name;
    std::vector<std::string> flags;
    CollectFlagsInto(&flags);
    c.run({});
    CollectFlagsInto(nullptr);
    std::string list;
    for (const std::string& f : flags) list += (list.empty() ? "" : " ") + f;
    cases += std::string("    ") + c.name + ") flags=\"" + list + "\" ;;\n";
  }
  std::cout << "# bash completion for patlab (made by 'patlab completion bash')\n"
               "_patlab() {\n"
               "  local cur=${COMP_WORDS[COMP_CWORD]} flags=\"\"\n"
               "  if (( COMP_CWORD == 1 )); then\n"
               "    COMPREPLY=($(compgen -W \""
            << commands
            << "\" -- \"$cur\"))\n"
               "    return\n"
               "  fi\n"
               "  case ${COMP_WORDS[1]} in\n"
               "    help) COMPREPLY=($(compgen -W \""
            << commands << "\" -- \"$cur\")); return ;;\n"
            << cases
            << "  esac\n"
               "  if [[ $cur == -* ]]; then\n"
               "    COMPREPLY=($(compgen -W \"$flags\" -- \"$cur\"))\n"
               "  fi\n"
               "}\n"
               "complete -o default -o bashdefault -F _patlab patlab\n";
  return kExitOk;
}

// A filesystem error is bad input when the path itself is at fault (too long, a symbolic link
// loop, not there, a file where a directory is needed), else the environment's.
int ReportFilesystemError(const std::string& name, const std::filesystem::filesystem_error& e) {
  const int code = e.code().value();
  const std::string path = patlab::EscapeForMessage(e.path1().string(), 1024);
  std::string expected = "an accessible path";
  int status = kExitFailure;
  if (code == ENAMETOOLONG) {
    expected = "a path whose every component is at most 255 bytes";
    status = kExitBadInput;
  } else if (code == ELOOP) {
    expected = "a path without a symbolic link loop";
    status = kExitBadInput;
  } else if (code == ENOENT || code == ENOTDIR || code == EISDIR || code == EINVAL) {
    expected = "an existing path of the right kind";
    status = kExitBadInput;
  }
  std::cerr << "patlab " << name << ": " << path << ": " << e.code().message() << "; expected "
            << expected << "\n";
  return status;
}

// Runs one subcommand; every exception it lets through becomes a message and an exit status.
int RunGuarded(const Command& c, const std::vector<std::string>& args) {
  const std::string name = c.name;
  try {
    return c.run(args);
  } catch (const patlab::EnvironmentError& e) {
    std::cerr << "patlab " << name << ": " << e.what() << "\n";
    return kExitFailure;
  } catch (const patlab::InputError& e) {
    std::cerr << "patlab " << name << ": " << e.what() << "\n";
    return kExitBadInput;
  } catch (const boost::program_options::error& e) {
    std::cerr << "patlab " << name << ": " << patlab::EscapeForMessage(e.what(), 300)
              << "; expected the options and values that 'patlab " << name << " --help' lists\n";
    return kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    return ReportFilesystemError(name, e);
  } catch (const std::bad_alloc&) {
    std::cerr << "patlab " << name
              << ": out of memory; expected a run that fits in this machine's memory (fewer "
                 "trials, frames or points)\n";
    return kExitFailure;
  } catch (const std::exception& e) {
    std::cerr << "patlab " << name << ": internal error: " << patlab::EscapeForMessage(e.what())
              << "\n";
    return kExitFailure;
  } catch (...) {
    std::cerr << "patlab " << name << ": internal error: an unknown exception\n";
    return kExitFailure;
  }
}

// Every argument must be UTF-8: names and values end up in UTF-8 JSON results and messages.
bool ArgumentsAreUtf8(const std::string& name, int argc, char** argv) {
  for (int k = 2; k < argc; ++k) {
    if (patlab::IsValidUtf8(argv[k])) continue;
    std::cerr << "patlab " << name << ": argument " << k - 1 << " '"
              << patlab::EscapeForMessage(argv[k])
              << "' is not valid UTF-8; expected UTF-8 text (rename the file)\n";
    return false;
  }
  return true;
}

// The folder of the running binary: /proc/self/exe, else argv[0]'s folder.
std::string BinaryDir(const char* argv0) {
  std::error_code ec;
  std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) exe = std::filesystem::absolute(argv0, ec);
  return exe.parent_path().string();
}

}  // namespace
}  // namespace patlab::cli

int main(int argc, char** argv) {
  using namespace patlab::cli;
  // The simulator and the statistics allocate and free many 0.1-10 MB arrays; glibc would serve
  // each from a fresh mmap and zero its pages again (a third of the run time in page faults).
  // Keep freed memory in the heap instead.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  SetBinaryDir(BinaryDir(argv[0]));
  if (argc < 2) {
    PrintUsage(std::cerr);
    return kExitBadInput;
  }
  std::string name = argv[1];
  std::vector<std::string> args(argv + 2, argv + argc);
  if (name == "--help" || name == "-h" || (name == "help" && args.empty())) {
    PrintUsage(std::cout);
    return kExitOk;
  }
  if (name == "--version") {
    PrintVersion();
    return kExitOk;
  }
  if (name == "completion") return PrintCompletion(args);
  if (name == "help") {
    if (args.size() != 1) {
      std::cerr << "patlab help: expected 'patlab help COMMAND'\n";
      return kExitBadInput;
    }
    name = args[0];
    args = {"--help"};
  }
  const Command* c = FindCommand(name);
  if (c == nullptr) return UnknownCommand(name);
  if (!ArgumentsAreUtf8(name, argc, argv)) return kExitBadInput;
  patlab::io::InstallSignalCleanup();
  return RunGuarded(*c, args);
}
