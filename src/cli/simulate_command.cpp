// patlab simulate: the Monte-Carlo engine (the main job).
#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/progress.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/io/atomic_file.h"
#include "patlab/sim/detect_runner.h"
#include "patlab/sim/replay.h"
#include "patlab/sim/report.h"
#include "patlab/sim/runner.h"
#include "patlab/sim/shard.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kSimulateExamples = R"(examples:
  patlab simulate fig5                           # the paper's Fig. 5 -> results/fig5.*
  patlab simulate fig5 --trials 10000 -j 1 -o quick
  patlab simulate fig5 --sigmas 0.5,1,2 --common-sigma-ratio 0.5
  patlab simulate fig5 --replay 3,41             # re-run trial 41 of data point 3
  patlab simulate id_confusion                   # whole frames through the detector
  patlab simulate id_confusion --replay 7,12     # frame 12 of point 7: blobs, detections
  patlab simulate fig5 --shard 2/8 -o shards     # share 2 of 8; then patlab merge
  patlab simulate my-experiment.toml -o results/mine

An EXPERIMENT is an experiment file or the name of a shipped one (fig5, id_confusion, table1...).
Writes <out>/<name>.csv (one row per pattern x estimator x sigma; with correspondence = "detect"
one row per pattern x false-blob rate x sigma) and <out>/<name>.json (the manifest: inputs,
seed, version, timings), both atomically. In detect mode --trials sets the frames per point.
With --shard K/N only share K of N of the points is run, and <out>/<name>.shard-K-of-N.json is
written instead; `patlab merge` joins the N shard files into the CSV and manifest (docs/merge.md).
Exit status: 0 ok, 1 cannot write results (checked before the first trial) or out of memory,
2 bad input.
)";

struct SimulateOptions {
  std::string experiment;
  std::string out_dir = "results";
  std::string name;
  int64_t trials = 0;
  std::string seed;
  int threads = 0;
  std::string sigmas;
  std::string replay;
  std::string shard;
  bool name_given = false;
  double sigma_y_ratio = -1, common_sigma_ratio = -1, outlier_probability = -1,
         outlier_sigma_ratio = -1;
  bool quiet = false;
};

// The result files of a run: <out>/<base>.csv and .json, and the command line for a shard's record.
struct OutputFiles {
  std::string csv_path, json_path, command_line;
};

OutputFiles Outputs(const sim::Experiment& experiment, const SimulateOptions& o,
                    const std::vector<std::string>& args) {
  const std::string base = o.name.empty() ? experiment.name : o.name;
  OutputFiles files;
  files.csv_path = (std::filesystem::path(o.out_dir) / (base + ".csv")).string();
  files.json_path = (std::filesystem::path(o.out_dir) / (base + ".json")).string();
  files.command_line = "patlab simulate";
  for (const std::string& a : args) files.command_line += " " + a;
  return files;
}

// Writes the files as one result set, the manifest last (io/atomic_file.h). A failure is an
// EnvironmentError: main() prints it and exits 1.
void WriteAll(const std::vector<std::pair<std::string, std::string>>& files) {
  io::WriteFilesAtomic(files);
}

// --name (or the experiment's name) is a file base name inside --out, never a path out of it.
void CheckName(const SimulateOptions& o) {
  if (o.name_given && !io::IsFileBaseName(o.name)) {
    throw InputError("--name is '" + EscapeForMessage(o.name) + "'; expected " +
                     io::kFileBaseNameExpected);
  }
}

void WriteOutputs(const OutputFiles& files, const std::string& csv, const std::string& manifest) {
  WriteAll({{files.csv_path, csv}, {files.json_path, manifest}});
}

std::string BaseName(const sim::Experiment& experiment, const SimulateOptions& o) {
  return o.name.empty() ? experiment.name : o.name;
}

// --shard K/N: the shard file <out>/<base>.shard-K-of-N.json.
std::string ShardPath(const sim::Experiment& experiment, const SimulateOptions& o,
                      const sim::ShardSpec& shard) {
  return (std::filesystem::path(o.out_dir) / sim::ShardFileName(BaseName(experiment, o), shard))
      .string();
}

// The files the run will write: the CSV and the manifest, or the shard file with --shard.
std::vector<std::string> TargetPaths(const sim::Experiment& experiment, const SimulateOptions& o,
                                     const OutputFiles& files, const sim::RunOptions& run_options) {
  if (o.shard.empty()) return {files.csv_path, files.json_path};
  return {ShardPath(experiment, o, run_options.shard)};
}

