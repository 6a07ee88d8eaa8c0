// patlab simulate: the Monte-Carlo engine (the main job).
#include <unistd.h>

#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli/command.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "sim/report.h"
#include "sim/runner.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kExamples = R"(examples:
  patlab simulate experiments/fig5.toml                  # the paper's Fig. 5 -> results/fig5.*
  patlab simulate experiments/fig5.toml --trials 10000 --threads 1 --out /tmp/quick
  patlab simulate experiments/fig5.toml --sigmas 0.5,1,2 --common-sigma-ratio 0.5
  patlab simulate experiments/fig5.toml --replay 3,41    # re-run trial 41 of data point 3

Writes <out>/<name>.csv (one row per pattern x estimator x sigma) and <out>/<name>.json (the
manifest: inputs, seed, version, timings), both atomically. Exit status: 0 ok, 2 bad input.
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
  double sigma_y_ratio = -1, common_sigma_ratio = -1, outlier_probability = -1,
         outlier_sigma_ratio = -1;
  bool quiet = false;
};

std::vector<double> ParseList(const std::string& text, const char* flag) {
  std::vector<double> values;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size()) {
      throw InputError(std::string(flag) + " has '" + item +
                       "'; expected comma-separated numbers, e.g. 0,0.5,1");
    }
    values.push_back(v);
  }
  if (values.empty()) throw InputError(std::string(flag) + " is empty; expected numbers");
  return values;
}

