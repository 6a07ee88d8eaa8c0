// patlab reproduce: every number the paper prints, regenerated and judged (docs/reproduce.md).
#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"
#include "patlab/sim/reproduce.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kExamples = R"(examples:
  patlab reproduce              # regenerate results/{fig5,table1,table1_tests}.csv and results/paper.md
  patlab reproduce --check      # regenerate in memory; fail if a number or a committed file moved

Runs experiments/fig5.toml and experiments/table1.toml, counts Table II's IDs, and judges every
number the paper prints (results/paper.md). With --check nothing is written: a line per failing
number and per regenerated file that differs from the committed one (cells compared within the
cross-machine tolerance of docs/paper-reproduction.md), exit status 1 if any.
Exit status: 0 ok, 1 a check failed or results cannot be written, 2 bad input.
)";

struct ReproduceFlags {
  std::string root = ".";
  std::string out_dir = "results";
  int threads = 0;
  bool check = false;
  bool quiet = false;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// --check: every failing number and every differing file on stdout; the count of failures.
int CheckAgainstCommitted(const sim::Reproduction& r, const std::string& out_dir) {
  int failures = 0;
  for (const sim::PaperNumber& n : r.numbers) {
    if (n.ok) continue;
    ++failures;
    std::printf("FAILS %s, %s: paper %.6g, patlab %.6g (%s)\n", n.where.c_str(), n.quantity.c_str(),
                n.paper, n.patlab, n.reason.c_str());
  }
  for (const auto& [name, text] : r.files) {
    const std::string path = (std::filesystem::path(out_dir) / name).string();
    if (!std::filesystem::exists(path)) {
      ++failures;
      std::printf("DIFFERS %s: missing; expected the committed file\n", path.c_str());
      continue;
    }
    const std::string difference = sim::CompareResultText(text, ReadFile(path));
    if (!difference.empty()) {
      ++failures;
      std::printf("DIFFERS %s: %s\n", path.c_str(), difference.c_str());
    }
  }
  return failures;
}

int RunReproduce(const std::vector<std::string>& args) {
  ReproduceFlags o;
  po::options_description visible("patlab reproduce [options]");
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("check", po::bool_switch(&o.check), "write nothing; fail if a number leaves its tolerance or a file differs from the committed one")
      ("root", po::value(&o.root), "the checkout (experiments/, patterns/; default: .)")
      ("out", po::value(&o.out_dir), "results directory (default: results)")
      ("threads", po::value(&o.threads), "worker threads (default: all cores); results do not depend on it")
      ("quiet,q", po::bool_switch(&o.quiet), "no summary on stderr");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, "unused", po::value<std::string>(), 0, kExamples, &vm)) {
    return kExitOk;
  }
  CheckThreads(o.threads);
  const sim::Reproduction r = sim::Reproduce({.root = o.root, .threads = o.threads});
  int ok = 0;
  for (const sim::PaperNumber& n : r.numbers) ok += n.ok ? 1 : 0;
  if (o.check) {
    const int failures = CheckAgainstCommitted(r, o.out_dir);
    if (!o.quiet) {
      std::fprintf(stderr, "patlab reproduce --check: %zu numbers, %d ok; %zu files; %d failures\n",
                   r.numbers.size(), ok, r.files.size(), failures);
    }
    return failures == 0 ? kExitOk : kExitFailure;
  }
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& [name, text] : r.files) {
    files.emplace_back((std::filesystem::path(o.out_dir) / name).string(), text);
  }
  try {
    io::WriteFilesAtomic(files);
  } catch (const InputError& e) {
    std::cerr << "patlab reproduce: " << e.what() << "\n";
    return kExitFailure;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "patlab reproduce: %zu numbers, %d ok; wrote %zu files in %s\n",
                 r.numbers.size(), ok, files.size(), o.out_dir.c_str());
  }
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("reproduce", "regenerate and judge every number the paper prints",
                        RunReproduce);

}  // namespace patlab::cli
