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

#include "cli/command.h"
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
        "usage: patlab <command> [options]   (patlab <command> --help for details)\n\n"
        "commands:\n";
  for (const Command& c : Commands()) {
    std::string name = c.name;
    name.resize(std::max<size_t>(name.size() + 2, 12), ' ');
    os << "  " << name << c.summary << "\n";
  }
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

}  // namespace
}  // namespace patlab::cli

int main(int argc, char** argv) {
  using namespace patlab::cli;
  // The simulator and the statistics allocate and free many 0.1-10 MB arrays; glibc would serve
  // each from a fresh mmap and zero its pages again (a third of the run time in page faults).
  // Keep freed memory in the heap instead.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  if (argc < 2) {
    PrintUsage(std::cerr);
    return kExitBadInput;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    PrintUsage(std::cout);
    return kExitOk;
  }
  if (name == "--version") {
    std::cout << "patlab " PATLAB_VERSION "\n";
    return kExitOk;
  }
  for (const Command& c : Commands()) {
    if (name != c.name) continue;
    if (!ArgumentsAreUtf8(name, argc, argv)) return kExitBadInput;
    patlab::io::InstallSignalCleanup();
    const std::vector<std::string> args(argv + 2, argv + argc);
    return RunGuarded(c, args);
  }
  std::cerr << "patlab: unknown command '" << patlab::EscapeForMessage(name)
            << "'; expected one of the commands that 'patlab --help' lists\n";
  return kExitBadInput;
}
