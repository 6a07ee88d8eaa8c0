// patlab merge: the shard files of `patlab simulate --shard K/N` joined into the CSV and manifest
// of the unsharded run (docs/merge.md).
#include <boost/program_options.hpp>
#include <cstdio>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/progress.h"
#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/name.h"
#include "patlab/sim/shard.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kMergeExamples = R"(examples:
  for k in 1 2 3 4; do patlab simulate fig5 --shard $k/4 -o shards -q; done
  patlab merge shards -o results        # -> results/fig5.csv, results/fig5.json
  patlab merge shards/fig5.shard-*-of-4.json -o merged --name fig5-merged

Each SHARD is a shard file or a directory of them (*.shard-K-of-N.json). The shards must be the
N shares of one experiment (same file, seed, grid, patterns, patlab version), each present once
and intact; otherwise the files at fault and the missing shares are named and nothing is written.
Exit status: 0 ok, 1 cannot write results, 2 bad input.
)";

struct MergeOptions {
  std::vector<std::string> shards;
  std::string out_dir = "results";
  std::string name;
  bool quiet = false;
};

// The help's option groups (command_line.h).
const OptionGroups kMergeGroups = {{"output", {"out", "name"}}};

int RunMerge(const std::vector<std::string>& args) {
  MergeOptions o;
  po::options_description visible("patlab merge SHARD... [options]");
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("out,o", po::value(&o.out_dir), "output directory, made if missing (default: results)")
      ("name", po::value(&o.name), "output file base name (default: the one the shards record)")
      ("quiet,q", po::bool_switch(&o.quiet), "no progress or summary on stderr");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, kMergeGroups, "shard", po::value(&o.shards), -1,
                      kMergeExamples, &vm)) {
    return kExitOk;
  }
  if (o.shards.empty()) {
    throw InputError("missing SHARD; expected 'patlab merge SHARD... --out DIR' (see --help)");
  }
  if (!o.name.empty()) io::CheckName(o.name, "--name");
  Progress progress("patlab merge", "shard files", !o.quiet, StderrIsTerminal());
  const sim::MergedOutputs merged =
      sim::MergeShards(o.shards, o.out_dir, o.name, progress.Callback());
  try {
    io::WriteFilesAtomic({{merged.csv_path, merged.csv}, {merged.json_path, merged.json}});
  } catch (const InputError& e) {
    std::cerr << "patlab merge: " << e.what() << "\n";
    return kExitFailure;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "patlab merge: wrote %s and %s\n", merged.csv_path.c_str(),
                 merged.json_path.c_str());
  }
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("merge", "join the shard files of 'simulate --shard K/N' into one result",
                        RunMerge);

}  // namespace patlab::cli
