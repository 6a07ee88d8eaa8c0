// patlab track: the paper's section II single-patch experiment in simulation (Table I, the
// Wilcoxon tests between patch sizes, and the data behind Figs. 2, 3 and 6).
#include <array>
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/data.h"
#include "cli/progress.h"
#include "patlab/analysis/track.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/formats/track_file.h"
#include "patlab/io/atomic_file.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kTrackExamples = R"(examples:
  patlab track table1                      # Table I -> results/table1*.csv
  patlab track table1 -o t1 -j 1
  patlab track table1 --seed 7             # another draw of the same experiment
  patlab track table1 --pixel-sigma 0 --jitter-px 0 -o results/track_quantisation
                                           # pixel quantisation alone
  patlab track table1 --replay 2,100       # re-measure run 2, frame 100 alone
  /usr/bin/python3 scripts/plot_track.py                   # Figs. 2, 3, 6 from the CSV files

Writes to <out>: <name>.csv (Table I: per subject std and 95% CI of the paper's estimated error
and of the true error, x along and y across the travel), <name>_tests.csv (Wilcoxon signed-rank
tests between the diameters on paired |error|), track_errors.csv (per-sample errors) and
<name>.json (manifest), all atomically. Exit status: 0 ok, 1 cannot write, 2 bad input.
)";

struct TrackCliOptions {
  std::string experiment;
  std::string out_dir = "results";
  std::string seed;
  int threads = 0;
  int decimate = 1;
  double pixel_sigma = -1.0, jitter_px = -1.0;
  std::string replay;
  bool quiet = false;
};

// Parses --replay RUN,FRAME and checks it against the experiment.
std::pair<int, int> ParseReplay(const analysis::TrackOptions& options, const std::string& spec) {
  long long run = -1, frame = -1;
  char comma = 0;
  std::istringstream is(spec);
  if (!(is >> run >> comma >> frame) || comma != ',' || !is.eof() || run < 0 || frame < 0) {
    throw InputError("--replay is '" + spec + "'; expected RUN,FRAME (two integers >= 0)");
  }
  if (run >= options.runs || frame >= options.samples_per_run) {
    throw InputError("--replay " + spec + " is out of range; expected RUN < " +
                     std::to_string(options.runs) + " and FRAME < " +
                     std::to_string(options.samples_per_run));
  }
  return {static_cast<int>(run), static_cast<int>(frame)};
}

int Replay(const analysis::TrackOptions& options, const std::string& spec) {
  const auto [run, frame] = ParseReplay(options, spec);
  const analysis::RunSetup setup = analysis::MakeRunSetup(options, run);
  std::fputs(StringPrintf("run %d, frame %d, seed %llu: heading %.6f deg, t = %.4f s\n", run, frame,
                          static_cast<unsigned long long>(options.seed),
                          setup.heading_rad * 180 / std::numbers::pi, frame / options.rate_hz)
                 .c_str(),
             stdout);
  for (const analysis::ReplayedSubject& s : analysis::ReplayFrame(options, run, frame)) {
    if (!s.found) {
      std::fputs(StringPrintf("%-10s truth (%.4f, %.4f) mm   not found\n", s.name.c_str(),
                              s.truth.x_mm, s.truth.y_mm)
                     .c_str(),
                 stdout);
      continue;
    }
    std::fputs(StringPrintf(
                   "%-10s truth (%.4f, %.4f) mm   measured (%.4f, %.4f) mm   true error along %.4f "
                   "across %.4f mm",
                   s.name.c_str(), s.truth.x_mm, s.truth.y_mm, s.measured.x_mm, s.measured.y_mm,
                   s.true_error_mm.x(), s.true_error_mm.y())
                   .c_str(),
               stdout);
    if (s.has_theta)
      std::fputs(StringPrintf("   theta error %.6f rad", s.true_theta_error_rad).c_str(), stdout);
    std::printf("\n");
  }
  return kExitOk;
}

// The experiment file with the command line's seed and noise overrides, checked again.
analysis::TrackOptions LoadWithOverrides(const TrackCliOptions& o, const po::variables_map& vm) {
  analysis::TrackOptions options =
      formats::LoadTrackExperiment(FindData(o.experiment, io::DataKind::kExperiment));
  if (!o.seed.empty()) options.seed = ParseSeed(o.seed, "--seed");
  if (vm.count("pixel-sigma")) options.pixel_sigma = o.pixel_sigma;
  if (vm.count("jitter-px")) options.jitter_sigma_px = o.jitter_px;
  if (vm.count("pixel-sigma") || vm.count("jitter-px")) {
    const auto problems = analysis::Check(options);
    if (!problems.empty()) {
      throw InputError("after the command-line overrides: " + problems.front().message);
    }
  }
  return options;
}

// Writes the four output files atomically; their paths, or nullopt (after a message on stderr)
// when they cannot be written.
// The four output files, the manifest last.
std::array<std::string, 4> OutputPaths(const TrackCliOptions& o,
                                       const analysis::TrackOptions& options) {
  namespace fs = std::filesystem;
  return {(fs::path(o.out_dir) / (options.name + ".csv")).string(),
          (fs::path(o.out_dir) / (options.name + "_tests.csv")).string(),
          (fs::path(o.out_dir) / "track_errors.csv").string(),
          (fs::path(o.out_dir) / (options.name + ".json")).string()};
}

