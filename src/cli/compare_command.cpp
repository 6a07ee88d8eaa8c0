// patlab compare: pattern designs ranked side by side (design/compare.h computes and renders it).
#include <unistd.h>

#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/progress.h"
#include "cli/text_output.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/design/compare.h"
#include "patlab/formats/pattern_file.h"
#include "patlab/io/atomic_file.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kCompareExamples = R"(examples:
  patlab compare ssl-standard butterfly triangle              # ranked table on stdout
  patlab compare simple linear triangle --sort-by ids_2c --format csv  # CSV on stdout
  patlab compare a.toml b.toml -o ab                          # compare.txt, .csv, .json in ab/
  patlab compare ssl-standard butterfly --trials 100000 --frames 10000 --sigmas 2,3,3.5,4

A DESIGN is a pattern file or the name of a shipped pattern (or one in --patterns-dir). Every design runs the work of
patlab evaluate with the same options and seed: first-order and Monte-Carlo accuracy against
the Cramer-Rao bound, ID capacity (patlab ids), misidentification in whole frames, and the
KS / Wilcoxon comparison of ML with fast; compare adds size, the smallest gap and how robust
the rotation fix is, and ranks the designs by --sort-by (best first). docs/compare.md defines
every column. The numbers are the same for any --threads. Progress goes to stderr (not with
-q). Figure: scripts/plot_compare.py DIR/compare.csv DIR/compare.png.
Exit status: 0 ok, 1 cannot write --out, 2 bad input (nothing is written).
)";

struct CompareFlags {
  std::vector<std::string> designs;
  std::string colors = "2,3,4";
  std::string sigmas = "1,2,3,4";
  std::string seed = "1";
  std::string out_dir;
  std::string format = "table";
  bool quiet = false;
  std::string patterns_dir;
};

design::CompareOptions ParseCompareOptions(const CompareFlags& f, const po::variables_map& vm,
                                           design::CompareOptions o, Progress* progress) {
  if (f.designs.empty()) {
    throw InputError("missing DESIGN; expected 'patlab compare DESIGN... [options]' (see --help)");
  }
  CheckFormat(f.format, "table|csv|json");
  CheckTolerance(o.evaluate.tolerance_mm);
  if (vm.count("id-colors")) o.evaluate.id_colours = vm["id-colors"].as<int>();
  o.evaluate.colour_counts = ParseColourCounts(f.colors);
  o.evaluate.sigmas_mm = ParseNumberList(
      f.sigmas, "--sigmas", "strictly increasing finite numbers >= 0 (mm), e.g. 1,2,3,4");
  o.evaluate.seed = ParseSeed(f.seed, "--seed");
  design::Validate(o);
  o.progress = progress->Callback();
  return o;
}

// The help's option groups (command_line.h).
const OptionGroups kCompareGroups = {{"input", {"patterns-dir"}},
                                     {"estimators", {"sigma", "trials"}},
                                     {"ID capacity", {"colors", "tolerance"}},
                                     {"misidentification", {"sigmas", "id-colors", "frames"}},
                                     {"output", {"out", "format", "sort-by"}}};

int RunCompare(const std::vector<std::string>& args) {
  CompareFlags f;
  design::CompareOptions o;
  design::EvaluateOptions& e = o.evaluate;
  po::options_description visible("usage: patlab compare DESIGN... [options]\n\noptions");
  // clang-format off
  visible.add_options()
      ("sort-by", po::value(&o.sort_by)->default_value(o.sort_by),
       "the column that ranks the designs (docs/compare.md lists them)")
      ("sigma", po::value(&e.sigma_mm)->default_value(e.sigma_mm), "Monte-Carlo patch std (mm)")
      ("trials", po::value(&e.trials)->default_value(e.trials), "Monte-Carlo trials per design")
      ("colors", po::value(&f.colors)->default_value(f.colors),
       "ID palette sizes of the ID capacity columns, comma-separated")
      ("tolerance", po::value(&e.tolerance_mm)->default_value(e.tolerance_mm),
       "symmetry tolerance (mm; patlab ids)")
      ("sigmas", po::value(&f.sigmas)->default_value(f.sigmas),
       "patch stds (mm) of the misidentification frames")
      ("id-colors", po::value<int>(),
       "ID colours of the frames' codebook, 1..8 (default: <design>.codebook.toml next to the "
       "file if present, else 2)")
      ("frames", po::value(&e.frames)->default_value(e.frames), "frames per sigma and design")
      ("seed", po::value(&f.seed)->default_value(f.seed), "seed (integer >= 0)")
      ("threads,j", po::value(&e.threads)->default_value(e.threads),
       "worker threads (0 = all cores); the output does not depend on it")
      ("format", po::value(&f.format)->default_value(f.format), "what stdout gets: table, csv or json")
      ("out,o", po::value(&f.out_dir), "write compare.txt, compare.csv and compare.json to this directory (then stdout gets only --format csv or json)")
      ("quiet,q", po::bool_switch(&f.quiet), "no progress or timing line on stderr")
      ("patterns-dir", po::value(&f.patterns_dir),
       "a folder searched for pattern names before the shipped patterns")
      ("help,h", "show this help");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(
          args, visible, kCompareGroups, "design", po::value(&f.designs), -1, kCompareExamples, &vm,
          {{"--json", "--format json"}, {"--csv", "--format csv"}, {"-c", "--colors"}})) {
    return kExitOk;
  }
  Progress progress("patlab compare", "runs", !f.quiet, StderrIsTerminal());
  o = ParseCompareOptions(f, vm, o, &progress);
  // Every design is read before the first (long) run, so a typo fails at once.
  std::vector<std::pair<Pattern, std::string>> designs;
  for (const std::string& reference : f.designs) {
    const std::string file = FindPattern(reference, f.patterns_dir);
    designs.emplace_back(formats::LoadPatternFile(file), file);
  }
  const design::CompareResult result = design::CompareDesigns(designs, o);
  const std::string text = TrimLineEnds(design::CompareText(result));
  if (!f.out_dir.empty()) {
    const std::filesystem::path dir(f.out_dir);
    try {
      io::WriteFilesAtomic({{(dir / "compare.txt").string(), text},
                            {(dir / "compare.csv").string(), design::CompareCsv(result)},
                            {(dir / "compare.json").string(), design::CompareJson(result)}});
    } catch (const InputError& error) {
      std::cerr << "patlab compare: " << error.what() << "\n";
      return kExitFailure;
    }
  }
  if (f.format == "csv") {
    std::cout << design::CompareCsv(result);
  } else if (f.format == "json") {
    std::cout << design::CompareJson(result);
  } else if (f.out_dir.empty()) {
    std::cout << text;
  }
  if (!f.quiet) {
    std::fputs(
        StringPrintf("patlab compare: %zu designs in %.1f s\n", designs.size(), result.wall_seconds)
            .c_str(),
        stderr);
  }
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("compare", "rank pattern designs side by side: accuracy, IDs, robustness",
                        RunCompare);

}  // namespace patlab::cli
