// patlab reproduce: every number the paper prints, regenerated and judged (docs/reproduce.md).
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>  // environ (GNU)

#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/progress.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/atomic_file.h"
#include "patlab/paper/reproduce.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kReproduceExamples = R"(examples:
  patlab reproduce              # regenerate every table, figure and manifest, and results/paper.md
  patlab reproduce --no-figures # the same without the PNGs (no python3 / matplotlib needed)
  patlab reproduce --check      # regenerate in memory; fail if a number or a committed file moved

Runs experiments/fig5.toml and experiments/table1.toml (also without sensor noise, for Fig. 6),
counts Table II's IDs, and judges every number the paper prints (results/paper.md); writes
fig5.{csv,json}, table1{.csv,_tests.csv,.json}, track_errors.csv, track_quantisation/ and
paper.md atomically, then draws Figs. 5, 2, 3, 6 (fig*.png) with /usr/bin/python3
scripts/plot_fig5.py and scripts/plot_track.py. With --check nothing is written: a line per
failing number, per regenerated file that differs from the committed one (CSV cells and
manifest numbers within the cross-machine tolerance of docs/paper-reproduction.md; manifests
without their run keys and paths) and per missing figure, exit status 1 if any.
Exit status: 0 ok, 1 a check failed, a figure script failed or results cannot be written,
2 bad input.
)";

struct ReproduceFlags {
  std::string root = ".";
  std::string out_dir = "results";
  int threads = 0;
  bool check = false;
  bool no_figures = false;
  bool quiet = false;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// --check: every failing number and every differing file on stdout; the count of failures.
int CheckAgainstCommitted(const paper::Reproduction& r, const std::vector<paper::FigureStep>& steps,
                          const std::string& out_dir) {
  int failures = 0;
  for (const paper::PaperNumber& n : r.numbers) {
    if (n.ok) continue;
    ++failures;
    std::fputs(StringPrintf("FAILS %s, %s: paper %.6g, patlab %.6g (%s)\n", n.where.c_str(),
                            n.quantity.c_str(), n.paper, n.patlab, n.reason.c_str())
                   .c_str(),
               stdout);
  }
  for (const auto& [name, text] : r.files) {
    const std::string path = (std::filesystem::path(out_dir) / name).string();
    if (!std::filesystem::exists(path)) {
      ++failures;
      std::printf("DIFFERS %s: missing; expected the committed file\n", path.c_str());
      continue;
    }
    const auto rules = r.rules.find(name);
    const std::string difference =
        name.ends_with(".json")  ? paper::CompareManifestText(text, ReadFile(path))
        : rules != r.rules.end() ? paper::CompareResultCsv(text, ReadFile(path), rules->second)
                                 : paper::CompareResultText(text, ReadFile(path));
    if (!difference.empty()) {
      ++failures;
      std::printf("DIFFERS %s: %s\n", path.c_str(), difference.c_str());
    }
  }
  // The figures are pictures of the CSVs checked above, drawn by matplotlib, whose bytes depend
  // on its version and fonts (docs/reproduce.md): only their presence is checked.
  for (const paper::FigureStep& step : steps) {
    for (const std::string& png : step.outputs) {
      if (std::filesystem::exists(png)) continue;
      ++failures;
      std::printf("DIFFERS %s: missing; expected the committed figure (%s)\n", png.c_str(),
                  step.figure.c_str());
    }
  }
  return failures;
}

// Runs one figure script (no shell: the arguments are passed as they are); its exit status, or
// -1 when it could not be started.
int RunFigureStep(const paper::FigureStep& step) {
  std::vector<char*> argv;
  for (const std::string& a : step.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), ::environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Draws the figures; false (after a message naming the step) when a script fails.
bool DrawFigures(const std::vector<paper::FigureStep>& steps) {
  for (const paper::FigureStep& step : steps) {
    const int status = RunFigureStep(step);
    if (status == 0) continue;
    std::string command;
    for (const std::string& a : step.argv) command.append(command.empty() ? "" : " ").append(a);
    std::cerr << "patlab reproduce: " << step.figure << ": '" << command << "' "
              << (status < 0 ? std::string("could not be run")
                             : "exited with status " + std::to_string(status))
              << "; expected python3 with matplotlib and numpy (scripts/setup.sh), or "
                 "--no-figures; the tables and paper.md are written\n";
    return false;
  }
  return true;
}

// The checkout when run in one (./experiments/fig5.toml), else the shipped data's root
// (share/patlab of the installation, $PATLAB_DATA).
std::string DefaultRoot() {
  std::error_code ec;
  if (std::filesystem::is_regular_file("experiments/fig5.toml", ec)) return ".";
  for (const std::string& root : DataRoots()) {
    if (std::filesystem::is_regular_file(root + "/experiments/fig5.toml", ec)) return root;
  }
  return ".";
}

// The help's option groups (command_line.h).
const OptionGroups kReproduceGroups = {{"input", {"root"}},
                                       {"output", {"out", "no-figures", "check"}}};

int RunReproduce(const std::vector<std::string>& args) {
  ReproduceFlags o;
  po::options_description visible("patlab reproduce [options]");
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("check", po::bool_switch(&o.check), "write nothing; fail if a number leaves its tolerance or a file differs from the committed one")
      ("root", po::value(&o.root), "the checkout (experiments/, patterns/; default: . in a checkout, else the shipped data)")
      ("out,o", po::value(&o.out_dir), "results directory, made if missing (default: results)")
      ("no-figures", po::bool_switch(&o.no_figures), "do not draw the PNG figures (no python3 needed)")
      ("threads,j", po::value(&o.threads), "worker threads (default: all cores); results do not depend on it")
      ("quiet,q", po::bool_switch(&o.quiet), "no progress or summary on stderr");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, kReproduceGroups, "unused", po::value<std::string>(), 0,
                      kReproduceExamples, &vm)) {
    return kExitOk;
  }
  CheckThreads(o.threads);
  if (!vm.count("root")) o.root = DefaultRoot();
  // The results folder is checked before the work (minutes of it), not when the files are written.
  if (!o.check) io::CheckWritable({(std::filesystem::path(o.out_dir) / "fig5.csv").string()});
  Progress progress("patlab reproduce", "steps", !o.quiet, StderrIsTerminal());
  const paper::ReproduceOptions options{
      .root = o.root, .threads = o.threads, .out_dir = o.out_dir, .progress = progress.Callback()};
  const paper::Reproduction r = paper::Reproduce(options);
  const std::vector<paper::FigureStep> steps = paper::FigureSteps(options);
  int ok = 0;
  for (const paper::PaperNumber& n : r.numbers) ok += n.ok ? 1 : 0;
  if (o.check) {
    const int failures = CheckAgainstCommitted(
        r, o.no_figures ? std::vector<paper::FigureStep>{} : steps, o.out_dir);
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
  const bool drawn = o.no_figures || DrawFigures(steps);
  if (!o.quiet) {
    size_t figures = 0;
    for (const paper::FigureStep& step : steps) figures += step.outputs.size();
    std::fprintf(stderr,
                 "patlab reproduce: %zu numbers, %d ok; wrote %zu files and %zu figures in %s\n",
                 r.numbers.size(), ok, files.size(), drawn && !o.no_figures ? figures : size_t{0},
                 o.out_dir.c_str());
  }
  return drawn ? kExitOk : kExitFailure;
}

}  // namespace

PATLAB_REGISTER_COMMAND("reproduce", "regenerate and judge every number the paper prints",
                        RunReproduce);

}  // namespace patlab::cli