std::optional<std::array<std::string, 4>> WriteOutputs(
    const TrackCliOptions& o, const analysis::TrackOptions& options,
    const analysis::TrackResult& result, const std::vector<analysis::TableRow>& table) {
  const std::array<std::string, 4> paths = OutputPaths(o, options);
  try {
    io::WriteFilesAtomic({{paths[0], analysis::TableCsv(table)},
                          {paths[1], analysis::SizeTestsCsv(analysis::MakeSizeTests(result))},
                          {paths[2], analysis::ErrorsCsv(options, result, o.decimate)},
                          {paths[3], analysis::TrackManifestJson(options, result, table,
                                                                 {paths.begin(), paths.end()})}});
  } catch (const InputError& e) {
    std::cerr << "patlab track: " << e.what() << "\n";
    return std::nullopt;
  }
  return paths;
}

void PrintSummary(const analysis::TrackOptions& options, const analysis::TrackResult& result,
                  const std::vector<analysis::TableRow>& table,
                  const std::array<std::string, 4>& paths) {
  std::fputs(
      StringPrintf("patlab track: %d runs x %d frames in %.2f s on %d threads (%.3f mm/px)\n",
                   options.runs, options.samples_per_run, result.wall_seconds, result.threads,
                   analysis::MmPerPixel(options))
          .c_str(),
      stderr);
  std::fprintf(stderr, "%-10s %-24s %-24s %-24s %-24s\n", "subject", "est sx [95% CI] mm", "est sy",
               "true sx", "true sy");
  auto cell = [](const stats::StdWithCi& s) {
    return StringPrintf("%.3f [%.3f-%.3f]", s.std, s.lower, s.upper);
  };
  for (const analysis::TableRow& r : table) {
    std::fprintf(stderr, "%-10s %-24s %-24s %-24s %-24s\n", r.subject.c_str(),
                 cell(r.est_x).c_str(), cell(r.est_y).c_str(), cell(r.true_x).c_str(),
                 cell(r.true_y).c_str());
  }
  std::fprintf(stderr, "wrote %s, %s, %s and %s\n", paths[0].c_str(), paths[1].c_str(),
               paths[2].c_str(), paths[3].c_str());
}

// The help's option groups (command_line.h).
const OptionGroups kTrackGroups = {{"noise model", {"pixel-sigma", "jitter-px"}},
                                   {"output", {"out", "decimate"}},
                                   {"run", {"seed", "threads", "replay", "quiet"}}};

int RunTrackCommand(const std::vector<std::string>& args) {
  TrackCliOptions o;
  po::options_description visible("patlab track EXPERIMENT [options]");
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("out,o", po::value(&o.out_dir), "output directory, made if missing (default: results)")
      ("seed", po::value(&o.seed), "experiment seed (overrides the file; integer >= 0)")
      ("threads,j", po::value(&o.threads), "worker threads (default: all cores); results do not depend on it")
      ("pixel-sigma", po::value(&o.pixel_sigma), "noise: intensity noise std, grey levels (overrides [noise] pixel_sigma)")
      ("jitter-px", po::value(&o.jitter_px), "noise: per-frame camera jitter std, px (overrides [noise] jitter_sigma_px)")
      ("decimate", po::value(&o.decimate), "track_errors.csv: only every N-th sample and the next (lag-1 pairs kept); default 1 = all")
      ("replay", po::value(&o.replay), "RUN,FRAME: re-measure every subject in one frame and print it")
      ("quiet,q", po::bool_switch(&o.quiet), "no progress or summary on stderr");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, kTrackGroups, "experiment", po::value(&o.experiment), 1,
                      kTrackExamples, &vm)) {
    return kExitOk;
  }
  if (o.experiment.empty()) {
    throw InputError("missing EXPERIMENT; expected 'patlab track EXPERIMENT' (see --help)");
  }
  CheckThreads(o.threads);
  if (o.decimate < 1) {
    throw InputError("--decimate is " + std::to_string(o.decimate) + "; expected an integer >= 1");
  }
  const analysis::TrackOptions options = LoadWithOverrides(o, vm);
  if (!o.replay.empty()) return Replay(options, o.replay);

  const std::array<std::string, 4> paths = OutputPaths(o, options);
  io::CheckWritable({paths.begin(), paths.end()});
  Progress progress("patlab track", "blocks of frames", !o.quiet, StderrIsTerminal());
  analysis::TrackRunOptions run_options;
  run_options.threads = o.threads;
  run_options.progress = progress.Callback();
  const analysis::TrackResult result = analysis::RunTrack(options, run_options);
  const std::vector<analysis::TableRow> table = analysis::MakeTable(result);
  const auto written = WriteOutputs(o, options, result, table);
  if (!written) return kExitFailure;
  if (!o.quiet) PrintSummary(options, result, table, *written);
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("track", "single-patch track experiment in simulation (paper Table I)",
                        RunTrackCommand);

}  // namespace patlab::cli
