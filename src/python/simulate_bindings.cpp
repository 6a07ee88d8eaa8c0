// patlab.simulate and patlab.simulate_experiment: sim::RunExperiment (or, for a detect-mode
// experiment, sim::RunDetectExperiment), the call `patlab simulate` makes, with the GIL released
// and Ctrl-C checked between blocks; per-point summaries as columns named as the CLI's CSV
// columns, holding the doubles the CSV prints with 10 digits.
#include <cmath>
#include <limits>
#include <optional>

#include "patlab/core/error.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/sim/batch.h"
#include "patlab/sim/detect_runner.h"
#include "patlab/sim/report.h"
#include "patlab/sim/runner.h"
#include "python/bindings.h"

namespace patlab::python {

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// One number column of the CLI's CSV: its name and its value for a point and an estimator.
struct Column {
  const char* name;
  double (*value)(const sim::PointResult&, const sim::EstimatorResult&);
};

double IfMl(const sim::EstimatorResult& r, double v) {
  return r.estimator == estimate::Estimator::kMl ? v : kNan;
}
double IfCompared(const sim::EstimatorResult& r, double v) { return r.vs_fast.computed ? v : kNan; }

// clang-format off
const Column kColumns[] = {
    {"sigma_mm", [](const sim::PointResult& p, const sim::EstimatorResult&) { return p.sigma_mm; }},
    {"trials", [](const sim::PointResult& p, const sim::EstimatorResult&) { return double(p.trials); }},
    {"mean_x_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.x.mean; }},
    {"std_x_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.x.std; }},
    {"std_x_lo_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.x.std_lower; }},
    {"std_x_hi_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.x.std_upper; }},
    {"mean_y_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.y.mean; }},
    {"std_y_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.y.std; }},
    {"std_y_lo_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.y.std_lower; }},
    {"std_y_hi_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.y.std_upper; }},
    {"mean_theta_rad", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.theta.mean; }},
    {"std_theta_rad", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.theta.std; }},
    {"std_theta_lo_rad", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.theta.std_lower; }},
    {"std_theta_hi_rad", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.theta.std_upper; }},
    {"std_pos_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.position_std_mm; }},
    {"std_pos_lo_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.position_std_lower_mm; }},
    {"std_pos_hi_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.position_std_upper_mm; }},
    {"rms_radial_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.radial_rms_mm; }},
    {"mean_radial_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.radial.mean; }},
    {"std_radial_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.radial.std; }},
    {"std_radial_lo_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.radial.std_lower; }},
    {"std_radial_hi_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.radial.std_upper; }},
    {"crlb_pos_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.crlb_position_mm; }},
    {"crlb_theta_rad", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.crlb_theta_rad; }},
    {"pred_pos_mm", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.predicted_position_mm; }},
    {"pred_theta_rad", [](const sim::PointResult&, const sim::EstimatorResult& r) { return r.predicted_theta_rad; }},
    {"efficiency_pos", [](const sim::PointResult&, const sim::EstimatorResult& r) { return sim::Efficiency(r.crlb_position_mm, r.position_std_mm); }},
    {"efficiency_theta", [](const sim::PointResult&, const sim::EstimatorResult& r) { return sim::Efficiency(r.crlb_theta_rad, r.theta.std); }},
    {"ml_nonconverged", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfMl(r, double(r.nonconverged)); }},
    {"ml_first_nonconverged_trial", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfMl(r, double(r.first_nonconverged_trial)); }},
    {"ml_mean_iterations", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfMl(r, r.mean_iterations); }},
    {"ks_x_d", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.ks_x.d); }},
    {"ks_x_p", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.ks_x.p_value); }},
    {"ks_y_d", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.ks_y.d); }},
    {"ks_y_p", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.ks_y.p_value); }},
    {"ks_theta_d", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.ks_theta.d); }},
    {"ks_theta_p", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.ks_theta.p_value); }},
    {"wilcoxon_pos_p", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.wilcoxon_position.p_value); }},
    {"wilcoxon_theta_p", [](const sim::PointResult&, const sim::EstimatorResult& r) { return IfCompared(r, r.vs_fast.wilcoxon_theta.p_value); }},
};
// clang-format on

