// patlab: the command-line front end. Dispatches to the registered subcommands and turns
// bad-input exceptions into a message on stderr and exit status 2 (docs/architecture.md rule 9).
#include <malloc.h>

#include <boost/program_options/errors.hpp>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli/command.h"
#include "patlab/core/error.h"

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
    const std::vector<std::string> args(argv + 2, argv + argc);
    try {
      return c.run(args);
    } catch (const patlab::InputError& e) {
      std::cerr << "patlab " << name << ": " << e.what() << "\n";
      return kExitBadInput;
    } catch (const boost::program_options::error& e) {
      std::cerr << "patlab " << name << ": " << e.what() << " (see patlab " << name << " --help)\n";
      return kExitBadInput;
    }
  }
  std::cerr << "patlab: unknown command '" << name << "'\n\n";
  PrintUsage(std::cerr);
  return kExitBadInput;
}
