#include "patlab/paper/reproduce.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "patlab/analysis/track.h"
#include "patlab/analysis/track_runner.h"
#include "patlab/formats/experiment_file.h"
#include "patlab/formats/track_file.h"
#include "patlab/paper/reproduce_compare.h"
#include "patlab/paper/reproduce_internal.h"
#include "patlab/sim/experiment.h"
#include "patlab/sim/report.h"
#include "patlab/sim/runner.h"

namespace patlab::paper {

namespace {

// The input `relative` of the checkout at `root`, as a path (experiments/fig5.toml for the root
// "."), so that the manifests record what `patlab simulate` and `patlab track` record.
std::string Input(const ReproduceOptions& o, const char* relative) {
  return (std::filesystem::path(o.root) / relative).lexically_normal().string();
}
std::string Output(const ReproduceOptions& o, const std::string& name) {
  return (std::filesystem::path(o.out_dir) / name).lexically_normal().string();
}

// |error| of every kept sample of one subject on axis 0 (x), 1 (y) or 2 (hypot), keyed by (run,
// frame) as error_stats.cpp pairs them.
std::map<std::pair<size_t, int>, double> AbsErrors(const std::vector<analysis::SubjectRun>& runs,
                                                   bool est, int axis) {
  std::map<std::pair<size_t, int>, double> out;
  for (size_t run = 0; run < runs.size(); ++run) {
    const analysis::SubjectRun& r = runs[run];
    const std::vector<double>& x = est ? r.est_x_mm : r.true_x_mm;
    const std::vector<double>& y = est ? r.est_y_mm : r.true_y_mm;
    for (size_t i = 0; i < r.sample.size(); ++i) {
      out[{run, r.sample[i]}] = axis == 0   ? std::abs(x[i])
                                : axis == 1 ? std::abs(y[i])
                                            : std::hypot(x[i], y[i]);
    }
  }
  return out;
}

// The rank allowance of every test of MakeSizeTests (the discs, paired by run and frame), keyed
// "error,axis,a,b" as the rows of table1_tests.csv.
std::map<std::string, RankAllowance> SizeTestAllowances(const analysis::TrackResult& result) {
  std::map<std::string, RankAllowance> out;
  const char* axes[] = {"x", "y", "xy"};
  for (const bool est : {true, false}) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<size_t> discs;
      std::vector<std::map<std::pair<size_t, int>, double>> abs;
      for (size_t k = 0; k < result.subjects.size(); ++k) {
        if (!result.subjects[k].ends_with("mm")) continue;
        discs.push_back(k);
        abs.push_back(AbsErrors(result.data[k], est, axis));
      }
      for (size_t a = 0; a < discs.size(); ++a) {
        for (size_t b = a + 1; b < discs.size(); ++b) {
          std::vector<double> va, vb;
          for (const auto& [key, value] : abs[a]) {
            const auto it = abs[b].find(key);
            if (it == abs[b].end()) continue;
            va.push_back(value);
            vb.push_back(it->second);
          }
          std::string key = est ? "est," : "true,";
          key.append(axes[axis]).append(",").append(result.subjects[discs[a]]);
          key.append(",").append(result.subjects[discs[b]]);
          out[key] = KnifeEdgeAllowance(va, vb);
        }
      }
    }
  }
  return out;
}

// The progress of run `index` of the three as a callback for its runner, or empty.
std::function<void(int, int)> RunProgress(const ReproduceOptions& o, int index) {
  if (!o.progress) return {};
  return [&o, index](int done, int total) {
    const int per_run = ReproduceOptions::kProgressPerRun;
    const int part = total > 0 ? static_cast<int>(static_cast<int64_t>(per_run) * done / total) : 0;
    o.progress(index * per_run + part, 3 * per_run);
  };
}

// The four files of a track run under `dir` ("" or "track_quantisation/"), as `patlab track`
// writes them; returns Table I and its tests.
std::pair<std::string, std::string> AddTrackFiles(const ReproduceOptions& o,
                                                  const analysis::TrackOptions& track, int decimate,
                                                  const std::string& dir, int run_index,
                                                  Reproduction* r) {
  const analysis::TrackResult result =
      analysis::RunTrack(track, {.threads = o.threads, .progress = RunProgress(o, run_index)});
  const std::vector<analysis::TableRow> table = analysis::MakeTable(result);
  const std::string names[] = {dir + track.name + ".csv", dir + track.name + "_tests.csv",
                               dir + "track_errors.csv", dir + track.name + ".json"};
  std::vector<std::string> outputs;
  for (const std::string& name : names) outputs.push_back(Output(o, name));
  const std::string table_csv = analysis::TableCsv(table);
  const std::string tests_csv = analysis::SizeTestsCsv(analysis::MakeSizeTests(result));
  r->files.emplace_back(names[0], table_csv);
  r->files.emplace_back(names[1], tests_csv);
  r->files.emplace_back(names[2], analysis::ErrorsCsv(track, result, decimate));
  r->files.emplace_back(names[3], analysis::TrackManifestJson(track, result, table, outputs));
  for (int k = 0; k < 3; ++k) r->rules[names[k]] = RulesForResultFile(names[k]);
  r->rules[names[1]].rank_allowances = SizeTestAllowances(result);
  return {table_csv, tests_csv};
}

}  // namespace

Reproduction Reproduce(const ReproduceOptions& options) {
  Reproduction r;
  sim::RunOptions run;
  run.threads = options.threads;
  run.progress = RunProgress(options, 0);
  const sim::Experiment fig5 = formats::LoadExperimentFile(Input(options, "experiments/fig5.toml"));
  const sim::RunResult fig5_result = sim::RunExperiment(fig5, run);
  const std::string fig5_csv = sim::ResultsCsv(fig5, fig5_result);
  r.files = {{"fig5.csv", fig5_csv},
             {"fig5.json",
              sim::ManifestJson(fig5, fig5_result,
                                {Output(options, "fig5.csv"), Output(options, "fig5.json")})}};
  r.rules["fig5.csv"] = RulesForResultFile("fig5.csv");
  const analysis::TrackOptions table1 =
      formats::LoadTrackExperiment(Input(options, "experiments/table1.toml"));
  const auto [table1_csv, tests_csv] = AddTrackFiles(options, table1, 1, "", 1, &r);
  // Fig. 6's left panels: the same runs with quantisation only (no intensity noise or jitter).
  analysis::TrackOptions quantisation = table1;
  quantisation.pixel_sigma = 0.0;
  quantisation.jitter_sigma_px = 0.0;
  Validate(quantisation);
  AddTrackFiles(options, quantisation, 4, "track_quantisation/", 2, &r);

  AddPaperNumbers(options, fig5, table1, {fig5_csv, table1_csv, tests_csv}, &r.numbers);
  r.files.emplace_back("paper.md", PaperMarkdown(r));
  return r;
}

std::vector<FigureStep> FigureSteps(const ReproduceOptions& options) {
  const std::string python = "/usr/bin/python3";
  return {
      {"Fig. 5",
       {python, Input(options, "scripts/plot_fig5.py"), Output(options, "fig5.csv"),
        Output(options, "fig5.png")},
       {Output(options, "fig5.png")}},
      {"Figs. 2, 3, 6",
       {python, Input(options, "scripts/plot_track.py"),
        std::filesystem::path(options.out_dir).lexically_normal().string(),
        Output(options, "track_quantisation")},
       {Output(options, "fig2.png"), Output(options, "fig3.png"), Output(options, "fig6.png")}}};
}

}  // namespace patlab::paper