// The columns of the CLI's CSV, in its order: strings as lists, numbers as float64 arrays (NaN
// where the CSV has an empty cell).
py::dict SummaryColumns(const sim::Experiment& experiment, const sim::RunResult& result) {
  std::vector<std::string> pattern, estimator;
  std::vector<std::vector<double>> numbers(std::size(kColumns));
  for (const sim::PointResult& p : result.points) {
    for (const sim::EstimatorResult& r : p.estimators) {
      pattern.push_back(p.pattern);
      estimator.emplace_back(estimate::EstimatorName(r.estimator));
      for (size_t c = 0; c < std::size(kColumns); ++c)
        numbers[c].push_back(kColumns[c].value(p, r));
    }
  }
  py::dict columns;
  columns["pattern"] = pattern;
  columns["estimator"] = estimator;
  const py::ssize_t rows = static_cast<py::ssize_t>(pattern.size());
  for (size_t c = 0; c < std::size(kColumns); ++c) {
    columns[kColumns[c].name] = ArrayOf(numbers[c], {rows});
    if (c == 1)
      columns["noise"] = std::vector<std::string>(pattern.size(), experiment.noise.Describe());
  }
  return columns;
}

// Every trial's errors, (points, estimators, trials, 3) float64 (x mm, y mm, theta rad): the
// trials of the run again, through the batched kernel the runner uses, from the same keys.
py::array_t<double> TrialErrors(const sim::Experiment& experiment) {
  const int64_t sigmas = static_cast<int64_t>(experiment.sigmas_mm.size());
  const int64_t points = static_cast<int64_t>(experiment.patterns.size()) * sigmas;
  const int64_t estimators = static_cast<int64_t>(experiment.estimators.size());
  py::array_t<double> errors({points, estimators, experiment.trials, int64_t{3}});
  double* out = errors.mutable_data();
  const py::gil_scoped_release nogil;
  std::vector<double> columns(static_cast<size_t>(3 * 4 * sim::kBatchSize));
  std::vector<uint8_t> iterations(sim::kBatchSize), termination(sim::kBatchSize);
  const std::function<void(int, int)> check = SignalCheck();
  for (int64_t point = 0; point < points; ++point) {
    const int pi = static_cast<int>(point / sigmas), si = static_cast<int>(point % sigmas);
    const estimate::Model model = estimate::Model::FromPattern(experiment.patterns[pi]);
    const sim::PointSetup setup = sim::MakePointSetup(experiment, model, pi, si);
    for (int64_t first = 0; first < experiment.trials; first += sim::kBatchSize) {
      const int count =
          static_cast<int>(std::min<int64_t>(sim::kBatchSize, experiment.trials - first));
      sim::BatchOutput batch;
      for (int e = 0; e < 4; ++e) {
        double* base = columns.data() + static_cast<size_t>(3 * e * sim::kBatchSize);
        if (setup.run[e])
          batch.errors[e] = {base, base + sim::kBatchSize, base + 2 * sim::kBatchSize};
      }
      batch.ml_iterations = iterations.data();
      batch.ml_termination = termination.data();
      sim::RunBatch(setup, static_cast<uint64_t>(first), count, batch);
      for (int64_t e = 0; e < estimators; ++e) {
        const sim::ErrorArrays& a = batch.errors[static_cast<int>(experiment.estimators[e])];
        double* row = out + ((point * estimators + e) * experiment.trials + first) * 3;
        for (int k = 0; k < count; ++k) {
          row[3 * k] = a.x_mm[k];
          row[3 * k + 1] = a.y_mm[k];
          row[3 * k + 2] = a.theta_rad[k];
        }
      }
    }
    check(static_cast<int>(point + 1), static_cast<int>(points));
  }
  return errors;
}

