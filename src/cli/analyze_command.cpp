// patlab analyze: the paper's section-II error analysis of measured tracks (analysis/analyze.h):
// Table I, Wilcoxon tests between subjects and the per-sample errors behind Figs. 2, 3 and 6. This
// file parses flags, calls the library and writes the files.
#include <boost/program_options.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "cli/arguments.h"
#include "cli/command.h"
#include "cli/command_line.h"
#include "cli/progress.h"
#include "patlab/analysis/analyze.h"
#include "patlab/core/error.h"
#include "patlab/core/format.h"
#include "patlab/io/atomic_file.h"

namespace patlab::cli {

namespace {

namespace po = boost::program_options;

constexpr const char* kAnalyzeExamples = R"(examples:
  patlab analyze track.csv -o results/analyze    # columns frame,subject,run,x_mm,y_mm,theta_rad
  patlab analyze run1.csv run2.csv --subject-column robot --x-column x --y-column y -o a
  patlab detect frames/ -t t.toml -c cal.toml -s det.toml --track track.csv && patlab analyze track.csv
  patlab analyze track.csv --truth truth.csv --correct-bias --along-travel
  /usr/bin/python3 scripts/plot_analyze.py results/analyze   # Figs. 2, 3, 6 as PNGs

Each sample's error is estimated as the sample minus the Gaussian-smoothed track (sigma = 10
samples, the paper's section II; --detrend linear or none: a straight line or the mean); tracks
are split at missed frames and never smoothed across a gap; the first and last 4 sigma samples of
every segment are dropped. Each std's 95% interval allows for the errors' autocorrelation
(effective dof (n - 1) / tau, Bartlett; the iid interval in the *_iid_lo/*_iid_hi columns, and a
warning when it is 10% or more too narrow). Writes to <out>: <name>.csv
(Table I: per subject std and 95% CI per axis, lag-k autocorrelation), <name>_tests.csv (Wilcoxon
signed-rank tests between subjects on |error| paired by run and frame), <name>_errors.csv
(per-sample errors) and <name>.json (manifest), all atomically.
Exit status: 0 ok, 1 cannot write, 2 bad input.
)";

struct AnalyzeCliOptions {
  std::vector<std::string> tracks;
  std::string truth;
  std::string out_dir = "results";
  std::string name = "analyze";
  analysis::TrackColumns columns;
  analysis::AnalyzeOptions analysis;
  std::string detrend = "smooth";
  bool quiet = false;
};

po::options_description Flags(AnalyzeCliOptions* o) {
  po::options_description visible("patlab analyze TRACK.csv... [options]");
  analysis::TrackColumns& c = o->columns;
  // clang-format off
  visible.add_options()
      ("help,h", "show this help")
      ("out,o", po::value(&o->out_dir), "output directory, made if missing (default: results)")
      ("name", po::value(&o->name), "base name of the output files (default: analyze)")
      ("frame-column", po::value(&c.frame), "integer frame number column (default: frame)")
      ("subject-column", po::value(&c.subject), "subject (robot, patch) column (default: subject; absent: one subject)")
      ("run-column", po::value(&c.run), "run column (default: run; absent: each file is a run)")
      ("x-column", po::value(&c.x), "x column, mm (default: x_mm)")
      ("y-column", po::value(&c.y), "y column, mm (default: y_mm)")
      ("theta-column", po::value(&c.theta), "orientation column, rad (default: theta_rad; absent: none)")
      ("detrend", po::value(&o->detrend), "what an error is measured against in each gap-free segment: smooth (the Gaussian-smoothed track, the paper's; default), linear (a least-squares line) or none (the mean)")
      ("smoothing-sigma", po::value(&o->analysis.smoothing.sigma_samples), "smoothing kernel std in samples (default: 10, the paper's)")
      ("lag", po::value(&o->analysis.lag), "lag of the reported autocorrelation (default: 1)")
      ("correct-bias", po::bool_switch(&o->analysis.correct_bias), "divide the estimated stds by the white-noise residual factor (0.974 for sigma 10)")
      ("along-travel", po::bool_switch(&o->analysis.along_travel), "errors along (x) and across (y) each segment's travel, not the file's axes")
      ("truth", po::value(&o->truth), "true poses, same columns: adds the true errors (sample - truth)")
      ("quiet,q", po::bool_switch(&o->quiet), "no progress or summary on stderr");
  // clang-format on
  return visible;
}

double Seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

void PrintSummary(const analysis::AnalyzeReport& report,
                  const std::vector<std::pair<std::string, double>>& timings, double seconds,
                  const std::vector<std::string>& paths) {
  size_t samples = 0;
  for (const analysis::SubjectAnalysis& a : report.subjects) samples += a.samples;
  std::string stages;
  for (const auto& [stage, s] : timings) stages += StringPrintf(", %s %.3f", stage.c_str(), s);
  std::fputs(StringPrintf(
                 "patlab analyze: %zu samples, %zu subject(s), %zu run(s) in %.3f s wall (%s s)\n",
                 samples, report.subjects.size(), report.runs.size(), seconds, stages.c_str() + 2)
                 .c_str(),
             stderr);
  std::fputs(
      StringPrintf(
          "residual std factor for white errors %.4f (%s), lag-%d white-noise reference %.3f\n",
          report.residual_factor,
          report.options.correct_bias ? "divided out: --correct-bias" : "not corrected",
          report.options.lag, report.white_noise_lag)
          .c_str(),
      stderr);
  std::fprintf(stderr, "%-12s %8s %-24s %-24s %-24s %-24s\n", "subject", "n", "sx [95% CI] mm",
               "sy", "true sx", "true sy");
  auto cell = [](const stats::StdWithCi& s) {
    return StringPrintf("%.3f [%.3f-%.3f]", s.std, s.lower, s.upper);
  };
  for (const analysis::SubjectAnalysis& a : report.subjects) {
    std::fprintf(stderr, "%-12s %8zu %-24s %-24s %-24s %-24s\n", a.subject.c_str(), a.est.x.n,
                 cell(a.est.x).c_str(), cell(a.est.y).c_str(),
                 a.has_truth ? cell(a.truth.x).c_str() : "",
                 a.has_truth ? cell(a.truth.y).c_str() : "");
    if (a.skipped_segments > 0) {
      std::fprintf(stderr, "  %s: skipped %d segment(s), %zu samples, shorter than %d frames\n",
                   a.subject.c_str(), a.skipped_segments, a.skipped_samples, report.min_segment);
    }
  }
  std::string wrote = "wrote";
  for (const std::string& p : paths) wrote.append(" ").append(p);
  std::fprintf(stderr, "%s\n", wrote.c_str());
}

// The help's option groups (command_line.h).
const OptionGroups kAnalyzeGroups = {
    {"input",
     {"frame-column", "subject-column", "run-column", "x-column", "y-column", "theta-column",
      "truth"}},
    {"analysis", {"detrend", "smoothing-sigma", "lag", "correct-bias", "along-travel"}},
    {"output", {"out", "name"}}};

int RunAnalyze(const std::vector<std::string>& args) {
  AnalyzeCliOptions o;
  const po::options_description visible = Flags(&o);
  po::variables_map vm;
  if (!ParseArguments(args, visible, kAnalyzeGroups, "track", po::value(&o.tracks), -1,
                      kAnalyzeExamples, &vm, {{"--sigma", "--smoothing-sigma (samples)"}})) {
    return kExitOk;
  }
  if (o.tracks.empty()) {
    throw InputError("no track files; expected 'patlab analyze TRACK.csv...' (see --help)");
  }
  ThrowFlagProblem(analysis::Check(o.analysis), vm,
                   {{"sigma_samples", "--smoothing-sigma"}, {"lag", "--lag"}});
  if (!io::IsFileBaseName(o.name)) {
    throw InputError("--name is '" + EscapeForMessage(o.name) + "'; expected " +
                     io::kFileBaseNameExpected);
  }
  o.columns.require_subject = vm.count("subject-column") > 0;
  o.columns.require_run = vm.count("run-column") > 0;
  o.columns.require_theta = vm.count("theta-column") > 0;
  o.analysis.detrend = ParseName(o.detrend, analysis::kDetrendNames, "--detrend");
  analysis::Validate(o.columns);
  analysis::Validate(o.analysis);
  const std::string base = o.out_dir + "/" + o.name;
  const std::vector<std::string> paths = {base + ".csv", base + "_tests.csv", base + "_errors.csv",
                                          base + ".json"};
  io::CheckWritable(paths);

  const auto start = std::chrono::steady_clock::now();
  std::vector<analysis::MeasuredTrack> tracks, truth;
  for (const std::string& path : o.tracks) {
    std::vector<analysis::MeasuredTrack> some = analysis::ReadTrackCsv(path, o.columns);
    tracks.insert(tracks.end(), std::make_move_iterator(some.begin()),
                  std::make_move_iterator(some.end()));
  }
  if (!o.truth.empty()) truth = analysis::ReadTrackCsv(o.truth, o.columns);
  const auto read = std::chrono::steady_clock::now();
  Progress progress("patlab analyze", "subjects", !o.quiet, StderrIsTerminal());
  o.analysis.progress = progress.Callback();
  const analysis::AnalyzeReport report =
      analysis::AnalyzeTracks(std::move(tracks), o.analysis, o.truth.empty() ? nullptr : &truth);
  const auto analysed = std::chrono::steady_clock::now();
  std::vector<std::string> inputs = o.tracks;
  if (!o.truth.empty()) inputs.push_back(o.truth);
  // The per-sample errors (35 MB for 1e6 samples) are streamed into their temporary file.
  std::vector<std::pair<std::string, double>> timings = {{"read", Seconds(start, read)},
                                                         {"analyse", Seconds(read, analysed)}};
  const std::vector<io::StreamedFile> files = {
      {paths[0], [&](const io::TextSink& sink) { sink(analysis::AnalyzeTableCsv(report)); }},
      {paths[1], [&](const io::TextSink& sink) { sink(stats::PairedTestsCsv(report.tests)); }},
      {paths[2], [&](const io::TextSink& sink) { analysis::WriteAnalyzeErrorsCsv(report, sink); }},
      {paths[3], [&](const io::TextSink& sink) {
         sink(analysis::AnalyzeManifestJson(report, inputs, paths));
       }}};
  try {
    io::WriteFilesAtomic(files);
  } catch (const EnvironmentError& e) {
    std::cerr << "patlab analyze: " << e.what() << "\n";
    return kExitFailure;
  }
  timings.emplace_back("write", Seconds(analysed, std::chrono::steady_clock::now()));
  for (const std::string& w : report.warnings) std::cerr << "patlab analyze: " << w << "\n";
  if (!o.quiet)
    PrintSummary(report, timings, Seconds(start, std::chrono::steady_clock::now()), paths);
  return kExitOk;
}

}  // namespace

PATLAB_REGISTER_COMMAND("analyze", "section-II error analysis of measured tracks (Table I)",
                        RunAnalyze);

}  // namespace patlab::cli
