// patlab simulate: the Monte-Carlo engine (the main job).
#include <unistd.h>

#include <boost/program_options.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "patlab/core/error.h"
#include "patlab/io/atomic_file.h"
#include "patlab/sim/detect_runner.h"
#include "patlab/sim/report.h"
#include "patlab/sim/runner.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kExamples = R"(examples:
  patlab simulate experiments/fig5.toml                  # the paper's Fig. 5 -> results/fig5.*
  patlab simulate experiments/fig5.toml --trials 10000 --threads 1 --out /tmp/quick
  patlab simulate experiments/fig5.toml --sigmas 0.5,1,2 --common-sigma-ratio 0.5
  patlab simulate experiments/fig5.toml --replay 3,41    # re-run trial 41 of data point 3
  patlab simulate experiments/id_confusion.toml          # whole frames through the detector
  patlab simulate experiments/id_confusion.toml --replay 7,12  # frame 12 of point 7: blobs, detections

Writes <out>/<name>.csv (one row per pattern x estimator x sigma; with correspondence = "detect"
one row per pattern x false-blob rate x sigma) and <out>/<name>.json (the manifest: inputs,
seed, version, timings), both atomically. In detect mode --trials sets the frames per point.
Exit status: 0 ok, 1 cannot write results, 2 bad input.
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
    std::printf(
        "%-5s      x %.9f mm  y %.9f mm  theta %.12f rad  (error %.3e mm, %.3e mm, %.3e rad)\n",
        std::string(estimate::EstimatorName(e)).c_str(), p.x_mm, p.y_mm, p.theta_rad,
        p.x_mm - truth.x_mm, p.y_mm - truth.y_mm, WrapAngle(p.theta_rad - truth.theta_rad));
  }
  std::printf("ml summary %s after %d iterations, cost %.6g -> %.6g mm^2\n",
              std::string(estimate::TerminationName(summary.termination)).c_str(),
              summary.iterations, summary.initial_cost, summary.final_cost);
  return kExitOk;
}

int ReplayDetect(const sim::Experiment& experiment, const std::string& spec) {
  int64_t point = -1, frame = -1;
  char comma = 0;
  std::istringstream is(spec);
  if (!(is >> point >> comma >> frame) || comma != ',' || !is.eof() || point < 0 || frame < 0) {
    throw InputError("--replay is '" + spec + "'; expected POINT,FRAME (two integers >= 0)");
  }
  const int64_t num_points = sim::NumDetectPoints(experiment);
  if (point >= num_points || frame >= experiment.detect.frames) {
    throw InputError("--replay " + spec + " is out of range; expected POINT < " +
                     std::to_string(num_points) + " and FRAME < " +
                     std::to_string(experiment.detect.frames));
  }
  const sim::DetectPoint p = sim::MakeDetectPoint(experiment, static_cast<uint32_t>(point));
  detect::Detector detector(p.config);
  const sim::Scene scene =
      sim::GenerateDetectFrame(experiment, p, detector, static_cast<uint64_t>(frame));
  std::vector<detect::Detection> detections;
  detector.Detect(scene.blobs, &detections);
  const sim::FrameScore score =
      sim::ScoreFrame(scene, detections, experiment.detect.match_radius_mm);
  const auto& palette = p.config.palette;
  std::printf(
      "point %lld (pattern %s, sigma %.6g mm, false blobs %.6g /m^2), frame %lld, seed %llu\n",
      static_cast<long long>(point), experiment.patterns[p.pattern_index].name.c_str(), p.sigma_mm,
      p.scene.false_blob_rate_per_m2, static_cast<long long>(frame),
      static_cast<unsigned long long>(experiment.seed));
  for (const sim::SceneRobot& r : scene.robots) {
    std::printf("robot      %-7s id %-3d x %.3f mm  y %.3f mm  theta %.6f rad\n",
                palette[r.team_colour].c_str(), r.id, r.pose.x_mm, r.pose.y_mm, r.pose.theta_rad);
  }
  for (size_t k = 0; k < scene.blobs.size(); ++k) {
    const detect::Blob& b = scene.blobs[k];
    std::printf("blob %-5zu %-7s (%.3f, %.3f) mm  area %.1f mm^2\n", k, palette[b.colour].c_str(),
                b.position_mm.x(), b.position_mm.y(), b.area_mm2);
  }
  for (const detect::Detection& d : detections) {
    std::printf("detection  %-7s id %-3d %-12s x %.3f mm  y %.3f mm  theta %.6f rad  E %.3f mm^2\n",
                palette[d.team_colour].c_str(), d.id,
                std::string(detect::DetectionStatusName(d.status)).c_str(), d.pose.x_mm,
                d.pose.y_mm, d.pose.theta_rad, d.residual_mm2);
  }
  std::printf(
      "score      robots %d correct %d wrong_id %d unknown_id %d ambiguous %d missed %d "
      "false_positives %d\n",
      score.robots, score.correct, score.wrong_id, score.unknown_id, score.ambiguous, score.missed,
      score.false_positives);
  return kExitOk;
}

// The result files of a run: <out>/<base>.csv and .json, and the command line for the manifest.
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