// What a run returns to Python, for the trial and the detect runs alike.
py::dict RunDict(const sim::Experiment& experiment, py::object columns, std::string csv,
                 int threads, int64_t total_trials, double wall_seconds, double simulate_seconds) {
  py::dict out;
  out["columns"] = std::move(columns);
  out["csv"] = std::move(csv);
  out["name"] = experiment.name;
  out["seed"] = experiment.seed;
  out["threads"] = threads;
  out["total_trials"] = total_trials;
  out["wall_seconds"] = wall_seconds;
  out["simulate_seconds"] = simulate_seconds;
  return out;
}

// correspondence = "detect": whole frames through the detector (sim::RunDetectExperiment), the
// run `patlab simulate` makes; the CSV is the table (Python reads its columns).
py::dict RunDetect(const sim::Experiment& experiment, const sim::RunOptions& options,
                   bool keep_errors) {
  if (keep_errors) {
    throw InputError(experiment.source_file +
                     ": keep_errors is set, but the experiment's correspondence is \"detect\" "
                     "(whole frames, no per-trial errors to keep); expected keep_errors=False");
  }
  sim::DetectRunResult result;
  {
    const py::gil_scoped_release nogil;
    result = sim::RunDetectExperiment(experiment, options);
  }
  return RunDict(experiment, py::none(), sim::DetectResultsCsv(experiment, result), result.threads,
                 result.total_frames, result.wall_seconds, result.simulate_seconds);
}

py::dict Run(const sim::Experiment& experiment, int threads, bool keep_errors) {
  sim::Validate(experiment);
  sim::RunOptions options;
  options.threads = threads;
  options.progress = SignalCheck();
  sim::Validate(options);
  if (experiment.correspondence == sim::Correspondence::kDetect) {
    return RunDetect(experiment, options, keep_errors);
  }
  sim::RunResult result;
  {
    const py::gil_scoped_release nogil;
    result = sim::RunExperiment(experiment, options);
  }
  py::dict out =
      RunDict(experiment, SummaryColumns(experiment, result), sim::ResultsCsv(experiment, result),
              result.threads, result.total_trials, result.wall_seconds, result.simulate_seconds);
  if (keep_errors) out["errors"] = TrialErrors(experiment);
  return out;
}

py::dict Simulate(const std::vector<Pattern>& patterns, const std::vector<std::string>& files,
                  const std::vector<double>& sigmas_mm, int64_t trials,
                  const std::vector<std::string>& estimators, const py::dict& noise, uint64_t seed,
                  int threads, bool keep_errors, const std::string& name) {
  sim::Experiment experiment;
  experiment.name = name;
  experiment.source_file = "python";
  experiment.patterns = patterns;
  experiment.pattern_files = files;
  experiment.estimators = ParseEstimators(estimators, "estimators");
  experiment.sigmas_mm = sigmas_mm;
  experiment.trials = trials;
  experiment.seed = seed;
  experiment.noise = NoiseFromDict(noise);
  if (patterns.empty()) throw InputError("patterns is empty; expected at least one pattern");
  return Run(experiment, threads, keep_errors);
}

py::dict SimulateExperiment(const std::string& path, std::optional<int64_t> trials,
                            std::optional<uint64_t> seed, const std::vector<double>& sigmas_mm,
                            int threads, bool keep_errors) {
  sim::Experiment experiment = formats::LoadExperimentFile(path);
  sim::Overrides overrides;
  overrides.trials = trials;
  overrides.seed = seed;
  overrides.sigmas_mm = sigmas_mm;
  sim::ApplyOverrides(overrides, &experiment);
  return Run(experiment, threads, keep_errors);
}

}  // namespace

void BindSimulate(py::module_& m) {
  m.def("_simulate", &Simulate, py::arg("patterns"), py::arg("pattern_files"), py::arg("sigmas_mm"),
        py::arg("trials"), py::arg("estimators"), py::arg("noise"), py::arg("seed"),
        py::arg("threads"), py::arg("keep_errors"), py::arg("name"));
  m.def("_simulate_experiment", &SimulateExperiment, py::arg("path"), py::arg("trials"),
        py::arg("seed"), py::arg("sigmas_mm"), py::arg("threads"), py::arg("keep_errors"));
}

}  // namespace patlab::python