// Threads, and progress on stderr unless -q was given.
sim::RunOptions RunOptionsFor(const SimulateOptions& o, Progress* progress) {
  sim::RunOptions run_options;
  run_options.threads = o.threads;
  if (!o.shard.empty()) run_options.shard = sim::ParseShardSpec(o.shard, "--shard");
  run_options.progress = progress->Callback();
  return run_options;
}

// correspondence = "detect": whole frames through the detector.
int RunDetectMode(const sim::Experiment& experiment, const SimulateOptions& o,
                  const std::vector<std::string>& args) {
  if (!o.replay.empty()) {
    std::cout << sim::ReplayText(
        sim::ReplayDetectFrame(experiment, sim::ParseReplayIndex(o.replay, "FRAME")));
    return kExitOk;
  }
  const OutputFiles files = Outputs(experiment, o, args);
  Progress progress("patlab simulate", "blocks", !o.quiet, StderrIsTerminal());
  const sim::RunOptions run_options = RunOptionsFor(o, &progress);
  io::CheckWritable(TargetPaths(experiment, o, files, run_options));
  const sim::DetectRunResult result = sim::RunDetectExperiment(experiment, run_options);
  if (!o.shard.empty()) {
    const std::string path = ShardPath(experiment, o, run_options.shard);
    WriteAll({{path, sim::DetectShardText(experiment, result, run_options.shard,
                                          BaseName(experiment, o), files.command_line)}});
    return kExitOk;
  }
  WriteOutputs(files, sim::DetectResultsCsv(experiment, result),
               sim::DetectManifestJson(experiment, result, {files.csv_path, files.json_path}));
  if (!o.quiet) {
    std::fputs(
        StringPrintf("patlab simulate: %lld frames in %.3f s wall (frames %.3f s = %.0f frames/s, "
                     "statistics %.3f s) on %d threads\nwrote %s and %s\n",
                     static_cast<long long>(result.total_frames), result.wall_seconds,
                     result.simulate_seconds, result.total_frames / result.simulate_seconds,
                     result.statistics_seconds, result.threads, files.csv_path.c_str(),
                     files.json_path.c_str())
            .c_str(),
        stderr);
  }
  return kExitOk;
}

// The experiment file with the command line's overrides applied and checked.
sim::Experiment LoadWithOverrides(const SimulateOptions& o, const po::variables_map& vm) {
  sim::Experiment experiment =
      formats::LoadExperimentFile(FindData(o.experiment, io::DataKind::kExperiment));
  sim::Overrides overrides;
  if (vm.count("trials")) overrides.trials = o.trials;
  if (vm.count("seed") > 0) overrides.seed = ParseSeed(o.seed, "--seed");
  if (vm.count("sigmas") > 0) {  // an empty --sigmas is refused, not ignored
    overrides.sigmas_mm =
        ParseNumberList(o.sigmas, "--sigmas", "comma-separated numbers, e.g. 0,0.5,1");
  }
  sim::ApplyOverrides(overrides, &experiment);
  sim::NoiseModel& noise = experiment.noise;
  if (vm.count("sigma-y-ratio")) noise.sigma_y_ratio = o.sigma_y_ratio;
  if (vm.count("common-sigma-ratio")) noise.common_sigma_ratio = o.common_sigma_ratio;
  if (vm.count("outlier-probability")) noise.outlier_probability = o.outlier_probability;
  if (vm.count("outlier-sigma-ratio")) noise.outlier_sigma_ratio = o.outlier_sigma_ratio;
  if (const auto problems = sim::Check(noise); !problems.empty()) {
    throw InputError("noise options: " + problems.front().message);
  }
  return experiment;
}