void ProgressBar(int done, int total) {
  const int width = 40;
  const int filled = total > 0 ? done * width / total : width;
  std::fprintf(stderr, "\r[%s%s] %d/%d points", std::string(filled, '#').c_str(),
               std::string(width - filled, ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

int Replay(const sim::Experiment& experiment, const std::string& spec) {
  int64_t point = -1, trial = -1;
  char comma = 0;
  std::istringstream is(spec);
  if (!(is >> point >> comma >> trial) || comma != ',' || !is.eof() || point < 0 || trial < 0) {
    throw InputError("--replay is '" + spec + "'; expected POINT,TRIAL (two integers >= 0)");
  }
  const int64_t num_sigmas = static_cast<int64_t>(experiment.sigmas_mm.size());
  const int64_t num_points = static_cast<int64_t>(experiment.patterns.size()) * num_sigmas;
  if (point >= num_points || trial >= experiment.trials) {
    throw InputError("--replay " + spec + " is out of range; expected POINT < " +
                     std::to_string(num_points) + " and TRIAL < " +
                     std::to_string(experiment.trials));
  }
  const int pattern_index = static_cast<int>(point / num_sigmas);
  const int sigma_index = static_cast<int>(point % num_sigmas);
  const Pattern& pattern = experiment.patterns[pattern_index];
  const estimate::Model model = estimate::Model::FromPattern(pattern);
  const sim::PointSetup setup = sim::MakePointSetup(experiment, model, pattern_index, sigma_index);
  Pose2 truth;
  std::array<Vec2, kMaxPatches> observed;
  sim::GenerateTrial(setup, static_cast<uint64_t>(trial), &truth, observed.data());
  std::printf("point %lld (pattern %s, sigma %.6g mm), trial %lld, seed %llu\n",
              static_cast<long long>(point), pattern.name.c_str(), setup.sigma_mm,
              static_cast<long long>(trial), static_cast<unsigned long long>(experiment.seed));
  std::printf("truth      x %.9f mm  y %.9f mm  theta %.12f rad\n", truth.x_mm, truth.y_mm,
              truth.theta_rad);
  for (int i = 0; i < pattern.size(); ++i) {
    std::printf("patch %-2d   observed (%.9f, %.9f) mm\n", i, observed[i].x(), observed[i].y());
  }
  const Pose2 fast = estimate::Fast(model, observed.data());
  estimate::Summary summary;
  const Pose2 estimates[] = {
      fast,
      estimate::MaximumLikelihood(model, observed.data(), fast, experiment.ml_options, &summary),
      estimate::LeastSquares(model, observed.data()), estimate::KeyPatch(model, observed.data())};
  for (estimate::Estimator e : estimate::kAllEstimators) {
    const Pose2& p = estimates[static_cast<int>(e)];
    std::printf("%-5s      x %.9f mm  y %.9f mm  theta %.12f rad  (error %.3e mm, %.3e mm, %.3e rad)\n",
                std::string(estimate::EstimatorName(e)).c_str(), p.x_mm, p.y_mm, p.theta_rad,
                p.x_mm - truth.x_mm, p.y_mm - truth.y_mm, WrapAngle(p.theta_rad - truth.theta_rad));
  }
  std::printf("ml summary %s after %d iterations, cost %.6g -> %.6g mm^2\n",
              std::string(estimate::TerminationName(summary.termination)).c_str(),
              summary.iterations, summary.initial_cost, summary.final_cost);
  return kExitOk;
}

int RunSimulate(const std::vector<std::string>& args) {
  SimulateOptions o;
  po::options_description visible("patlab simulate EXPERIMENT.toml [options]");
  visible.add_options()
      ("help,h", "show this help")
      ("trials", po::value(&o.trials), "trials per data point (overrides the file; >= 2)")
      ("seed", po::value(&o.seed), "experiment seed (overrides the file; integer >= 0)")
      ("threads", po::value(&o.threads), "worker threads (default: all cores); results do not depend on it")
      ("out", po::value(&o.out_dir), "output directory (default: results)")
      ("name", po::value(&o.name), "output file base name (default: the experiment's name)")
      ("sigmas", po::value(&o.sigmas), "patch sigma grid in mm, comma-separated (overrides [sigma])")
      ("sigma-y-ratio", po::value(&o.sigma_y_ratio), "noise: sigma_y / sigma_x (anisotropic)")
      ("common-sigma-ratio", po::value(&o.common_sigma_ratio), "noise: common-mode std / sigma")
      ("outlier-probability", po::value(&o.outlier_probability), "noise: outlier probability per patch")
      ("outlier-sigma-ratio", po::value(&o.outlier_sigma_ratio), "noise: outlier std / sigma")
      ("replay", po::value(&o.replay), "POINT,TRIAL: re-run one trial and print every estimate")
      ("quiet,q", po::bool_switch(&o.quiet), "no progress bar or summary on stderr");
  po::options_description all;
  all.add(visible).add_options()("experiment", po::value(&o.experiment));
  po::positional_options_description positional;
  positional.add("experiment", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(all).positional(positional).run(), vm);
  po::notify(vm);
  if (vm.count("help")) {
    std::cout << visible << "\n" << kExamples;
    return kExitOk;
  }
  if (o.experiment.empty()) {
    throw InputError("missing EXPERIMENT.toml; expected 'patlab simulate EXPERIMENT.toml' (see --help)");
  }
  if (o.threads < 0) throw InputError("--threads is " + std::to_string(o.threads) + "; expected >= 0");

  sim::Experiment experiment = sim::LoadExperimentFile(o.experiment);
  sim::Overrides overrides;
  overrides.trials = o.trials;
  if (vm.count("trials") && o.trials == 0) throw InputError("--trials is 0; expected an integer >= 2");
  if (!o.seed.empty()) {
    size_t used = 0;
    try {
      overrides.seed = std::stoull(o.seed, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != o.seed.size() || o.seed[0] == '-') {
      throw InputError("--seed is '" + o.seed + "'; expected an integer >= 0");
    }
    overrides.has_seed = true;
  }
  if (!o.sigmas.empty()) overrides.sigmas_mm = ParseList(o.sigmas, "--sigmas");
  sim::ApplyOverrides(overrides, &experiment);
  sim::NoiseModel& noise = experiment.noise;
  if (vm.count("sigma-y-ratio")) noise.sigma_y_ratio = o.sigma_y_ratio;
  if (vm.count("common-sigma-ratio")) noise.common_sigma_ratio = o.common_sigma_ratio;
  if (vm.count("outlier-probability")) noise.outlier_probability = o.outlier_probability;
  if (vm.count("outlier-sigma-ratio")) noise.outlier_sigma_ratio = o.outlier_sigma_ratio;
  if (const std::string problem = noise.Validate(); !problem.empty()) {
    throw InputError("noise options: " + problem);
  }

  if (!o.replay.empty()) return Replay(experiment, o.replay);

  const bool show_progress = !o.quiet && ::isatty(STDERR_FILENO);
  sim::RunOptions run_options;
  run_options.threads = o.threads;
  if (show_progress) run_options.progress = ProgressBar;
  const sim::RunResult result = sim::RunExperiment(experiment, run_options);

  const std::string base = o.name.empty() ? experiment.name : o.name;
  const std::string csv_path = (std::filesystem::path(o.out_dir) / (base + ".csv")).string();
  const std::string json_path = (std::filesystem::path(o.out_dir) / (base + ".json")).string();
  std::string command_line = "patlab simulate";
  for (const std::string& a : args) command_line += " " + a;
  try {
    io::WriteFilesAtomic({{csv_path, sim::ResultsCsv(experiment, result)},
                          {json_path, sim::ManifestJson(experiment, result, command_line,
                                                        {csv_path, json_path})}});
  } catch (const InputError& e) {
    std::cerr << "patlab simulate: " << e.what() << "\n";
    return kExitFailure;
  }
  if (!o.quiet) {
    std::fprintf(stderr,
                 "patlab simulate: %lld trials in %.3f s wall (simulate %.3f s = %.1f M trials/s, "
                 "statistics %.3f s) on %d threads\nwrote %s and %s\n",
                 static_cast<long long>(result.total_trials), result.wall_seconds,
                 result.simulate_seconds, result.total_trials / result.simulate_seconds / 1e6,
                 result.statistics_seconds, result.threads, csv_path.c_str(), json_path.c_str());
  }
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("simulate", "run a Monte-Carlo experiment (Fig. 5 curves, KS and Wilcoxon)",
                        RunSimulate);

}  // namespace patlab::cli
