// patlab fitnoise: which error mechanisms, with which magnitudes, reproduce the paper's Table I
// and its section-IV Butterfly at once (paper/noise_fit.h): the fit with profile
// likelihood intervals, bootstrap correlations, candidate models and the sensitivity to the
// Butterfly's unknown size, as CSV files in a directory.
#include <boost/program_options.hpp>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/progress.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/atomic_file.h"
#include "patlab/paper/noise_fit.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kFitnoiseExamples = R"(examples:
  patlab fitnoise -o results/camera-noise/fit
  patlab fitnoise --free independent_x_mm,independent_y_mm,common_mm,colour_mm \
      --id-radius-mm 58 --out /tmp/fit58

Writes OUT/fit.csv (per mechanism: estimate, 95% profile interval, bootstrap percentiles,
verdict, most correlated mechanism), data.csv (observed, se, quantisation, predicted, z,
blob-level simulation), profiles.csv, correlation.csv, models.csv (candidate models) and
sensitivity.csv (the Butterfly's assumed size). Docs: docs/fitnoise.md.
Exit status: 0 ok, 1 cannot write the files, 2 bad input.
)";

struct FitnoiseOptions {
  std::string out, free = "all", seed = "14", radii = "45,50,55,60,65,70,80";
  paper::NoiseFitStudyOptions study;
  bool quiet = false;
};

void AddFitnoiseOptions(po::options_description* d, FitnoiseOptions* o) {
  paper::NoiseFitStudyOptions& s = o->study;
  d->add_options()("help,h", "show this help")("out,o", po::value(&o->out),
                                               "output directory (required)")(
      "free", po::value(&o->free), "mechanisms fitted (comma list of names, or all), default all")(
      "id-radius-mm", po::value(&s.geometry.id_radius_mm),
      "the Butterfly's key-to-dot distance (assumed), default 65")(
      "lateral-mm", po::value(&s.geometry.lateral_mm), "range of run offsets, default 200")(
      "travel-mm", po::value(&s.geometry.travel_mm), "travel, default 2000")(
      "correlation-length-mm", po::value(&s.geometry.correlation_length_mm), "default 100")(
      "smoothing-sigma", po::value(&s.geometry.smoothing_sigma_samples),
      "the paper's estimate (samples); 0 = true errors, default 10")(
      "table1-tau", po::value(&s.paper.table1_tau), "variance inflation of Table I, default 5")(
      "butterfly-tau", po::value(&s.paper.butterfly_tau),
      "variance inflation of the Butterfly's stds, default 2")(
      "bootstrap", po::value(&s.fit.bootstrap), "replicates, default 200")(
      "profile-points", po::value(&s.fit.profile_points), "default 41")(
      "sensitivity-radii", po::value(&o->radii), "id radii (mm) refitted, default 45,...,80")(
      "simulate-runs", po::value(&s.simulate_runs), "blob-level check runs (0: none), default 5")(
      "seed", po::value(&o->seed), "default 14");
  AddQuiet(d->add_options(), &o->quiet);
}

std::array<bool, paper::kNumMechanisms> ParseFree(const std::string& text) {
  std::array<bool, paper::kNumMechanisms> free{};
  if (text == "all") {
    free.fill(true);
    return free;
  }
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    const std::string name = text.substr(start, comma - start);
    free[static_cast<size_t>(ParseName(name, paper::kMechanismNames, "--free"))] = true;
    start = comma + 1;
  }
  return free;
}

// The help's option groups (command_line.h).
const OptionGroups kFitnoiseGroups = {
    {"model",
     {"free", "id-radius-mm", "lateral-mm", "travel-mm", "correlation-length-mm",
      "smoothing-sigma"}},
    {"data", {"table1-tau", "butterfly-tau"}},
    {"intervals and checks",
     {"bootstrap", "profile-points", "sensitivity-radii", "simulate-runs", "seed"}}};

int RunFitnoise(const std::vector<std::string>& args) {
  FitnoiseOptions o;
  po::options_description visible("usage: patlab fitnoise --out DIR");
  AddFitnoiseOptions(&visible, &o);
  po::variables_map vm;
  if (!ParseArguments(args, visible, kFitnoiseGroups, "unused", po::value<std::string>(), 0,
                      kFitnoiseExamples, &vm))
    return kExitOk;
  if (o.out.empty()) throw InputError("missing --out DIR; expected the output directory");
  o.study.fit.free = ParseFree(o.free);
  o.study.fit.seed = ParseSeed(o.seed, "--seed");
  o.study.sensitivity_radii_mm =
      ParseNumberList(o.radii, "--sensitivity-radii", "numbers in (10, 200] (mm)");
  paper::Validate(o.study.geometry);
  std::vector<std::string> paths;
  for (const char* name : {"fit.csv", "data.csv", "profiles.csv", "correlation.csv", "models.csv",
                           "sensitivity.csv"}) {
    paths.push_back(o.out + "/" + name);
  }
  io::CheckWritable(paths);
  Progress progress("patlab fitnoise", "steps", !o.quiet, StderrIsTerminal());
  o.study.progress = progress.Callback();
  paper::NoiseFitStudy study = paper::RunNoiseFitStudy(o.study);
  for (auto& [name, text] : study.files) name = o.out + "/" + name;
  try {
    io::WriteFilesAtomic(study.files);
  } catch (const InputError& e) {
    std::cerr << "patlab fitnoise: " << e.what() << "\n";
    return kExitFailure;
  }
  std::cout << study.summary;
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("fitnoise", "fit error-mechanism magnitudes to Table I and the Butterfly",
                        RunFitnoise);

}  // namespace patlab::cli
