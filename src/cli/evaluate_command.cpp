// patlab evaluate: one report for a pattern designer (design/evaluate.h computes and renders it).
#include <boost/program_options.hpp>
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
#include "patlab/design/evaluate.h"
#include "patlab/formats/pattern_file.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kEvaluateExamples = R"(examples:
  patlab evaluate butterfly                          # the whole report, < 1 s on 2 cores
  patlab evaluate triangle my-pattern.toml --format json > report.json
  patlab evaluate butterfly --sigma 0.8 --trials 1000000
  patlab evaluate ssl-standard --sigmas 3,3.5,4,4.5 --frames 5000
  patlab evaluate butterfly --id-colors 4 --colors 2,3,4,5

A PATTERN is a pattern file or the name of a shipped pattern (or one in --patterns-dir). The report has four parts:
 1. accuracy from the geometry: each estimator's first-order std per mm of patch sigma
    (position per axis, angle), the Cramer-Rao bound, efficiency = bound^2 / predicted^2;
 2. the same by Monte-Carlo at --sigma (isotropic Gaussian patch noise, random poses on the
    2800 x 2300 mm field): simulated std with its 95% chi-square interval beside the prediction;
 3. ID capacity as patlab ids computes it (--colors, --tolerance);
 4. misidentification: --frames whole frames per --sigmas value, each with up to 5 robots per
    team (blue, yellow keys) with distinct IDs and a ball, through the detector (default
    options, patch_sigma_mm matched to the noise: max(2, sigma)); the codebook is
    <pattern>.codebook.toml next to the pattern file if there is one and --id-colors is not
    given, else every ID of --id-colors colours (default 2). Rates with 95% Wilson intervals.
Output is the same for any --threads. Exit status: 0 ok, 2 bad input.
)";

// The flags as given; the lists and the seed are parsed into design::EvaluateOptions.
struct EvaluateFlags {
  std::vector<std::string> patterns;
  std::string colors = "2,3,4";
  std::string sigmas = "1,2,3,4";
  std::string seed = "1";
  std::string format = "table";
  bool quiet = false;
  std::string patterns_dir;
};

design::EvaluateOptions ParseEvaluateOptions(const EvaluateFlags& f, const po::variables_map& vm,
                                             design::EvaluateOptions o) {
  if (f.patterns.empty()) {
    throw InputError(
        "missing PATTERN; expected 'patlab evaluate PATTERN... [options]' (see --help)");
  }
  CheckTolerance(o.tolerance_mm);
  if (vm.count("id-colors")) o.id_colours = vm["id-colors"].as<int>();
  o.colour_counts = ParseColourCounts(f.colors);
  o.sigmas_mm = ParseNumberList(f.sigmas, "--sigmas",
                                "strictly increasing finite numbers >= 0 (mm), e.g. 1,2,3,4");
  o.seed = ParseSeed(f.seed, "--seed");
  CheckFormat(f.format, "table|json");
  design::Validate(o);
  return o;
}

// The help's option groups (command_line.h).
const OptionGroups kEvaluateGroups = {{"input", {"patterns-dir"}},
                                      {"estimators", {"sigma", "trials"}},
                                      {"ID capacity", {"colors", "tolerance"}},
                                      {"misidentification", {"sigmas", "id-colors", "frames"}}};

int RunEvaluate(const std::vector<std::string>& args) {
  EvaluateFlags f;
  design::EvaluateOptions o;
  po::options_description visible("usage: patlab evaluate PATTERN... [options]\n\noptions");
  // clang-format off
  visible.add_options()
      ("sigma", po::value(&o.sigma_mm)->default_value(o.sigma_mm), "Monte-Carlo patch std (mm) of part 2")
      ("trials", po::value(&o.trials)->default_value(o.trials), "Monte-Carlo trials of part 2")
      ("colors", po::value(&f.colors)->default_value(f.colors),
       "ID palette sizes for the ID capacity of part 3, comma-separated")
      ("tolerance", po::value(&o.tolerance_mm)->default_value(o.tolerance_mm),
       "symmetry tolerance (mm) of parts 3 and 4 (paper section III: 10 mm)")
      ("sigmas", po::value(&f.sigmas)->default_value(f.sigmas),
       "patch stds (mm) of the misidentification frames of part 4")
      ("id-colors", po::value<int>(),
       "ID colours of part 4's codebook, 1..8 (default: <pattern>.codebook.toml next to the "
       "pattern file if present, else 2)")
      ("frames", po::value(&o.frames)->default_value(o.frames), "frames per sigma of part 4")
      ("seed", po::value(&f.seed)->default_value(f.seed), "seed (integer >= 0)")
      ("threads,j", po::value(&o.threads)->default_value(o.threads),
       "worker threads (0 = all cores); the output does not depend on it")
      ("format", po::value(&f.format)->default_value(f.format), "what stdout gets: table (text) or json")
      ("quiet,q", po::bool_switch(&f.quiet), "no progress on stderr")
      ("patterns-dir", po::value(&f.patterns_dir),
       "a folder searched for pattern names before the shipped patterns")
      ("help,h", "show this help");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, kEvaluateGroups, "pattern", po::value(&f.patterns), -1,
                      kEvaluateExamples, &vm, {{"--json", "--format json"}, {"-c", "--colors"}})) {
    return kExitOk;
  }
  o = ParseEvaluateOptions(f, vm, o);
  // Resolve every pattern before the first (long) run, so a typo fails at once.
  std::vector<std::pair<std::string, Pattern>> patterns;
  for (const std::string& reference : f.patterns) {
    const std::string file = FindPattern(reference, f.patterns_dir);
    patterns.emplace_back(file, formats::LoadPatternFile(file));
  }
  std::vector<design::EvaluationReport> reports;
  for (const auto& [file, pattern] : patterns) {
    Progress progress("patlab evaluate " + pattern.name, "steps", !f.quiet, StderrIsTerminal());
    design::EvaluateOptions with_progress = o;
    with_progress.progress = progress.Callback();
    reports.push_back(design::EvaluatePattern(pattern, file, with_progress));
    reports.back().options.progress = nullptr;
  }
  if (f.format == "json") {
    std::cout << design::EvaluationJson(o, reports);
    return kExitOk;
  }
  std::string text;
  for (size_t k = 0; k < reports.size(); ++k) {
    if (k > 0) text += "\n";
    text += design::EvaluationText(reports[k]);
  }
  std::cout << TrimLineEnds(text);
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND(
    "evaluate", "one report per pattern: accuracy vs the CRLB, ID capacity, misidentification",
    RunEvaluate);

}  // namespace patlab::cli