// correspondence = "known": the estimator engine (or one replayed trial, or one share).
int RunKnownMode(const sim::Experiment& experiment, const SimulateOptions& o,
                 const std::vector<std::string>& args) {
  if (!o.replay.empty()) {
    std::cout << sim::ReplayText(
        sim::ReplayTrial(experiment, sim::ParseReplayIndex(o.replay, "TRIAL")));
    return kExitOk;
  }

  const OutputFiles files = Outputs(experiment, o, args);
  Progress progress("patlab simulate", "blocks", !o.quiet, StderrIsTerminal());
  const sim::RunOptions run_options = RunOptionsFor(o, &progress);
  io::CheckWritable(TargetPaths(experiment, o, files, run_options));
  const sim::RunResult result = sim::RunExperiment(experiment, run_options);
  if (!o.shard.empty()) {
    const std::string path = ShardPath(experiment, o, run_options.shard);
    WriteAll({{path, sim::KnownShardText(experiment, result, run_options.shard,
                                         BaseName(experiment, o), files.command_line)}});
    return kExitOk;
  }
  WriteOutputs(files, sim::ResultsCsv(experiment, result),
               sim::ManifestJson(experiment, result, {files.csv_path, files.json_path}));
  if (!o.quiet) {
    std::fputs(
        StringPrintf(
            "patlab simulate: %lld trials in %.3f s wall (simulate %.3f s = %.1f M trials/s, "
            "statistics %.3f s) on %d threads\nwrote %s and %s\n",
            static_cast<long long>(result.total_trials), result.wall_seconds,
            result.simulate_seconds, result.total_trials / result.simulate_seconds / 1e6,
            result.statistics_seconds, result.threads, files.csv_path.c_str(),
            files.json_path.c_str())
            .c_str(),
        stderr);
  }
  return kExitOk;
}

// The help's option groups (command_line.h).
const OptionGroups kSimulateGroups = {
    {"experiment", {"trials", "sigmas", "seed"}},
    {"noise model",
     {"sigma-y-ratio", "common-sigma-ratio", "outlier-probability", "outlier-sigma-ratio"}},
    {"output", {"out", "name"}},
    {"run", {"threads", "shard", "replay", "quiet"}}};

int RunSimulate(const std::vector<std::string>& args) {
  SimulateOptions o;
  po::options_description visible("patlab simulate EXPERIMENT [options]");
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("trials", po::value(&o.trials), "trials per data point (overrides the file; >= 2); frames in detect mode")
      ("seed", po::value(&o.seed), "experiment seed (overrides the file; integer >= 0)")
      ("threads,j", po::value(&o.threads), "worker threads (default: all cores); results do not depend on it")
      ("out,o", po::value(&o.out_dir), "output directory, made if missing (default: results)")
      ("name", po::value(&o.name), "output file base name (default: the experiment's name)")
      ("sigmas", po::value(&o.sigmas), "patch sigma grid in mm, comma-separated (overrides [sigma])")
      ("sigma-y-ratio", po::value(&o.sigma_y_ratio), "noise: sigma_y / sigma_x (anisotropic)")
      ("common-sigma-ratio", po::value(&o.common_sigma_ratio), "noise: common-mode std / sigma")
      ("outlier-probability", po::value(&o.outlier_probability), "noise: outlier probability per patch")
      ("outlier-sigma-ratio", po::value(&o.outlier_sigma_ratio), "noise: outlier std / sigma")
      ("replay", po::value(&o.replay), "POINT,TRIAL: re-run one trial and print every estimate (detect mode: POINT,FRAME)")
      ("shard", po::value(&o.shard), "K/N: run only share K of N of the points, write <out>/<name>.shard-K-of-N.json (patlab merge joins them)")
      ("quiet,q", po::bool_switch(&o.quiet), "no progress or summary on stderr");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, kSimulateGroups, "experiment", po::value(&o.experiment), 1,
                      kSimulateExamples, &vm)) {
    return kExitOk;
  }
  if (o.experiment.empty()) {
    throw InputError("missing EXPERIMENT; expected 'patlab simulate EXPERIMENT' (see --help)");
  }
  CheckThreads(o.threads);
  o.name_given = vm.count("name") > 0;
  CheckName(o);
  if (!o.shard.empty()) {
    sim::ParseShardSpec(o.shard, "--shard");
    if (!o.replay.empty()) throw InputError("--shard and --replay together; expected one of them");
  }

  const sim::Experiment experiment = LoadWithOverrides(o, vm);
  if (experiment.correspondence == sim::Correspondence::kDetect) {
    return RunDetectMode(experiment, o, args);
  }
  return RunKnownMode(experiment, o, args);
}

}  // namespace

PATLAB_REGISTER_COMMAND("simulate", "run a Monte-Carlo experiment (Fig. 5 curves, KS and Wilcoxon)",
                        RunSimulate);

}  // namespace patlab::cli
