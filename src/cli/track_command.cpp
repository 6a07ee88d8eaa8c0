// patlab track: the paper's section II single-patch experiment in simulation (Table I, the
// Wilcoxon tests between patch sizes, and the data behind Figs. 2, 3 and 6).
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"
#include "patlab/io/toml_util.h"
#include "patlab/sim/track.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kExamples = R"(examples:
  patlab track experiments/table1.toml                     # Table I -> results/table1*.csv
  patlab track experiments/table1.toml --out /tmp/t1 --threads 1
  patlab track experiments/table1.toml --seed 7            # another draw of the same experiment
  patlab track experiments/table1.toml --pixel-sigma 0 --jitter-px 0 --out results/track_quantisation
                                                           # pixel quantisation alone
  patlab track experiments/table1.toml --replay 2,100      # re-measure run 2, frame 100 alone
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

nlohmann::json StdJson(const stats::StdWithCi& s) {
  return {{"std", s.std}, {"lower", s.lower}, {"upper", s.upper}, {"n", s.n}};
}

std::string Manifest(const sim::TrackOptions& o, const sim::TrackResult& result,
                     const std::vector<sim::TableRow>& table, const std::string& command_line,
                     const std::vector<std::string>& outputs) {
  nlohmann::json j;
  j["tool"] = "patlab track";
  j["version"] = PATLAB_VERSION;
  j["command"] = command_line;
  j["experiment"] = o.source_file;
  j["name"] = o.name;
  j["description"] = o.description;
  j["seed"] = o.seed;
  j["runs"] = o.runs;
  j["diameters_mm"] = o.diameters_mm;
  j["pattern_file"] = o.pattern_file;
  j["platform"] = {{"samples_per_run", o.samples_per_run},
                   {"rate_hz", o.rate_hz},
                   {"speed_mm_per_s", o.speed_mm_per_s},
                   {"heading_max_deg", o.heading_max_deg},
                   {"lateral_range_mm", o.lateral_range_mm},
                   {"start_jitter_mm", o.start_jitter_mm},
                   {"spacing_mm", o.spacing_mm},
                   {"plane_height_mm", o.plane_height_mm}};
  j["camera"] = {{"height_mm", o.camera.height_mm},
                 {"image_size_px", {o.camera.image_width_px, o.camera.image_height_px}},
                 {"focal_length_px", o.camera.focal_length_px},
                 {"mm_per_px", sim::MmPerPixel(o)}};
  j["render"] = {{"background_level", o.background_level},
                 {"patch_level", o.patch_level},
                 {"threshold_level", o.threshold_level},
                 {"supersampling", o.supersampling}};
  j["noise"] = {{"pixel_sigma", o.pixel_sigma}, {"jitter_sigma_px", o.jitter_sigma_px}};
  stats::SmoothingOptions smoothing;
  smoothing.sigma_samples = o.smoothing_sigma_samples;
  j["analysis"] = {{"smoothing_sigma_samples", o.smoothing_sigma_samples},
                   {"trim_samples", o.trim_samples},
                   {"white_noise_residual_factor", sim::ResidualStdFactor(smoothing)}};
  nlohmann::json runs = nlohmann::json::array();
  for (const sim::RunSetup& s : result.setups) {
    runs.push_back({{"heading_deg", s.heading_rad * 180.0 / std::numbers::pi},
                    {"start_mm", {s.start_mm.x(), s.start_mm.y()}}});
  }
  j["run_setups"] = runs;
  nlohmann::json rows = nlohmann::json::array();
  for (const sim::TableRow& r : table) {
    nlohmann::json row = {{"subject", r.subject},        {"est_x", StdJson(r.est_x)},
                          {"est_y", StdJson(r.est_y)},   {"true_x", StdJson(r.true_x)},
                          {"true_y", StdJson(r.true_y)}, {"missed_frames", r.missed_frames}};
    if (r.has_theta) {
      row["est_theta"] = StdJson(r.est_theta);
      row["true_theta"] = StdJson(r.true_theta);
    }
    rows.push_back(row);
  }
  j["table"] = rows;
  j["threads"] = result.threads;
  j["timings_s"] = {{"wall", result.wall_seconds},
                    {"measure", result.measure_seconds},
                    {"analysis", result.analysis_seconds}};
  j["outputs"] = outputs;
  return j.dump(2) + "\n";
}

int Replay(const sim::TrackOptions& options, const std::string& spec) {
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
  const sim::RunSetup setup = sim::MakeRunSetup(options, static_cast<int>(run));
  std::printf("run %lld, frame %lld, seed %llu: heading %.6f deg, t = %.4f s\n", run, frame,
              static_cast<unsigned long long>(options.seed),
              setup.heading_rad * 180 / std::numbers::pi, frame / options.rate_hz);
  const double c = std::cos(setup.heading_rad), s = std::sin(setup.heading_rad);
  for (int k = 0; k < sim::NumSubjects(options); ++k) {
    const std::string name = k < static_cast<int>(options.diameters_mm.size())
                                 ? io::FormatNumber(options.diameters_mm[k]) + "mm"
                                 : options.pattern.name;
    const Pose2 truth = sim::TruthPose(options, setup, static_cast<int>(frame), k);
    Pose2 measured;
    if (!sim::MeasureSubject(options, static_cast<int>(run), static_cast<int>(frame), k,
                                &measured)) {
      std::printf("%-10s truth (%.4f, %.4f) mm   not found\n", name.c_str(), truth.x_mm,
                  truth.y_mm);
      continue;
    }
    const double ex = measured.x_mm - truth.x_mm, ey = measured.y_mm - truth.y_mm;
    std::printf(
        "%-10s truth (%.4f, %.4f) mm   measured (%.4f, %.4f) mm   true error along %.4f "
        "across %.4f mm",
        name.c_str(), truth.x_mm, truth.y_mm, measured.x_mm, measured.y_mm, c * ex + s * ey,
        -s * ex + c * ey);
    if (k >= static_cast<int>(options.diameters_mm.size())) {
      std::printf("   theta error %.6f rad", WrapAngle(measured.theta_rad - truth.theta_rad));
    }
    std::printf("\n");
  }
  return kExitOk;
}