// Writes both files atomically; on failure says why on stderr and returns false (exit 1).
bool WriteOutputs(const OutputFiles& files, const std::string& csv, const std::string& manifest) {
  try {
    io::WriteFilesAtomic({{files.csv_path, csv}, {files.json_path, manifest}});
  } catch (const InputError& e) {
    std::cerr << "patlab simulate: " << e.what() << "\n";
    return false;
  }
  return true;
}

// Threads, and a progress bar on stderr when it is a terminal and -q was not given.
sim::RunOptions RunOptionsFor(const SimulateOptions& o) {
  sim::RunOptions run_options;
  run_options.threads = o.threads;
  if (!o.quiet && ::isatty(STDERR_FILENO)) run_options.progress = ProgressBar;
  return run_options;
}

// correspondence = "detect": whole frames through the detector.
int RunDetectMode(const sim::Experiment& experiment, const SimulateOptions& o,
                  const std::vector<std::string>& args) {
  if (!o.replay.empty()) return ReplayDetect(experiment, o.replay);
  const sim::RunOptions run_options = RunOptionsFor(o);
  const sim::DetectRunResult result = sim::RunDetectExperiment(experiment, run_options);

  const OutputFiles files = Outputs(experiment, o, args);
  if (!WriteOutputs(files, sim::DetectResultsCsv(experiment, result),
                    sim::DetectManifestJson(experiment, result, files.command_line,
                                            {files.csv_path, files.json_path}))) {
    return kExitFailure;
  }
  if (!o.quiet) {
    std::fprintf(stderr,
                 "patlab simulate: %lld frames in %.3f s wall (frames %.3f s = %.0f frames/s, "
                 "statistics %.3f s) on %d threads\nwrote %s and %s\n",
                 static_cast<long long>(result.total_frames), result.wall_seconds,
                 result.simulate_seconds, result.total_frames / result.simulate_seconds,
                 result.statistics_seconds, result.threads, files.csv_path.c_str(),
                 files.json_path.c_str());
  }
  return kExitOk;
}

int RunSimulate(const std::vector<std::string>& args) {
  SimulateOptions o;
  po::options_description visible("patlab simulate EXPERIMENT.toml [options]");
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("trials", po::value(&o.trials), "trials per data point (overrides the file; >= 2); frames in detect mode")
      ("seed", po::value(&o.seed), "experiment seed (overrides the file; integer >= 0)")
      ("threads", po::value(&o.threads), "worker threads (default: all cores); results do not depend on it")
      ("out", po::value(&o.out_dir), "output directory (default: results)")
      ("name", po::value(&o.name), "output file base name (default: the experiment's name)")
      ("sigmas", po::value(&o.sigmas), "patch sigma grid in mm, comma-separated (overrides [sigma])")
      ("sigma-y-ratio", po::value(&o.sigma_y_ratio), "noise: sigma_y / sigma_x (anisotropic)")
      ("common-sigma-ratio", po::value(&o.common_sigma_ratio), "noise: common-mode std / sigma")
      ("outlier-probability", po::value(&o.outlier_probability), "noise: outlier probability per patch")
      ("outlier-sigma-ratio", po::value(&o.outlier_sigma_ratio), "noise: outlier std / sigma")
      ("replay", po::value(&o.replay), "POINT,TRIAL: re-run one trial and print every estimate (detect mode: POINT,FRAME)")
      ("quiet,q", po::bool_switch(&o.quiet), "no progress bar or summary on stderr");
  // clang-format on
  po::variables_map vm;
  if (!ParseArguments(args, visible, "experiment", po::value(&o.experiment), 1, kExamples, &vm)) {
    return kExitOk;
  }
  if (o.experiment.empty()) {
    throw InputError(
        "missing EXPERIMENT.toml; expected 'patlab simulate EXPERIMENT.toml' (see --help)");
  }
  CheckThreads(o.threads);

  sim::Experiment experiment = sim::LoadExperimentFile(o.experiment);
  sim::Overrides overrides;
  if (vm.count("trials")) overrides.trials = o.trials;
  if (!o.seed.empty()) overrides.seed = ParseSeed(o.seed, "--seed");
  if (!o.sigmas.empty()) {
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

  if (experiment.correspondence == sim::Correspondence::kDetect) {
    return RunDetectMode(experiment, o, args);
  }
  if (!o.replay.empty()) return Replay(experiment, o.replay);

  const sim::RunOptions run_options = RunOptionsFor(o);
  const sim::RunResult result = sim::RunExperiment(experiment, run_options);

  const OutputFiles files = Outputs(experiment, o, args);
  if (!WriteOutputs(files, sim::ResultsCsv(experiment, result),
                    sim::ManifestJson(experiment, result, files.command_line,
                                      {files.csv_path, files.json_path}))) {
    return kExitFailure;
  }
  if (!o.quiet) {
    std::fprintf(stderr,
                 "patlab simulate: %lld trials in %.3f s wall (simulate %.3f s = %.1f M trials/s, "
                 "statistics %.3f s) on %d threads\nwrote %s and %s\n",
                 static_cast<long long>(result.total_trials), result.wall_seconds,
                 result.simulate_seconds, result.total_trials / result.simulate_seconds / 1e6,
                 result.statistics_seconds, result.threads, files.csv_path.c_str(),
                 files.json_path.c_str());
  }
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("simulate", "run a Monte-Carlo experiment (Fig. 5 curves, KS and Wilcoxon)",
                        RunSimulate);

}  // namespace patlab::cli