int RunTrackCommand(const std::vector<std::string>& args) {
  TrackCliOptions o;
  po::options_description visible("patlab track EXPERIMENT.toml [options]");
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("out", po::value(&o.out_dir), "output directory (default: results)")
      ("seed", po::value(&o.seed), "experiment seed (overrides the file; integer >= 0)")
      ("threads", po::value(&o.threads), "worker threads (default: all cores); results do not depend on it")
      ("pixel-sigma", po::value(&o.pixel_sigma), "noise: intensity noise std, grey levels (overrides [noise] pixel_sigma)")
      ("jitter-px", po::value(&o.jitter_px), "noise: per-frame camera jitter std, px (overrides [noise] jitter_sigma_px)")
      ("decimate", po::value(&o.decimate), "track_errors.csv: only every N-th sample and the next (lag-1 pairs kept); default 1 = all")
      ("replay", po::value(&o.replay), "RUN,FRAME: re-measure every subject in one frame and print it")
      ("quiet,q", po::bool_switch(&o.quiet), "no summary on stderr");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, "experiment", po::value(&o.experiment), 1, kExamples, &vm)) {
    return kExitOk;
  }
  if (o.experiment.empty()) {
    throw InputError(
        "missing EXPERIMENT.toml; expected 'patlab track EXPERIMENT.toml' (see --help)");
  }
  CheckThreads(o.threads);
  if (o.decimate < 1) {
    throw InputError("--decimate is " + std::to_string(o.decimate) + "; expected an integer >= 1");
  }
  sim::TrackOptions options = sim::LoadTrackExperiment(o.experiment);
  if (!o.seed.empty()) options.seed = ParseSeed(o.seed, "--seed");

  if (vm.count("pixel-sigma")) options.pixel_sigma = o.pixel_sigma;
  if (vm.count("jitter-px")) options.jitter_sigma_px = o.jitter_px;
  if (vm.count("pixel-sigma") || vm.count("jitter-px")) {
    const auto problems = sim::CheckTrackOptions(options);
    if (!problems.empty())
      throw InputError("after the command-line overrides: " + problems.front().message);
  }

  if (!o.replay.empty()) return Replay(options, o.replay);

  sim::TrackRunOptions run_options;
  run_options.threads = o.threads;
  const sim::TrackResult result = sim::RunTrack(options, run_options);
  const std::vector<sim::TableRow> table = sim::MakeTable(result);
  const std::vector<sim::SizeTest> tests = sim::MakeSizeTests(result);

  namespace fs = std::filesystem;
  const std::string table_path = (fs::path(o.out_dir) / (options.name + ".csv")).string();
  const std::string tests_path = (fs::path(o.out_dir) / (options.name + "_tests.csv")).string();
  const std::string errors_path = (fs::path(o.out_dir) / "track_errors.csv").string();
  const std::string json_path = (fs::path(o.out_dir) / (options.name + ".json")).string();
  std::string command_line = "patlab track";
  for (const std::string& a : args) command_line += " " + a;
  try {
    io::WriteFilesAtomic({{table_path, sim::TableCsv(table)},
                          {tests_path, sim::SizeTestsCsv(tests)},
                          {errors_path, sim::ErrorsCsv(options, result, o.decimate)},
                          {json_path, Manifest(options, result, table, command_line,
                                               {table_path, tests_path, errors_path, json_path})}});
  } catch (const InputError& e) {
    std::cerr << "patlab track: " << e.what() << "\n";
    return kExitFailure;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "patlab track: %d runs x %d frames in %.2f s on %d threads (%.3f mm/px)\n",
                 options.runs, options.samples_per_run, result.wall_seconds, result.threads,
                 sim::MmPerPixel(options));
    std::fprintf(stderr, "%-10s %-24s %-24s %-24s %-24s\n", "subject", "est sx [95% CI] mm",
                 "est sy", "true sx", "true sy");
    for (const sim::TableRow& r : table) {
      auto cell = [](const stats::StdWithCi& s) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.3f [%.3f-%.3f]", s.std, s.lower, s.upper);
        return std::string(buf);
      };
      std::fprintf(stderr, "%-10s %-24s %-24s %-24s %-24s\n", r.subject.c_str(),
                   cell(r.est_x).c_str(), cell(r.est_y).c_str(), cell(r.true_x).c_str(),
                   cell(r.true_y).c_str());
    }
    std::fprintf(stderr, "wrote %s, %s, %s and %s\n", table_path.c_str(), tests_path.c_str(),
                 errors_path.c_str(), json_path.c_str());
  }
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("track", "single-patch track experiment in simulation (paper Table I)",
                        RunTrackCommand);

}  // namespace patlab::cli
